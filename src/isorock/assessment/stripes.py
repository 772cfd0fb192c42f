"""Assessment of a real object: multiple-stripe analysis, fragility, isolator displacement, validity,
and the choice of an isolator.

An object (a statue, a cabinet) is a rigid block of full height ``h`` and width ``w`` (in the direction
it may rock): slenderness ``lambda = h / w``, size ``R = sqrt(h^2 + w^2) / 2``, with a friction
coefficient ``mu`` against its floor. Every record, processed as everywhere else, is scaled to each
intensity level (a *stripe*: the record's PGA set to the level) and analysed in a full run
(:func:`isorock.engine.simulate` semantics: peaks and reactions over the whole motion, the free
vibration included). Per run: the outcome, ``max theta / alpha``, the peak isolator displacement and
the contact-force demands ``mu_required`` and ``min_normal_over_weight``
(:class:`isorock.result.Result`): a run is *outside the model* when ``mu_required > mu`` (the object
would slide) or the normal force vanishes (it would jump).

From the stripes (:func:`stripe_table`): per level the counts of overturning and uplift, the median
and 84th-percentile isolator displacement. :func:`fragility_rows` fits lognormal fragility functions
(:func:`isorock.assessment.fragility.fit_fragility`, Baker 2015) for overturning and for uplift;
:func:`design_level_rows` gives, at each design level, the probabilities from the fits, the displacement
demand and the fraction of records that exceed the isolator's displacement capacity. The design search
(:mod:`isorock.assessment.design`) repeats this over a grid of isolators.

The analyses of one record run in parallel threads (:func:`isorock.engine.run_many`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
import pandas as pd

from ..excitation import GroundMotion
from ..model import Block, System
from .fragility import fit_fragility

__all__ = [
    "AssessedObject",
    "run_levels",
    "stripe_table",
    "fragility_rows",
    "design_level_rows",
    "RUN_COLUMNS",
]

#: the per-run columns of :func:`run_levels`
RUN_COLUMNS = (
    "pga_g", "scale", "outcome", "outcome_code", "max_theta_over_alpha", "max_base_disp_m", "mu_required",
    "min_normal_over_weight", "slides", "jumps", "outside_model", "decided",
)  # fmt: skip


@dataclass(frozen=True)
class AssessedObject:
    """An object to assess.

    Parameters
    ----------
    name : str
        Name used in tables and figures.
    lam : float
        Slenderness ``h / w`` [-].
    R_m : float
        Half-diagonal [m].
    friction : float
        Friction coefficient between the object and its floor [-].
    height_m, width_m : float or None
        Full height and width [m], when given that way.
    """

    name: str
    lam: float
    R_m: float
    friction: float
    height_m: float | None = None
    width_m: float | None = None

    @classmethod
    def from_config(cls, d: Mapping[str, Any]) -> AssessedObject:
        """From a configuration entry: ``{name, height_m, width_m, friction}`` or ``{name, lambda, R_m,
        friction}``."""
        if "height_m" in d:
            h, w = float(d["height_m"]), float(d["width_m"])
            return cls(d["name"], h / w, 0.5 * math.hypot(h, w), float(d["friction"]), h, w)
        return cls(d["name"], float(d["lambda"]), float(d["R_m"]), float(d["friction"]))

    def block(self) -> Block:
        return Block.from_lambda_R(self.lam, self.R_m)

    def columns(self) -> dict[str, Any]:
        """Table columns: object, lambda_, R_m, height_m, width_m (NaN if not given), friction, tan_alpha."""
        blk = self.block()
        return {
            "object": self.name,
            "lambda_": self.lam,
            "R_m": self.R_m,
            "height_m": math.nan if self.height_m is None else self.height_m,
            "width_m": math.nan if self.width_m is None else self.width_m,
            "friction": self.friction,
            "tan_alpha": blk.tan_alpha,
        }

    def to_dict(self) -> dict:
        return asdict(self)


def run_levels(
    systems: Sequence[System],
    gm: GroundMotion,
    levels_g: Sequence[float],
    friction: float,
    *,
    threads: int | None = None,
    progress: Callable[[str], None] | None = None,
) -> pd.DataFrame:
    """Full runs of every system with the record scaled to every level, in parallel.

    Parameters
    ----------
    systems : sequence of System
        The object on each isolation to analyse (one row block per system).
    gm : GroundMotion
        The processed record [m/s^2].
    levels_g : sequence of float
        PGA the record is scaled to [g].
    friction : float
        The object's friction coefficient [-] (for the ``slides`` and ``outside_model`` flags).
    threads : int, optional
        Parallel threads (default: numba's setting, all cores).
    progress : callable, optional
        Called with one line per system.

    Returns
    -------
    pandas.DataFrame
        One row per (system, level), in that order, with ``system`` (its index) and
        :data:`RUN_COLUMNS`.
    """
    from ..engine import run_many

    pga = gm.pga_g
    rows = [(si, float(x), float(x) / pga) for si in range(len(systems)) for x in levels_g]
    res = run_many(
        [systems[si] for si, _, _ in rows], gm, [sc for _, _, sc in rows], early_stop=False, threads=threads
    )
    out = []
    for i, (si, x, scale) in enumerate(rows):
        mu = float(res.mu_required[i])
        nmin = float(res.min_normal_over_weight[i])
        slides, jumps = mu > friction, nmin <= 0.0
        code = int(res.outcome_code[i])
        out.append(
            {
                "system": si,
                "pga_g": x,
                "scale": scale,
                "outcome": res.outcome[i],
                "outcome_code": code,
                "max_theta_over_alpha": float(res.max_theta_over_alpha[i]),
                "max_base_disp_m": float(res.max_base_disp_m[i]),
                "mu_required": mu,
                "min_normal_over_weight": nmin,
                "slides": bool(slides),
                "jumps": bool(jumps),
                "outside_model": bool(slides or jumps),
                "decided": bool(res.decided[i]),
            }
        )
    if progress is not None:
        for si in range(len(systems)):
            sel = [o for o in out if o["system"] == si]
            n_ov = sum(o["outcome_code"] == 2 for o in sel)
            progress(f"system {si + 1}/{len(systems)}: {len(sel)} runs, {n_ov} overturn")
    return pd.DataFrame(out)


def _p84(v: np.ndarray) -> float:
    return float(np.percentile(v, 84.0)) if v.size else math.nan


def stripe_table(runs: pd.DataFrame, capacity_m: float | None = None) -> pd.DataFrame:
    """Per intensity level (``pga_g``) of one object and isolation: ``n_records``, ``n_overturn``,
    ``n_uplift`` (rocking or overturn), ``disp_median_m``, ``disp_p84_m`` (isolator displacement over
    the records [m]), ``n_exceed_capacity`` (records whose displacement exceeds ``capacity_m``) and
    ``n_outside_model``."""
    out = []
    for x, g in runs.groupby("pga_g", sort=True):
        d = g["max_base_disp_m"].to_numpy(dtype=float)
        out.append(
            {
                "pga_g": float(x),
                "n_records": len(g),
                "n_overturn": int((g["outcome_code"] == 2).sum()),
                "n_uplift": int((g["outcome_code"] >= 1).sum()),
                "disp_median_m": float(np.median(d)),
                "disp_p84_m": _p84(d),
                "n_exceed_capacity": int((d > capacity_m).sum()) if capacity_m else 0,
                "n_outside_model": int(g["outside_model"].sum()),
            }
        )
    return pd.DataFrame(out)


def fragility_rows(stripes: pd.DataFrame) -> list[dict[str, Any]]:
    """Lognormal fragility of overturning and of uplift from a :func:`stripe_table` [g]."""
    out = []
    for damage, col in (("overturn", "n_overturn"), ("uplift", "n_uplift")):
        f = fit_fragility(stripes["pga_g"], stripes["n_records"], stripes[col])
        out.append(
            {
                "damage": damage,
                "median_g": f.median,
                "beta": f.beta,
                "n_levels": f.n_levels,
                "n_runs": f.n_runs,
                "n_damaged": f.n_damaged,
                "note": f.note,
                "_fit": f,
            }
        )
    return out


def design_level_rows(
    stripes: pd.DataFrame,
    design_runs: pd.DataFrame,
    fits: Mapping[str, Any],
    design_g: Iterable[float],
    capacity_m: float | None,
) -> list[dict[str, Any]]:
    """At each design level [g]: ``p_overturn`` and ``p_uplift`` from the fitted fragilities, the
    fractions observed (``p_overturn_observed``), the median and 84th-percentile displacement [m],
    and the fraction of records whose displacement exceeds the capacity."""
    out = []
    for x in design_g:
        g = design_runs[np.isclose(design_runs["pga_g"], x, rtol=1e-12)]
        d = g["max_base_disp_m"].to_numpy(dtype=float)
        n = len(g)
        out.append(
            {
                "pga_g": float(x),
                "p_overturn": float(fits["overturn"].probability(x)),
                "p_uplift": float(fits["uplift"].probability(x)),
                "p_overturn_observed": float((g["outcome_code"] == 2).mean()) if n else math.nan,
                "disp_median_m": float(np.median(d)) if n else math.nan,
                "disp_p84_m": _p84(d),
                "frac_exceed_capacity": float((d > capacity_m).mean()) if (n and capacity_m) else math.nan,
                "n_records": n,
            }
        )
    return out
