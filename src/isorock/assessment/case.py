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

**Displacement at the MCE.** A candidate isolator is *eligible* when the codes' statistic of its peak
displacements at the maximum considered earthquake is within the capacity: the *mean* of the records'
peaks when at least :data:`MIN_RECORDS` records are analysed, their *maximum* with fewer (the rule of
EN 1998-1:2004 §4.3.3.4.3(3) for time-history analyses; ASCE/SEI 7-16 asks for at least seven ground
motions in a response-history analysis and uses their average). The statistic carries its bootstrap
interval (the records resampled as for the fragilities), and beside it the *probability* that the
displacement exceeds the capacity at the MCE and at the design level: the fraction of records beyond
it with its exact (Clopper-Pearson) 95 % interval. A run that overturns the object enters with the
peak it reached up to the overturn: a lower bound of what the isolator would do (the model stops
there), counted and said (``n_mce_overturn``). The displacement is the one horizontal component
analysed, not the vector of two: the model has one horizontal input.

**Friction pendulum.** The residual displacement can reach ``mu_b R_b`` (friction holds the slider
anywhere the restoring force ``W u / R_b`` is below ``mu_b W``), and the restoring-force check of ASCE/SEI
7-16 §17.2.4.4 (the force at the total maximum displacement ``D`` exceeds that at ``D / 2`` by at least
2.5 % of the weight: ``D / (2 R_b) >= 0.025``) is reported.

