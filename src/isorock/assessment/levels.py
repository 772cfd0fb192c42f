"""The levels an assessment runs every record at: stripes, design levels and their maximum considered
earthquake (MCE) levels, and where each design and MCE level comes from. A light module (numpy and
the hazard curve's reader, no fits): the workflow's planning reads it for every job.

A design level is given in g (``design_g``), or as a return period read off the site's hazard curve
(``design_return_period_yr``: the PGA whose annual frequency of exceedance is ``1 / T``). Its MCE
level is given in g (``mce_g``), as a return period off the curve (``mce_return_period_yr``), or, with
a hazard curve, by default its 2475-year level (:data:`MCE_RETURN_PERIOD_YR`). Without a hazard curve
and without ``mce_g`` the configuration is refused: no ratio of MCE to design level is assumed (the
codes' 1.5 for spectral values is no site's ratio for the PGA; the worked example's curve gives 2.0).
Each level carries its basis in words
(:attr:`Levels.design_basis`, :attr:`Levels.mce_basis`), printed with the results.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

__all__ = [
    "MCE_FACTOR",
    "MCE_RETURN_PERIOD_YR",
    "Levels",
    "mce_levels",
    "resolve_levels",
    "run_levels_of",
    "level_round",
]

#: the ratio S_MS / S_DS = 1.5 of ASCE/SEI 7-16 (:func:`mce_levels` without ``mce_g``): no longer a
#: default of the assessment, whose MCE level is given or read off the hazard curve
MCE_FACTOR = 1.5
#: the MCE's return period read off a hazard curve when none is given [years]: 2 % in 50 years, the
#: MCE of ASCE/SEI 7-05 and of the isolation chapters before the risk-targeted MCE_R
MCE_RETURN_PERIOD_YR = 2475.0


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
        Where each level comes from ("given (design_g)", "the 475-year level of OpenQuake's mean curve
        at site 3 (...), file ...").
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


def _source(curve: Any) -> str:
    """The curve in words ("OpenQuake's mean curve at site 3 (lon .., lat ..), file ..."), else "the site's
    hazard curve"."""
    return curve.describe() if hasattr(curve, "describe") else "the site's hazard curve"


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
        from isorock.assessment.hazard_files import curve_from_config

        if not hz_cfg:
            from isorock.errors import ConfigError

            raise ConfigError("assessment: a return period is read off the site's hazard curve: give hazard")
        curve = curve_from_config(hz_cfg, basedir if basedir is not None else Path.cwd())
    if a.get("design_return_period_yr"):
        assert curve is not None
        periods = _periods(a["design_return_period_yr"])
        design = [_read_off(curve, T, "design_return_period_yr") for T in periods]
        design_basis = [f"the {T:g}-year level of {_source(curve)}" for T in periods]
    else:
        design = [float(x) for x in a.get("design_g") or []]
        design_basis = ["given (design_g)" for _ in design]
    if a.get("mce_return_period_yr"):
        assert curve is not None
        periods = _periods(a["mce_return_period_yr"], len(design))
        mce = [_read_off(curve, T, "mce_return_period_yr") for T in periods]
        mce_basis = [f"the {T:g}-year level of {_source(curve)}" for T in periods]
    elif a.get("mce_g") is not None:
        mce = mce_levels(design, a.get("mce_g"))
        mce_basis = ["given (mce_g)" for _ in mce]
    elif curve is not None or hz_cfg:
        if curve is None:
            from isorock.assessment.hazard_files import curve_from_config

            assert hz_cfg is not None
            curve = curve_from_config(hz_cfg, basedir if basedir is not None else Path.cwd())
        T = MCE_RETURN_PERIOD_YR
        mce = [_read_off(curve, T, "mce_return_period_yr (default 2475)") for _ in design]
        mce_basis = [f"the {T:g}-year level of {_source(curve)} (the default MCE)" for _ in mce]
    elif design:
        from isorock.errors import ConfigError

        raise ConfigError(
            "configuration: assessment: the MCE level is needed (the collapse check and the isolator's "
            "displacement are judged there): give mce_g (g), or a hazard curve (its 2475-year level, or "
            "mce_return_period_yr)"
        )
    else:
        mce, mce_basis = [], []
    return Levels(tuple(design), tuple(mce), tuple(design_basis), tuple(mce_basis))


def run_levels_of(a: Mapping[str, Any], basedir: str | Path | None = None) -> list[float]:
    """Every level of an ``assessment`` section, sorted: stripes, design and MCE levels [g]."""
    lv = resolve_levels(a, basedir)
    return sorted({*map(float, a["stripes_g"]), *lv.design, *lv.mce})
