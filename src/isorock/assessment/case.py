"""The assessment of one object on one base from its runs: failure modes, fragilities with their
intervals, the values at the design and MCE levels, and the mean annual frequencies with a hazard.

:class:`Settings` holds what the configuration says (stripes, design and MCE levels, capacity, how runs
outside the model count, bootstrap, hazard); :func:`evaluate` turns the runs of one object and base
into a :class:`CaseEvaluation`: the per-stripe counts (:func:`~isorock.assessment.stripes.stripe_table`),
the fragilities of overturning, failure (overturn or isolator displacement beyond the capacity) and
uplift with their bootstrap over records (:func:`~isorock.assessment.fragility.bootstrap_fragility`),
and per design level the probabilities, their 95 % intervals, what was observed at that level with its
exact binomial bounds, the displacement at the maximum considered earthquake, and with a hazard curve
the mean annual frequencies (:mod:`isorock.assessment.hazard`).

**Displacement at the MCE.** The isolation codes check the isolator's displacement capacity at the
maximum considered earthquake with the *average* of the peak displacements over the ground motions
when at least seven are analysed, and with the *maximum* when fewer are (ASCE/SEI 7-10 §17.6.4.3, kept
in ASCE/SEI 7-16 §17.6.3.4 with at least seven motions required by §17.3.3; EN 1998-1:2004
§4.3.3.4.3(3) for time-history analyses): :data:`MIN_RECORDS`. The displacement is the one horizontal
component analysed, not the vector of two: the model has one horizontal input.

**Friction pendulum.** The residual displacement can reach ``mu_b R_b`` (friction holds the slider
anywhere the restoring force ``W u / R_b`` is below ``mu_b W``), and the restoring-force check of ASCE/SEI
7-16 §17.2.4.4 (the force at the total maximum displacement ``D`` exceeds that at ``D / 2`` by at least
2.5 % of the weight: ``D / (2 R_b) >= 0.025``) is reported.

**When no fragility can be fitted** (no failure, every run failing, separated stripes), the
probabilities are reported as not estimable, with the count observed at the level and its exact
binomial bounds; the annual frequency is then the risk integral of the stripes' observed fractions
(a step function, each stripe's fraction held down to the stripe below it) between the integrals of
their Clopper-Pearson bounds: a nonparametric estimate, said to be one.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from ..constants import G
from .fragility import N_BOOTSTRAP, FragilityEstimate, bootstrap_fragility, clopper_pearson
from .hazard import HazardCurve, quadrature, risk_integral
from .levels import mce_levels
from .stripes import classify_runs, outcome_matrices, stripe_table

__all__ = [
    "MIN_RECORDS",
    "DAMAGE_STATES",
    "Settings",
    "CaseEvaluation",
    "evaluate",
    "displacement_statistic",
    "interval_columns",
    "table_row",
]

#: ground motions the isolation codes ask of a response-history analysis (ASCE/SEI 7-16 §17.3.3); with
#: fewer, the maximum of the peak displacements is used instead of their mean
MIN_RECORDS = 7
#: the damage states fitted: overturning, failure (overturn or beyond the capacity), uplift
DAMAGE_STATES = ("overturn", "failure", "uplift")
#: the restoring-force margin of ASCE/SEI 7-16 §17.2.4.4 (fraction of the weight)
RESTORING_MARGIN = 0.025


@dataclass(frozen=True)
class Settings:
    """What an assessment asks for.

    Parameters
    ----------
    stripes : tuple of float
        Stripe levels [g], increasing.
    design : tuple of float
        Design levels [g] (within the stripes' range).
    mce : tuple of float
        The maximum considered earthquake level of each design level [g].
    capacity_m : float or None
        Isolator displacement capacity [m].
    outside_model : {"exclude", "failure"}
        How runs outside the model (sliding, jumping) count.
    n_boot : int
        Bootstrap resamples of the records.
    seed : int
        Seed of the resampling.
    hazard : HazardCurve or None
        The site's hazard curve, in the stripes' unit.
    """

    stripes: tuple[float, ...]
    design: tuple[float, ...] = ()
    mce: tuple[float, ...] = ()
    capacity_m: float | None = None
    outside_model: str = "exclude"
    n_boot: int = N_BOOTSTRAP
    seed: int = 0
    hazard: HazardCurve | None = field(default=None, compare=False)

    @classmethod
    def from_config(cls, a: Mapping[str, Any], basedir: str | Path | None = None) -> Settings:
        """From a validated ``assessment`` section (``mce_g`` default: 1.5 x each design level)."""
        design = tuple(float(x) for x in a.get("design_g") or ())
        mce = tuple(mce_levels(design, a.get("mce_g")))
        hz = a.get("hazard")
        return cls(
            stripes=tuple(float(x) for x in a["stripes_g"]),
            design=design,
            mce=mce,
            capacity_m=a.get("capacity_m"),
            outside_model=str(a.get("outside_model") or "exclude"),
            n_boot=int(a.get("bootstrap", N_BOOTSTRAP)),
            seed=int(a.get("seed", 0)),
            hazard=HazardCurve.from_config(hz, basedir) if hz else None,
        )

    @property
    def levels(self) -> list[float]:
        """Every level a record is run at: stripes, design and MCE levels [g]."""
        return sorted({*self.stripes, *self.design, *self.mce})


def displacement_statistic(d: np.ndarray) -> tuple[float, str]:
    """The codes' statistic of the peak isolator displacements ``d`` [m] of the records at one level:
    their mean with at least :data:`MIN_RECORDS` records, else their maximum; and its name."""
    d = np.asarray(d, dtype=float)
    if d.size == 0:
        return math.nan, "none"
    if d.size >= MIN_RECORDS:
        return float(np.mean(d)), f"mean of {d.size} records"
    return float(np.max(d)), f"maximum of {d.size} records (fewer than {MIN_RECORDS})"


@dataclass
class CaseEvaluation:
    """The assessment of one object on one base (see :func:`evaluate`).

    Attributes
    ----------
    stripes : pandas.DataFrame
        Per stripe: counts of every failure mode and displacement statistics.
    estimates : dict
        ``{damage: FragilityEstimate}`` for :data:`DAMAGE_STATES`.
    levels : list of dict
        Per design level: probabilities with their intervals, what was observed, displacements, MCE.
    hazard : dict or None
        Per damage state (overturn, failure): annual frequency, 50-year probability, intervals.
    n_records : int
        Records analysed.
    n_excluded : int
        Stripe runs outside the model (left out of the fits, or counted as failures).
    by_measure : list of dict
        The fragilities of overturning and of failure fitted against each intensity measure of the runs
        (PGA, PGV, Sa at the isolation period): ``measure``, ``unit``, ``period_s``, ``damage``,
        ``median``, ``beta``, ``estimable``, ``note``. The smaller beta, the better the measure predicts
        the damage (its efficiency, Luco & Cornell 2007).
    """

    stripes: pd.DataFrame
    estimates: dict[str, FragilityEstimate]
    levels: list[dict[str, Any]]
    hazard: dict[str, dict[str, Any]] | None
    n_records: int
    n_excluded: int
    by_measure: list[dict[str, Any]] = field(default_factory=list)

    def band_rows(self, x: Sequence[float]) -> list[dict[str, Any]]:
        """The fitted curves and their 95 % bands at the levels ``x`` [g] (the figures' shading): one row
        per damage state and level, ``p``, ``p_lo``, ``p_hi`` (NaN where not estimable)."""
        rows = []
        for damage, e in self.estimates.items():
            for xi in x:
                ci = e.probability_ci95(float(xi))
                p = e.fit.probability(float(xi)) if e.fit.estimable else math.nan
                lo, hi = (math.nan, math.nan) if ci is None else ci
                rows.append({"damage": damage, "pga_g": float(xi), "p": float(p), "p_lo": lo, "p_hi": hi})
        return rows

    def fragility_rows(self) -> list[dict[str, Any]]:
        """One flat row per damage state (the ``/assessment/fragility`` table)."""
        rows = []
        for damage, e in self.estimates.items():
            s = e.summary()
            rows.append(
                {
                    "damage": damage,
                    "median_g": _nan(s["median_g"]),
                    "beta": _nan(s["beta"]),
                    **interval_columns("median_ci95_g", s["median_ci95_g"]),
                    **interval_columns("beta_ci95", s["beta_ci95"]),
                    "estimable": bool(s["estimable"]),
                    "n_levels": s["n_levels"],
                    "n_runs": s["n_runs"],
                    "n_damaged": s["n_damaged"],
                    "note": s["note"],
                    "n_boot": s["n_boot"],
                    "n_boot_fitted": s["n_boot_fitted"],
                }
            )
        return rows


def _nan(v: float | None) -> float:
    return math.nan if v is None else float(v)


def interval_columns(name: str, ci: Sequence[float] | None) -> dict[str, float]:
    """A 95 % interval as two table columns, ``<name>_lo`` and ``<name>_hi`` (NaN when there is none)."""
    lo, hi = (math.nan, math.nan) if ci is None else (float(ci[0]), float(ci[1]))
    return {f"{name}_lo": lo, f"{name}_hi": hi}


def table_row(row: Mapping[str, Any]) -> dict[str, Any]:
    """A row for an HDF5 table: intervals (``*_ci95`` keys) as ``_lo``/``_hi`` columns, None as NaN."""
    out: dict[str, Any] = {}
    for k, v in row.items():
        if k.endswith("_ci95"):
            out.update(interval_columns(k, v))
        else:
            out[k] = math.nan if v is None else v
    return out


def _observed(runs_at: pd.DataFrame, damage: str, outside_model: str) -> tuple[int, int]:
    """(damaged, counted) among the runs at one level, counted as the fit counts them."""
    if runs_at.empty:
        return 0, 0
    out = runs_at["outside_model"].to_numpy(dtype=bool)
    dmg = runs_at[damage].to_numpy(dtype=bool)
    if damage == "failure" and outside_model == "failure":
        return int(np.sum(dmg | out)), len(runs_at)
    return int(np.sum(dmg & ~out)), int(np.sum(~out))


def _step_envelopes(stripes: Sequence[float], D: np.ndarray, inc: np.ndarray):
    """Nonparametric P(D | x): each stripe's observed fraction (and its two-sided 95 % Clopper-Pearson
    bounds) held from the stripe below it up to the stripe; above the last stripe, the last one's."""
    x = np.asarray(stripes, dtype=float)
    z = (D & inc).sum(0)
    n = inc.sum(0)
    frac = np.where(n > 0, z / np.maximum(n, 1), np.nan)
    lo = np.array([clopper_pearson(int(k), int(m))[0] if m else np.nan for k, m in zip(z, n, strict=True)])
    hi = np.array([clopper_pearson(int(k), int(m))[1] if m else np.nan for k, m in zip(z, n, strict=True)])

    def step(values: np.ndarray):
        v = values.copy()
        good = np.isfinite(v)

        def f(q: np.ndarray) -> np.ndarray:
            idx = np.searchsorted(x[good], np.asarray(q, dtype=float), side="left")
            idx = np.clip(idx, 0, good.sum() - 1)
            return v[good][idx]

        return f

    return step(frac), step(lo), step(hi)


def _hazard_rows(
    settings: Settings,
    estimates: dict[str, FragilityEstimate],
    mats: Mapping[str, tuple[np.ndarray, np.ndarray]],
) -> dict[str, dict[str, Any]] | None:
    hz = settings.hazard
    if hz is None:
        return None
    from .hazard import probability_in

    out: dict[str, dict[str, Any]] = {}
    for damage in ("overturn", "failure"):
        e = estimates[damage]
        if e.fit.estimable:
            ri = risk_integral(_curve(e.fit), hz)
            xq, wq = quadrature(hz)
            pb = _phi(e.a[:, None] + e.b[:, None] * np.log(xq)[None, :])
            pb[e.status == 1] = 0.0
            pb[e.status == 2] = 1.0
            boot = pb @ wq
            ci = [float(v) for v in np.percentile(boot, [2.5, 97.5])] if boot.size else None
            method = "fitted fragility"
        else:
            D, inc = mats[damage]
            mid, lo_f, hi_f = _step_envelopes(settings.stripes, D, inc)
            ri = risk_integral(mid, hz)
            ci = [risk_integral(lo_f, hz).annual_rate, risk_integral(hi_f, hz).annual_rate]
            method = "stripe fractions (no fragility could be fitted)"
        rate = float(ri.annual_rate)
        out[damage] = {
            "annual_rate": rate,
            "annual_rate_ci95": ci,
            "p50": probability_in(rate, 50.0),
            "p50_ci95": None if ci is None else [probability_in(ci[0]), probability_in(ci[1])],
            "above_last_max": float(ri.above_last_max),
            "p_at_first": float(ri.p_at_first),
            "method": method,
        }
    return out


def _curve(f: Any) -> Any:
    """``P(D | x)`` of a fitted fragility, as a function of an array of levels."""

    def p(q: np.ndarray) -> np.ndarray:
        return np.asarray(f.probability(q), dtype=float)

    return p


def _phi(s: np.ndarray) -> np.ndarray:
    from scipy.stats import norm

    return norm.cdf(s)


def evaluate(
    runs: pd.DataFrame, settings: Settings, isolation: Mapping[str, Any] | None = None
) -> CaseEvaluation:
    """The assessment of one object on one base.

    Parameters
    ----------
    runs : pandas.DataFrame
        Its runs: columns ``record``, ``pga_g`` and :data:`~isorock.assessment.stripes.RUN_COLUMNS`, at the
        stripes, design and MCE levels.
    settings : Settings
    isolation : mapping, optional
        The base (``isolation``: none/linear/fp, and ``mu_b``, ``R_b_m`` for FP: the residual
        displacement and the restoring-force check).

    Returns
    -------
    CaseEvaluation
    """
    stripes = np.asarray(settings.stripes, dtype=float)
    lv = runs["pga_g"].to_numpy(dtype=float)
    on_stripe = np.isclose(lv[:, None], stripes[None, :], rtol=1e-12).any(axis=1)
    st_runs = runs[on_stripe]
    table = stripe_table(st_runs, settings.capacity_m) if len(st_runs) else pd.DataFrame()
    records, mats = outcome_matrices(st_runs, settings.stripes, settings.capacity_m, settings.outside_model)
    estimates = {
        d: bootstrap_fragility(settings.stripes, *mats[d], n_boot=settings.n_boot, seed=settings.seed)
        for d in DAMAGE_STATES
    }
    classified = classify_runs(runs, settings.capacity_m)
    levels = []
    iso = dict(isolation or {})
    for k, x in enumerate(settings.design):
        at = classified[np.isclose(lv, x, rtol=1e-12)]
        row: dict[str, Any] = {"pga_g": float(x), "n_records": len(at)}
        for damage in DAMAGE_STATES:
            e = estimates[damage]
            z, n = _observed(at, damage, settings.outside_model)
            row[f"p_{damage}"] = float(e.fit.probability(x)) if e.fit.estimable else None
            row[f"p_{damage}_ci95"] = e.probability_ci95(x)
            row[f"p_{damage}_observed"] = (z / n) if n else None
            row[f"n_{damage}_observed"] = z
            row[f"n_{damage}_counted"] = n
            row[f"p_{damage}_observed_ci95"] = list(clopper_pearson(z, n)) if n else None
            row[f"p_{damage}_upper95"] = clopper_pearson(z, n, side="upper")[1] if n else None
            row[f"{damage}_estimable"] = e.fit.estimable
        row["estimable"] = row["failure_estimable"]
        d = at["max_base_disp_m"].to_numpy(dtype=float)
        row["disp_median_m"] = float(np.median(d)) if d.size else math.nan
        row["disp_p84_m"] = float(np.percentile(d, 84.0)) if d.size else math.nan
        row["frac_exceed_capacity"] = (
            float(np.mean(d > settings.capacity_m)) if (d.size and settings.capacity_m) else math.nan
        )
        row.update(_mce_row(classified, lv, settings, k, iso))
        levels.append(row)
    n_excl = int(st_runs["outside_model"].sum()) if len(st_runs) else 0
    return CaseEvaluation(
        stripes=table,
        estimates=estimates,
        levels=levels,
        hazard=_hazard_rows(settings, estimates, mats),
        n_records=len(records),
        n_excluded=n_excl,
        by_measure=_by_measure(classify_runs(st_runs, settings.capacity_m), settings.outside_model),
    )


#: the measures of a run: column, name, unit
_MEASURE_COLUMNS = (("pga_g", "pga", "g"), ("pgv_m_s", "pgv", "m/s"), ("sa_g", "sa", "g"))


def _by_measure(runs: pd.DataFrame, outside_model: str) -> list[dict[str, Any]]:
    """Fragilities of overturning and failure against each measure the runs carry: every run is its own
    point (a cloud: the records of one stripe differ in PGV and Sa), fitted by maximum likelihood."""
    from .fragility import fit_fragility

    rows = []
    out = runs["outside_model"].to_numpy(dtype=bool) if len(runs) else np.zeros(0, dtype=bool)
    for col, name, unit in _MEASURE_COLUMNS:
        if col not in runs or len(runs) == 0:
            continue
        x = runs[col].to_numpy(dtype=float)
        if not np.all(np.isfinite(x) & (x > 0)):
            continue
        period = None
        if name == "sa" and "sa_period_s" in runs:
            period = float(runs["sa_period_s"].iloc[0])
        for damage in ("overturn", "failure"):
            dmg = runs[damage].to_numpy(dtype=bool)
            if damage == "failure" and outside_model == "failure":
                keep, z = np.ones(x.size, dtype=bool), dmg | out
            else:
                keep, z = ~out, dmg
            f = fit_fragility(x[keep], np.ones(int(keep.sum())), z[keep].astype(float))
            rows.append(
                {"measure": name, "unit": unit, "period_s": period, "damage": damage,
                 "median": f.median, "beta": f.beta, "estimable": f.estimable, "note": f.note}
            )  # fmt: skip
    return rows


def _mce_row(
    classified: pd.DataFrame, lv: np.ndarray, settings: Settings, k: int, iso: Mapping[str, Any]
) -> dict[str, Any]:
    """The displacement check at the MCE level of design level ``k``."""
    if k >= len(settings.mce):
        return {"mce_g": None}
    x = settings.mce[k]
    at = classified[np.isclose(lv, x, rtol=1e-12)]
    d = at["max_base_disp_m"].to_numpy(dtype=float)
    stat, how = displacement_statistic(d)
    cap = settings.capacity_m
    fixed = iso.get("isolation", "") == "none"
    row: dict[str, Any] = {
        "mce_g": float(x),
        "disp_mce_m": 0.0 if fixed else stat,
        "disp_mce_statistic": "fixed base" if fixed else how,
        "disp_mce_p84_m": float(np.percentile(d, 84.0)) if d.size else math.nan,
        "n_mce_records": int(d.size),
        "n_mce_exceed_capacity": int(np.sum(d > cap)) if cap else 0,
        "mce_within_capacity": bool(fixed or cap is None or (math.isfinite(stat) and stat <= cap)),
        "n_mce_overturn": int(at["overturn"].sum()) if len(at) else 0,
    }
    if iso.get("isolation") == "fp" and iso.get("mu_b") is not None and iso.get("R_b_m") is not None:
        mu, rb = float(iso["mu_b"]), float(iso["R_b_m"])
        row["residual_max_m"] = mu * rb
        row["recentring_ok"] = bool(math.isfinite(stat) and stat / (2.0 * rb) >= RESTORING_MARGIN)
        row["fp_period_s"] = 2.0 * math.pi * math.sqrt(rb / G)
    return row
