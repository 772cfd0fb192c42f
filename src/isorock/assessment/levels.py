"""The levels an assessment runs every record at: stripes, design levels and their maximum considered
earthquake (MCE) levels, and where each design and MCE level comes from. A light module (numpy and
the hazard curve's reader, no fits): the workflow's planning reads it for every job.

A design level is given in g (``design_g``), or as a return period read off the site's hazard curve
(``design_return_period_yr``: the PGA whose annual frequency of exceedance is ``1 / T``). Its MCE
level is given in g (``mce_g``), as a return period off the curve (``mce_return_period_yr``, e.g.
2475 years), or by default :data:`MCE_FACTOR` times the design level: the ratio of the MCE to the
design spectral accelerations of ASCE/SEI 7-16 (S_DS = 2/3 S_MS), applied here to the PGA, which is
an approximation (the codes define the ratio for spectral values, and a site's PGA ratio between two
return periods is what its hazard curve says). Each level carries its basis in words
(:attr:`Levels.design_basis`, :attr:`Levels.mce_basis`), printed with the results.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

__all__ = ["MCE_FACTOR", "Levels", "mce_levels", "resolve_levels", "run_levels_of", "level_round"]

#: the default MCE level as a multiple of the design level: S_MS / S_DS = 1.5 of ASCE/SEI 7-16, borrowed
#: for the PGA (an approximation, said so wherever the level is printed)
MCE_FACTOR = 1.5


def level_round(x: float) -> float:
    """A level [g] as it is run and printed: 4 significant digits (so that 1.5 x 0.4 is the 0.6 g of a
    stripe, not 0.6000000000000001 g, a second level beside it)."""
    return float(f"{float(x):.4g}")


@dataclass(frozen=True)
class Levels:
    """The design and MCE levels of an assessment, and their bases in words.

    Attributes
    ----------
    design : tuple of float
        Design levels [g].
    mce : tuple of float
        MCE level of each design level [g].
    design_basis, mce_basis : tuple of str
        Where each level comes from ("given", "the 475-year PGA of the hazard curve", "1.5 x the design
        level (approximation ...)").
    """

    design: tuple[float, ...] = ()
    mce: tuple[float, ...] = ()
    design_basis: tuple[str, ...] = ()
    mce_basis: tuple[str, ...] = ()


def mce_levels(design_g: Sequence[float], mce_g: float | Sequence[float] | None = None) -> list[float]:
    """The MCE level of each design level [g]: ``mce_g`` (one value for all, or one per design level),
    by default :data:`MCE_FACTOR` times each design level."""
    design = [float(x) for x in design_g]
    if mce_g is None:
        return [level_round(MCE_FACTOR * x) for x in design]
    if isinstance(mce_g, int | float):
        return [float(mce_g) for _ in design]
    return [float(x) for x in mce_g]


def _periods(v: Any, n: int | None = None) -> list[float]:
    if v is None:
        return []
    vals = [float(v)] if isinstance(v, int | float) else [float(x) for x in v]
    return vals * n if (n is not None and len(vals) == 1 and n > 1) else vals


def _read_off(curve: Any, years: float, key: str) -> float:
    """The level [g] of a return period on the hazard curve, to 3 significant digits (what an
    interpolated hazard curve supports)."""
    return float(f"{curve.level_at_return_period(years, key):.3g}")


def resolve_levels(a: Mapping[str, Any], basedir: str | Path | None = None) -> Levels:
    """The design and MCE levels of an ``assessment`` section (see the module docstring).

    Parameters
    ----------
    a : mapping
        The section (validated: ``design_g`` and ``design_return_period_yr`` are not both given, nor
        ``mce_g`` and ``mce_return_period_yr``; return periods come with a ``hazard``).
    basedir : path-like, optional
        Where a relative hazard file is (default: the working directory).

    Raises
    ------
    ConfigError
        A return period outside the hazard curve's range (nothing is extrapolated).
    """
    hz_cfg = a.get("hazard")
    curve = None
    if a.get("design_return_period_yr") or a.get("mce_return_period_yr"):
        from .hazard import HazardCurve

        if not hz_cfg:
            from ..errors import ConfigError

            raise ConfigError("assessment: a return period is read off the site's hazard curve: give hazard")
        curve = HazardCurve.from_config(hz_cfg, basedir if basedir is not None else Path.cwd())
    if a.get("design_return_period_yr"):
        assert curve is not None
        periods = _periods(a["design_return_period_yr"])
        design = [_read_off(curve, T, "design_return_period_yr") for T in periods]
        design_basis = [f"the {T:g}-year PGA of the site's hazard curve" for T in periods]
    else:
        design = [float(x) for x in a.get("design_g") or []]
        design_basis = ["given (design_g)" for _ in design]
    if a.get("mce_return_period_yr"):
        assert curve is not None
        periods = _periods(a["mce_return_period_yr"], len(design))
        mce = [_read_off(curve, T, "mce_return_period_yr") for T in periods]
        mce_basis = [f"the {T:g}-year PGA of the site's hazard curve" for T in periods]
    elif a.get("mce_g") is not None:
        mce = mce_levels(design, a.get("mce_g"))
        mce_basis = ["given (mce_g)" for _ in mce]
    else:
        mce = mce_levels(design)
        mce_basis = [
            f"{MCE_FACTOR:g} x the design level: the codes' ratio of MCE to design spectral accelerations "
            "(ASCE/SEI 7-16, S_DS = 2/3 S_MS) applied to the PGA, an approximation; a hazard curve with "
            "mce_return_period_yr gives the site's own"
            for _ in mce
        ]
    return Levels(tuple(design), tuple(mce), tuple(design_basis), tuple(mce_basis))


def run_levels_of(a: Mapping[str, Any], basedir: str | Path | None = None) -> list[float]:
    """Every level of an ``assessment`` section, sorted: stripes, design and MCE levels [g]."""
    lv = resolve_levels(a, basedir)
    return sorted({*map(float, a["stripes_g"]), *lv.design, *lv.mce})