**When no fragility can be fitted** (no failure, every run failing, separated stripes), the
probabilities are reported as not estimable, with the count observed at the level and its exact
binomial bounds; the annual frequency is then the risk integral of the stripes' observed fractions
(a step function, each stripe's fraction held down to the stripe below it) between the integrals of
their Clopper-Pearson bounds: a nonparametric estimate, said to be one.

**Resamples kept for comparisons.** Every estimate of an evaluation is computed on the same bootstrap
resamples of its records (:func:`~isorock.assessment.fragility.resample_weights`): the same records in
the same order and the same seed give every base the same resamples. The resampled values of the
metrics the design search compares are kept (:attr:`CaseEvaluation.samples`), on two footings, so that
two bases are compared resample by resample and on the same footing: *fitted* (the probability of
failure at each design level of the resample's fragility; the risk integral of it) where the failure
fragility of all the data is estimable, and *observed* always (the resample's fraction of failing
records at each design level; the risk integral of its stripe fractions).
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from isorock.assessment.fragility import (
    N_BOOTSTRAP,
    FragilityEstimate,
    bootstrap_cloud,
    bootstrap_fragility,
    clopper_pearson,
    resample_weights,
)
from isorock.assessment.hazard import FIRST_POINT_TOLERANCE, HazardCurve, quadrature, risk_integral
from isorock.assessment.hazard_files import curve_from_config
from isorock.assessment.levels import resolve_levels
from isorock.assessment.scaling import Scaling, scaling_from_config
from isorock.assessment.stripes import classify_runs, outcome_matrices, stripe_table
from isorock.assessment.target import Target
from isorock.constants import G

__all__ = [
    "MIN_RECORDS",
    "GAMMA_X",
    "DISP_FRACTILE",
    "EQUIVALENCE_MARGIN",
    "DAMAGE_STATES",
    "Settings",
    "CaseEvaluation",
    "evaluate",
    "displacement_statistic",
    "interval_columns",
    "table_row",
    "PAIR_KEY",
]

#: ground motions the isolation codes ask of a response-history analysis (ASCE/SEI 7-16 asks for at
#: least seven); with fewer, the maximum of the peak displacements is used instead of their mean (the
#: rule of EN 1998-1 §4.3.3.4.3(3))
MIN_RECORDS = 7
#: the damage states fitted: overturning, failure (overturn or beyond the capacity), uplift
DAMAGE_STATES = ("overturn", "failure", "uplift")
#: the restoring-force margin of ASCE/SEI 7-16 §17.2.4.4 (fraction of the weight)
RESTORING_MARGIN = 0.025
#: the factor on the isolator's displacement before it is compared with the capacity: gamma_x of EN
#: 1998-1:2004 §10.3(2) (recommended value 1.2), "the reliability of the isolating system" increased by
#: designing each isolator for gamma_x times the displacement of the analysis
GAMMA_X = 1.2
#: the fractile of the records' peak displacements at the MCE checked besides the codes' statistic
DISP_FRACTILE = 0.9
#: the default margin of equivalence, as a fraction of the fixed base's estimate
EQUIVALENCE_MARGIN = 0.1


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
    design_basis, mce_basis : tuple of str
        Where each design and MCE level comes from, in words
        (:func:`~isorock.assessment.levels.resolve_levels`).
    target : Target
        What a base must meet to be adequate (:mod:`isorock.assessment.target`).
    gamma_x : float
        Factor on the isolator's displacement before it meets the capacity [-] (:data:`GAMMA_X`).
    disp_fractile : float
        The fractile of the records' peak displacements at the MCE checked besides the codes' statistic.
    equivalence_margin : float
        How close to the best a simpler isolator must be shown to be, as a fraction of the fixed
        base's estimate (:func:`isorock.assessment.paired.equivalent`).
    scaling : Scaling
        The stripes' intensity measure and the component definition the records are scaled on
        (:mod:`isorock.assessment.scaling`); the levels are in its unit.
    """

    stripes: tuple[float, ...]
    design: tuple[float, ...] = ()
    mce: tuple[float, ...] = ()
    capacity_m: float | None = None
    outside_model: str = "exclude"
    n_boot: int = N_BOOTSTRAP
    seed: int = 0
    hazard: HazardCurve | None = field(default=None, compare=False)
    design_basis: tuple[str, ...] = ()
    mce_basis: tuple[str, ...] = ()
    target: Target = field(default_factory=Target)
    gamma_x: float = GAMMA_X
    disp_fractile: float = DISP_FRACTILE
    equivalence_margin: float = EQUIVALENCE_MARGIN
    scaling: Scaling = field(default_factory=Scaling)

    @property
    def capacity_factored_m(self) -> float | None:
        """The capacity the analysed displacement is compared with: ``capacity_m / gamma_x`` [m]."""
        return None if not self.capacity_m else float(self.capacity_m) / self.gamma_x

    @classmethod
    def from_config(cls, a: Mapping[str, Any], basedir: str | Path | None = None) -> Settings:
        """From a validated ``assessment`` section (the levels of
        :func:`~isorock.assessment.levels.resolve_levels`)."""
        lv = resolve_levels(a, basedir)
        hz = a.get("hazard")
        curve = curve_from_config(hz, basedir if basedir is not None else Path.cwd()) if hz else None
        return cls(
            stripes=tuple(float(x) for x in a["stripes_g"]),
            design=lv.design,
            mce=lv.mce,
            capacity_m=a.get("capacity_m"),
            outside_model=str(a.get("outside_model") or "exclude"),
            n_boot=int(a.get("bootstrap", N_BOOTSTRAP)),
            seed=int(a.get("seed", 0)),
            hazard=curve,
            design_basis=lv.design_basis,
            mce_basis=lv.mce_basis,
            target=Target.from_config(a.get("target"), bool(hz)),
            gamma_x=float(a.get("gamma_x", GAMMA_X)),
            disp_fractile=float(a.get("disp_fractile", DISP_FRACTILE)),
            equivalence_margin=float(a.get("equivalence_margin", EQUIVALENCE_MARGIN)),
            scaling=scaling_from_config(a, curve),
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
        ``median``, ``beta`` and their ``_ci95`` (bootstrap), ``estimable``, ``note``. The smaller beta,
        the better the measure predicts the damage (its efficiency, Luco & Cornell 2007).
    records : list of str
        The records, in the order of the resamples' columns.
    samples : dict
        Resampled values of the compared metrics, one per bootstrap resample (the same resamples for
        every base evaluated with the same records and seed): ``p_failure_fitted`` and
        ``p_failure_observed`` (lists, one array per design level; the fitted ones None where the
        failure fragility is not estimable) and, with a hazard curve, ``annual_rate_failure_fitted``
        (None where not estimable) and ``annual_rate_failure_observed`` (the risk integral of the
        stripe fractions), with the point estimate of the last one, ``annual_rate_failure_observed_est``.
    """

    stripes: pd.DataFrame
    estimates: dict[str, FragilityEstimate]
    levels: list[dict[str, Any]]
    hazard: dict[str, dict[str, Any]] | None
    n_records: int
    n_excluded: int
    by_measure: list[dict[str, Any]] = field(default_factory=list)
    records: list[str] = field(default_factory=list)
    samples: dict[str, Any] = field(default_factory=dict, repr=False)

    def band_rows(self, x: Sequence[float]) -> list[dict[str, Any]]:
        """The fitted curves and their 95 % bands at the levels ``x`` [g] (the figures' shading): one row
        per damage state and level, ``p``, ``p_lo``, ``p_hi`` (NaN where not estimable)."""
        rows = []
        for damage, e in self.estimates.items():
            for xi in x:
                ci = e.probability_ci95(float(xi))
                p = e.fit.probability(float(xi)) if e.fit.estimable else math.nan
                lo, hi = (math.nan, math.nan) if ci is None else ci
                rows.append({"damage": damage, "level": float(xi), "p": float(p), "p_lo": lo, "p_hi": hi})
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


#: the keys of a pair of numbers (an interval, two bounds): ``*_ci95``, ``*_bounds``, with a unit suffix
PAIR_KEY = re.compile(r"_(ci95|bounds)(_[a-z]+)?$")


def table_row(row: Mapping[str, Any]) -> dict[str, Any]:
    """A row for an HDF5 table: intervals and bounds (:data:`PAIR_KEY`: ``*_ci95``, ``*_ci95_m``,
    ``*_bounds``) as ``_lo``/``_hi`` columns, None as NaN."""
    out: dict[str, Any] = {}
    for k, v in row.items():
        if PAIR_KEY.search(k) and (v is None or isinstance(v, list | tuple)):
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


def _step(stripes: Sequence[float], values: np.ndarray):
    """The step function of per-stripe values (one row per resample, or one row): each stripe's value
    held from the stripe below it up to the stripe, the last one's above it; a stripe with no value
    (no run counted) takes the next stripe's above it, else the one below."""
    x = np.asarray(stripes, dtype=float)
    v = np.atleast_2d(np.asarray(values, dtype=float))
    if np.isnan(v).any():
        v = pd.DataFrame(v).bfill(axis=1).ffill(axis=1).to_numpy()

    def f(q: np.ndarray) -> np.ndarray:
        idx = np.clip(np.searchsorted(x, np.asarray(q, dtype=float), side="left"), 0, x.size - 1)
        out = v[:, idx]
        return out[0] if np.ndim(values) == 1 else out

    return f


def _fractions(D: np.ndarray, inc: np.ndarray, W: np.ndarray | None = None) -> np.ndarray:
    """Per stripe, the fraction of the counted runs that are damaged: of the records (one row), or of
    each resample (a row per row of ``W``); NaN where none is counted."""
    z, n = (D & inc).astype(float), inc.astype(float)
    if W is None:
        zs, ns = z.sum(0), n.sum(0)
    else:
        zs, ns = W @ z, W @ n
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(ns > 0, zs / np.where(ns > 0, ns, 1.0), np.nan)


#: the return periods [years] that cut the deaggregation of an annual frequency into bands of shaking
DEAGG_YEARS = (50.0, 475.0, 2475.0, 10000.0)


def deaggregate(p_nodes: np.ndarray, hazard: HazardCurve) -> list[dict[str, Any]]:
    """Which shaking contributes the annual frequency ``sum w_i P(x_i)``: its parts from levels whose
    return period ``1 / H(x)`` lies below 50 years, 50 to 475, 475 to 2475, 2475 to 10000 and beyond
    (:data:`DEAGG_YEARS`; the exceedances of the curve's last level count in the band of that level).

    Returns
    -------
    list of dict
        Per band with a part: ``from_yr``, ``to_yr`` (None: unbounded), ``annual_rate`` [1/yr],
        ``share`` [-] of the total.
    """
    xq, wq = quadrature(hazard)
    part = np.asarray(p_nodes, dtype=float) * wq
    total = float(part.sum())
    T = 1.0 / hazard.rate(np.clip(xq, hazard.levels[0], hazard.levels[-1]))
    edges = (0.0, *DEAGG_YEARS, math.inf)
    out = []
    for lo, hi in zip(edges[:-1], edges[1:], strict=True):
        sel = (T >= lo) & (T < hi)
        r = float(part[sel].sum())
        if r > 0:
            out.append(
                {"from_yr": lo, "to_yr": None if math.isinf(hi) else hi, "annual_rate": r,
                 "share": r / total if total > 0 else math.nan}
            )  # fmt: skip
    return out


def _hazard_rows(
    settings: Settings,
    estimates: dict[str, FragilityEstimate],
    mats: Mapping[str, tuple[np.ndarray, np.ndarray]],
    W: np.ndarray,
) -> tuple[dict[str, dict[str, Any]] | None, dict[str, Any]]:
    """Per damage state (overturn, failure) the risk integral with its interval, its two tails and its
    deaggregation by return period; and the resampled annual frequencies of failure on both footings
    (fitted, observed). Failure includes overturning: its fitted frequency integrates ``max(P(failure),
    P(overturn))`` (the bound by its part), so that it is never below the frequency of overturning."""
    hz = settings.hazard
    if hz is None:
        return None, {}
    from isorock.assessment.hazard import probability_in

    out: dict[str, dict[str, Any]] = {}
    samples: dict[str, Any] = {}
    xq, wq = quadrature(hz)
    over = estimates["overturn"]
    for damage in ("overturn", "failure"):
        e = estimates[damage]
        D, inc = mats[damage]
        steps = _step(settings.stripes, _fractions(D, inc, W))(xq) @ wq if W.shape[0] else np.zeros(0)
        steps_fn = _step(settings.stripes, _fractions(D, inc))
        steps_est = risk_integral(steps_fn, hz)
        lo_f, hi_f = _exact_envelopes(D, inc)
        exact_ci = [risk_integral(_step(settings.stripes, lo_f), hz).annual_rate,
                    risk_integral(_step(settings.stripes, hi_f), hz).annual_rate]  # fmt: skip
        bounded = damage == "failure" and over.fit.estimable
        if e.fit.estimable:
            fn = _curve(e.fit, over.fit if bounded else None)
            ri = risk_integral(fn, hz)
            p_nodes = fn(xq)
            pb = _phi(e.a[:, None] + e.b[:, None] * np.log(xq)[None, :])
            pb[e.status == 1] = 0.0
            pb[e.status == 2] = 1.0
            if bounded and over.n_boot == e.n_boot:
                po = _phi(over.a[:, None] + over.b[:, None] * np.log(xq)[None, :])
                po[over.status == 1] = 0.0
                po[over.status == 2] = 1.0
                pb = np.maximum(pb, po)
            boot = pb @ wq
            ci = [float(v) for v in np.percentile(boot, [2.5, 97.5])] if boot.size else None
            method = "fitted fragility"
        else:
            boot = None
            ri = steps_est
            p_nodes = steps_fn(xq)
            # between the integrals of the stripes' exact (Clopper-Pearson) bounds: an interval that a
            # resampling of records with no failure at all (every resample zero) would not give
            ci = exact_ci
            method = "stripe fractions (no fragility could be fitted)"
        rate = float(ri.annual_rate)
        if damage == "failure":
            samples = {
                "annual_rate_failure_fitted": boot,
                "annual_rate_failure_observed": steps,
                "annual_rate_failure_observed_est": float(steps_est.annual_rate),
            }
        out[damage] = {
            "annual_rate": rate,
            "annual_rate_ci95": ci,
            "annual_rate_exact_ci95": exact_ci,
            "annual_rate_bounds": [rate, float(ri.upper)],
            "tails_differ": bool(rate > 0 and ri.tails_differ),
            "p50": probability_in(rate, 50.0),
            "p50_ci95": None if ci is None else [probability_in(ci[0]), probability_in(ci[1])],
            "above_last_max": float(ri.above_last_max),
            "p_at_first": float(ri.p_at_first),
            "first_point_matters": bool(ri.p_at_first > FIRST_POINT_TOLERANCE),
            "method": method,
            "n_damaged_stripes": int((D & inc).sum()),
            "deaggregation": json.dumps(deaggregate(p_nodes, hz)),
        }
    return out, samples


def _exact_envelopes(D: np.ndarray, inc: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per stripe, the two-sided 95 % Clopper-Pearson bounds of the fraction damaged (NaN where no run
    is counted)."""
    z = (D & inc).sum(0)
    n = inc.sum(0)
    lo = np.array([clopper_pearson(int(k), int(m))[0] if m else np.nan for k, m in zip(z, n, strict=True)])
    hi = np.array([clopper_pearson(int(k), int(m))[1] if m else np.nan for k, m in zip(z, n, strict=True)])
    return lo, hi


def _curve(f: Any, at_least: Any = None) -> Any:
    """``P(D | x)`` of a fitted fragility, as a function of an array of levels; with ``at_least`` (a
    fitted fragility of a part of the damage), never below it."""

    def p(q: np.ndarray) -> np.ndarray:
        v = np.asarray(f.probability(q), dtype=float)
        return v if at_least is None else np.maximum(v, np.asarray(at_least.probability(q), dtype=float))

    return p


def _phi(s: np.ndarray) -> np.ndarray:
    """The standard normal CDF: ``scipy.special.ndtr``, what ``scipy.stats.norm.cdf`` computes (the same
    numbers, without its checks of the arguments)."""
    from scipy.special import ndtr

    return ndtr(s)


def evaluate(
    runs: pd.DataFrame,
    settings: Settings,
    isolation: Mapping[str, Any] | None = None,
    *,
    records: Sequence[str] | None = None,
    measures: bool = True,
) -> CaseEvaluation:
    """The assessment of one object on one base.

    Parameters
    ----------
    runs : pandas.DataFrame
        Its runs: columns ``record``, ``level`` and :data:`~isorock.assessment.stripes.RUN_COLUMNS`, at the
        stripes, design and MCE levels.
    settings : Settings
    isolation : mapping, optional
        The base (``isolation``: none/linear/fp, and ``mu_b``, ``R_b_m`` for FP: the residual
        displacement and the restoring-force check).
    records : sequence of str, optional
        The records, in the order of the resamples (default: those of ``runs``, sorted). Bases
        evaluated with the same records and settings share their resamples.
    measures : bool
        Fit the fragilities against the other intensity measures too (:attr:`CaseEvaluation.by_measure`).

    Returns
    -------
    CaseEvaluation
    """
    stripes = np.asarray(settings.stripes, dtype=float)
    lv = runs["level"].to_numpy(dtype=float)
    on_stripe = np.isclose(lv[:, None], stripes[None, :], rtol=1e-12).any(axis=1)
    st_runs = runs[on_stripe]
    cap = settings.capacity_factored_m
    table = stripe_table(st_runs, cap) if len(st_runs) else pd.DataFrame()
    recs = sorted(runs["record"].unique()) if records is None else list(records)
    W = resample_weights(len(recs), settings.n_boot, settings.seed)
    _, mats = outcome_matrices(st_runs, settings.stripes, cap, settings.outside_model, recs)
    estimates = {d: bootstrap_fragility(settings.stripes, *mats[d], weights=W) for d in DAMAGE_STATES}
    classified = classify_runs(runs, cap)
    rindex = {r: i for i, r in enumerate(recs)}
    levels = []
    p_fitted: list[np.ndarray | None] = []
    p_observed: list[np.ndarray] = []
    iso = dict(isolation or {})
    fail, over = estimates["failure"], estimates["overturn"]
    for k, x in enumerate(settings.design):
        at = classified[np.isclose(lv, x, rtol=1e-12)]
        row: dict[str, Any] = {"level": float(x), "n_records": len(at)}
        if k < len(settings.design_basis):
            row["design_basis"] = settings.design_basis[k]
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
        fitted, observed = _failure_samples(fail, at, x, rindex, W, settings.outside_model)
        row["p_failure_bounded_by_overturn"] = False
        if fail.fit.estimable and over.fit.estimable and fitted is not None and fitted.size:
            p, row["p_failure_ci95"], fitted = _failure_bounded(fail, over, x)
            row["p_failure_bounded_by_overturn"] = p > row["p_failure"]
            row["p_failure"] = p
        p_fitted.append(fitted)
        p_observed.append(observed)
        d = at["max_base_disp_m"].to_numpy(dtype=float)
        row["disp_median_m"] = float(np.median(d)) if d.size else math.nan
        row["disp_p84_m"] = float(np.percentile(d, 84.0)) if d.size else math.nan
        row.update(_exceedance(d, cap, iso, ""))
        row["frac_exceed_capacity"] = row["p_exceed_capacity"]
        row.update(_mce_row(classified, lv, settings, k, iso, rindex, W))
        row.update(_failure_at_mce(classified, lv, settings, k, fail, over, len(recs)))
        levels.append(row)
    n_excl = int(st_runs["outside_model"].sum()) if len(st_runs) else 0
    hazard, rate_samples = _hazard_rows(settings, estimates, mats, W)
    by_measure = (
        _by_measure(classify_runs(st_runs, cap), settings.outside_model, rindex, W) if measures else []
    )
    return CaseEvaluation(
        stripes=table,
        estimates=estimates,
        levels=levels,
        hazard=hazard,
        n_records=int(runs["record"].nunique()),
        n_excluded=n_excl,
        by_measure=by_measure,
        records=recs,
        samples={"p_failure_fitted": p_fitted, "p_failure_observed": p_observed, **rate_samples},
    )


def _failure_samples(
    e: FragilityEstimate,
    at: pd.DataFrame,
    x: float,
    rindex: Mapping[str, int],
    W: np.ndarray,
    outside_model: str,
) -> tuple[np.ndarray | None, np.ndarray]:
    """P(failure) at the design level ``x`` on every resample, on both footings: the resample's fitted
    fragility (None where the fit of all the data is not estimable), and the resample's fraction of the
    runs at that level (NaN where a resample counts none)."""
    if W.shape[0] == 0:
        return (np.zeros(0) if e.fit.estimable else None), np.zeros(0)
    fitted = np.asarray(e.resampled_probability(x), dtype=float) if e.fit.estimable else None
    fail = np.zeros(W.shape[1])
    counted = np.zeros(W.shape[1])
    out = at["outside_model"].to_numpy(dtype=bool)
    dmg = at["failure"].to_numpy(dtype=bool)
    for r, f, o in zip(at["record"], dmg, out, strict=True):
        i = rindex.get(r)
        if i is None:
            continue
        if outside_model == "failure":
            counted[i], fail[i] = 1.0, float(f or o)
        elif not o:
            counted[i], fail[i] = 1.0, float(f)
    ns, zs = W @ counted, W @ fail
    with np.errstate(invalid="ignore", divide="ignore"):
        return fitted, np.where(ns > 0, zs / np.where(ns > 0, ns, 1.0), np.nan)


def _exceedance(d: np.ndarray, cap: float | None, iso: Mapping[str, Any], at: str) -> dict[str, Any]:
    """The fraction of records whose peak displacement ``d`` [m] exceeds the capacity, with its exact
    95 % interval (None on a fixed base, which has no isolator, or without a capacity); keys
    ``n_<at>exceed_capacity``, ``p_<at>exceed_capacity`` and its ``_ci95``."""
    n = int(np.sum(d > cap)) if (cap and d.size) else 0
    if iso.get("isolation") == "none" or not cap or not d.size:
        return {
            f"n_{at}exceed_capacity": n,
            f"p_{at}exceed_capacity": None,
            f"p_{at}exceed_capacity_ci95": None,
        }
    return {
        f"n_{at}exceed_capacity": n,
        f"p_{at}exceed_capacity": n / d.size,
        f"p_{at}exceed_capacity_ci95": list(clopper_pearson(n, int(d.size))),
    }


#: the measures of the analysed component of a run: column, name (OpenQuake's, SA's period added), unit
_MEASURE_COLUMNS = (("pga_g", "PGA", "g"), ("pgv_m_s", "PGV", "m/s"), ("sa_g", "SA", "g"))


def _by_measure(
    runs: pd.DataFrame, outside_model: str, rindex: Mapping[str, int], W: np.ndarray
) -> list[dict[str, Any]]:
    """Fragilities of overturning and failure against each measure the runs carry: every run is its own
    point (a cloud: the records of one stripe differ in PGV and Sa), fitted by maximum likelihood, with
    the bootstrap over records of its median and beta (the same resamples as every other estimate)."""
    rows: list[dict[str, Any]] = []
    if len(runs) == 0:
        return rows
    out = runs["outside_model"].to_numpy(dtype=bool)
    rec = np.array([rindex.get(r, -1) for r in runs["record"]])
    for col, name, unit in _MEASURE_COLUMNS:
        if col not in runs:
            continue
        x = runs[col].to_numpy(dtype=float)
        if not np.all(np.isfinite(x) & (x > 0)) or np.any(rec < 0):
            continue
        period = None
        if name == "SA" and "sa_period_s" in runs:
            period = float(runs["sa_period_s"].iloc[0])
            name = f"SA({float(f'{period:.3g}')!r})"  # the FP's 2 pi sqrt(R_b / g): SA(3.0), not 3.0024
        for damage in ("overturn", "failure"):
            dmg = runs[damage].to_numpy(dtype=bool)
            if damage == "failure" and outside_model == "failure":
                keep, z = np.ones(x.size, dtype=bool), dmg | out
            else:
                keep, z = ~out, dmg
            e = bootstrap_cloud(x[keep], z[keep], rec[keep], W)
            f = e.fit
            rows.append(
                {"measure": name, "component": "analysed", "unit": unit, "period_s": period, "damage": damage,
                 "median": f.median, "beta": f.beta, "median_ci95": e.median_ci95, "beta_ci95": e.beta_ci95,
                 "estimable": f.estimable, "note": f.note}
            )  # fmt: skip
    return rows


def _mce_row(
    classified: pd.DataFrame,
    lv: np.ndarray,
    settings: Settings,
    k: int,
    iso: Mapping[str, Any],
    rindex: Mapping[str, int],
    W: np.ndarray,
) -> dict[str, Any]:
    """The displacement check at the MCE level of design level ``k``: the codes' statistic with its
    bootstrap interval and, times ``gamma_x``, against the capacity; the same for the
    ``disp_fractile`` fractile of the records' peaks; the probability of exceeding the capacity
    (``gamma_x d > capacity``) with its exact interval, and the runs that overturned (their peak is a
    lower bound)."""
    if k >= len(settings.mce):
        return {"mce_g": None}
    x = settings.mce[k]
    at = classified[np.isclose(lv, x, rtol=1e-12)]
    d = at["max_base_disp_m"].to_numpy(dtype=float)
    stat, how = displacement_statistic(d)
    # the order statistic at or above the fractile (no interpolation): with 18 records and 0.9, the 17th
    # of 18, so that the check fails whenever more than 10 % of the records are beyond the capacity
    frac = float(np.quantile(d, settings.disp_fractile, method="higher")) if d.size else math.nan
    gx = settings.gamma_x
    cap_given = settings.capacity_m
    cap = settings.capacity_factored_m
    fixed = iso.get("isolation", "") == "none"
    n_ov = int(at["overturn"].sum()) if len(at) else 0
    within_stat = bool(cap_given is None or (math.isfinite(stat) and gx * stat <= cap_given))
    within_frac = bool(cap_given is None or (math.isfinite(frac) and gx * frac <= cap_given))
    row: dict[str, Any] = {
        "mce_g": float(x),
        "mce_basis": settings.mce_basis[k] if k < len(settings.mce_basis) else "",
        "disp_mce_m": 0.0 if fixed else stat,
        "disp_mce_ci95_m": None if fixed else _statistic_ci(at, d, rindex, W),
        "disp_mce_statistic": "fixed base" if fixed else how,
        "disp_mce_p84_m": float(np.percentile(d, 84.0)) if d.size else math.nan,
        "gamma_x": gx,
        "disp_mce_factored_m": 0.0 if fixed else gx * stat,
        "disp_fractile": settings.disp_fractile,
        "disp_mce_fractile_m": 0.0 if fixed else frac,
        "disp_mce_fractile_factored_m": 0.0 if fixed else gx * frac,
        "mce_statistic_within_capacity": bool(fixed or within_stat),
        "mce_fractile_within_capacity": bool(fixed or within_frac),
        "n_mce_records": int(d.size),
        "mce_within_capacity": bool(fixed or (within_stat and within_frac)),
        "n_mce_overturn": n_ov,
        "n_mce_outside_model": int(at["outside_model"].sum()) if len(at) else 0,
        "n_mce_slides_beyond": int(at["slides_beyond"].sum()) if len(at) else 0,
        "disp_mce_overturned": (
            f"{n_ov} of {d.size} runs at the MCE overturn the object: each enters with the peak reached "
            "before the overturn, a lower bound"
            if n_ov and not fixed
            else ""
        ),
    }
    row.update(_exceedance(d, cap, iso, "mce_"))
    if iso.get("isolation") == "fp" and iso.get("mu_b") is not None and iso.get("R_b_m") is not None:
        mu, rb = float(iso["mu_b"]), float(iso["R_b_m"])
        row["residual_max_m"] = mu * rb
        row["recentring_ok"] = bool(math.isfinite(stat) and stat / (2.0 * rb) >= RESTORING_MARGIN)
        row["fp_period_s"] = 2.0 * math.pi * math.sqrt(rb / G)
    return row


def _failure_bounded(
    fail: FragilityEstimate, over: FragilityEstimate, x: float
) -> tuple[float, list[float], np.ndarray]:
    """P(failure) at ``x`` bounded by its part, overturning, both fitted: ``max(P(failure), P(overturn))``
    for the fit of all the data and for every resample (two separate fits need not say that failure,
    which includes overturning, is at least as likely). Returns (estimate, 95 % interval, resamples)."""
    p = max(float(fail.fit.probability(x)), float(over.fit.probability(x)))
    bs = np.maximum(fail.resampled_probability(x), over.resampled_probability(x))
    return p, [float(v) for v in np.percentile(bs, [2.5, 97.5])], bs


def _failure_at_mce(
    classified: pd.DataFrame,
    lv: np.ndarray,
    settings: Settings,
    k: int,
    fail: FragilityEstimate,
    over: FragilityEstimate,
    n_records: int,
) -> dict[str, Any]:
    """P(failure) at the MCE level of design level ``k``, the collapse check: fitted (at least
    P(overturn), with its bootstrap interval) where the failure fragility is estimable, the MCE lies
    within the stripes and at least :data:`MIN_RECORDS` records are analysed; else the observed
    fraction ``k/n`` of the runs at the MCE with its exact interval. What was observed there is given
    beside it in both cases."""
    if k >= len(settings.mce):
        return {"p_failure_mce": None, "p_failure_mce_ci95": None, "p_failure_mce_basis": ""}
    x = settings.mce[k]
    at = classified[np.isclose(lv, x, rtol=1e-12)]
    z, n = _observed(at, "failure", settings.outside_model)
    st = settings.stripes
    row: dict[str, Any] = {
        "n_failure_mce_observed": z,
        "n_failure_mce_counted": n,
        "p_failure_mce_observed": (z / n) if n else None,
        "p_failure_mce_observed_ci95": list(clopper_pearson(z, n)) if n else None,
        "p_failure_mce_upper95": clopper_pearson(z, n, side="upper")[1] if n else None,
    }
    inside = bool(st) and min(st) * (1 - 1e-9) <= x <= max(st) * (1 + 1e-9)
    if fail.fit.estimable and inside and n_records >= MIN_RECORDS:
        ci: list[float] | None
        if over.fit.estimable and fail.n_boot:
            p, ci, _ = _failure_bounded(fail, over, x)
        else:
            p, ci = float(fail.fit.probability(x)), fail.probability_ci95(x)
            if over.fit.estimable:
                p = max(p, float(over.fit.probability(x)))
        row.update(p_failure_mce=p, p_failure_mce_ci95=ci, p_failure_mce_basis="fitted")
    else:
        why = (
            f"fewer than {MIN_RECORDS} records"
            if n_records < MIN_RECORDS
            else (
                "the MCE lies outside the stripes" if not inside else "no failure fragility could be fitted"
            )
        )
        row.update(
            p_failure_mce=row["p_failure_mce_observed"],
            p_failure_mce_ci95=row["p_failure_mce_observed_ci95"],
            p_failure_mce_basis=f"observed ({why})",
        )
    return row


def _statistic_ci(
    at: pd.DataFrame, d: np.ndarray, rindex: Mapping[str, int], W: np.ndarray
) -> list[float] | None:
    """95 % percentile interval of the codes' displacement statistic over the resamples of the records
    (the mean of the drawn records' peaks, or their maximum with fewer than :data:`MIN_RECORDS`)."""
    if W.shape[0] == 0 or d.size == 0:
        return None
    idx = np.array([rindex.get(r, -1) for r in at["record"]])
    keep = idx >= 0
    w = W[:, idx[keep]]
    dd = d[keep]
    if dd.size >= MIN_RECORDS:
        tot = w.sum(1)
        vals = np.where(tot > 0, (w @ dd) / np.where(tot > 0, tot, 1.0), np.nan)
    else:
        vals = np.where(w > 0, dd[None, :], -np.inf).max(1)
    vals = vals[np.isfinite(vals)]
    if not vals.size:
        return None
    lo, hi = np.percentile(vals, [2.5, 97.5])
    return [float(lo), float(hi)]
