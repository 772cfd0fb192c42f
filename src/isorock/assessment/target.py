"""Adequacy: is a base good enough, judged against a stated target, not only better than another.

A base (the fixed base, an isolator) is judged by its probability of failure (overturning, sliding beyond
the allowance, the isolator beyond its capacity) against a target the answer states
(:class:`Target`):

* ``p_mce`` (the default, 10 %): the probability of failure at the maximum considered earthquake (MCE)
  level. 10 % is the target reliability of ASCE/SEI 7-16 Table 1.3-2 for structural stability under
  earthquake: a conditional probability of failure of 10 % under the MCE_R ground motion for Risk
  Category I and II structures; a collapse objective borrowed here for a free-standing object (its
  overturning is its collapse);
* ``rate_per_yr``: the mean annual frequency of failure (needs a hazard curve);
* ``p_50yr``: the probability of failure in 50 years (needs a hazard curve; ASCE/SEI 7-16 §21.2.1
  builds its risk-targeted MCE_R on 1 % in 50 years of collapse).

:func:`judge` says, from the estimate and its 95 % interval, whether a base is ``adequate`` (True: the
estimate meets the target), clearly not adequate (False: even the lower end of the interval misses
it), or neither (None: adequacy is not shown). The estimate is the fitted one where a fragility can be
fitted, else the observed fraction ``k/n`` with its exact (Clopper-Pearson) interval; 0 failures of 17
records is an estimate of 0, which meets a target of 10 %, although the exact one-sided upper bound
(16 %) does not: requiring the bound would make adequacy unreachable for ordinary record sets.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from isorock.errors import ConfigError

__all__ = ["TARGET_KINDS", "DEFAULT_P_MCE", "Target", "judge"]

#: the kinds of target and their words
TARGET_KINDS = {
    "p_mce": "the probability of failure at the MCE level",
    "rate_per_yr": "the mean annual frequency of failure",
    "p_50yr": "the probability of failure in 50 years",
}
#: the default target: P(failure | MCE) at most 10 % (ASCE/SEI 7-16 Table 1.3-2, Risk Category I/II,
#: total or partial collapse)
DEFAULT_P_MCE = 0.10


@dataclass(frozen=True)
class Target:
    """The target a base is judged against.

    Attributes
    ----------
    kind : {"p_mce", "rate_per_yr", "p_50yr"}
    value : float
        The largest acceptable value (a probability, or failures per year).
    source : str
        Where it comes from, in words.
    """

    kind: str = "p_mce"
    value: float = DEFAULT_P_MCE
    source: str = (
        "the default: 10 % at the MCE, the target reliability of ASCE/SEI 7-16 Table 1.3-2 (conditional "
        "probability of failure under the MCE_R, Risk Category I and II structures), borrowed for the "
        "object's overturning"
    )

    @classmethod
    def from_config(cls, cfg: Mapping[str, Any] | None, has_hazard: bool) -> Target:
        """From ``assessment.target`` (``{p_mce: 0.1}``, ``{rate_per_yr: 1e-4}`` or ``{p_50yr: 0.01}``);
        None: the default."""
        if not cfg:
            return cls()
        if len(cfg) != 1 or next(iter(cfg)) not in TARGET_KINDS:
            raise ConfigError(
                f"configuration: assessment.target: {dict(cfg)}: give one of "
                + ", ".join(f"{{{k}: value}}" for k in TARGET_KINDS)
            )
        kind, value = next(iter(cfg.items()))
        v = float(value)
        if not (math.isfinite(v) and 0 < v < (1 if kind != "rate_per_yr" else math.inf)):
            raise ConfigError(f"configuration: assessment.target.{kind}: {value} must be in (0, 1)")
        if kind != "p_mce" and not has_hazard:
            raise ConfigError(
                f"configuration: assessment.target.{kind}: an annual frequency needs the site's hazard "
                "curve: add assessment.hazard, or give {p_mce: ...}"
            )
        return cls(kind, v, "given (assessment.target)")

    @property
    def words(self) -> str:
        """The target in words: "P(failure) at the MCE at most 10 %"."""
        if self.kind == "p_mce":
            return f"P(failure) at the MCE at most {_pct(self.value)}"
        if self.kind == "p_50yr":
            return f"P(failure) in 50 years at most {_pct(self.value)}"
        return f"at most {self.value:.2g} failures per year"

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "value": self.value, "words": self.words, "source": self.source}


def _pct(v: float) -> str:
    return f"{100 * v:.3g} %"


def judge(estimate: float | None, ci95: Sequence[float] | None, target: float) -> bool | None:
    """Adequacy against ``target``: True when the estimate meets it, False when even the lower end of
    the 95 % interval misses it, None between the two (or without an estimate)."""
    if estimate is None or not math.isfinite(estimate):
        return None
    if estimate <= target:
        return True
    if ci95 is not None and math.isfinite(ci95[0]) and ci95[0] > target:
        return False
    return None
