"""The isolation design search: which base to choose, compared with doing nothing, by paired evidence.

The candidates are the fixed base (no isolation: the *floor* every recommendation is compared with),
the isolation cases of the configuration and the isolators of the design grid. Each is assessed like a
case (:func:`isorock.assessment.case.evaluate`: its runs on every record at the stripes, the design and
the MCE levels), all of them on **the same records and the same bootstrap resamples** of them. At each
design level:

1. a candidate whose displacement at the maximum considered earthquake (the codes' statistic,
   :func:`~isorock.assessment.case.displacement_statistic`) exceeds the capacity is not *eligible*;
2. the metric is the mean annual frequency of failure with a hazard curve, else the probability of
   failure (overturn or displacement beyond the capacity) at the design level: fitted where a
   fragility can be fitted, else the fraction observed at that level; the eligible candidates are
   ranked by its estimate;
3. every candidate is compared with the floor and with the best (the lowest estimate among the
   eligible isolators) **resample by resample** (:func:`paired`): the difference of the metric with
   its 95 % percentile interval, and the share of resamples in which the candidate is better
   (``p_better``) and worse (``p_worse``). Two separate intervals that overlap say nothing about
   their difference; the paired difference uses what the runs hold, that every candidate saw the
   same records. Two candidates are compared on the same footing (``basis``): their fitted
   fragilities where both can be fitted, else both observed fractions at the design level (or the
   risk integrals of both sets of stripe fractions): a fitted probability against a count of zero
   would call the zero better in almost every resample;
4. the **verdict** (:data:`VERDICTS`):

   * ``isolate``: some eligible isolator beats the floor in at least :data:`P_DECIDE` of the
     resamples, with a lower estimate; the recommendation is the simplest (shortest isolation
     period, then the lower estimate) of those that do and that the paired test cannot tell from the
     best (the best is better in fewer than :data:`P_DECIDE` of the resamples);
   * ``fixed_base``: the floor beats every eligible isolator in at least :data:`P_DECIDE` of the
     resamples, or every isolator assessed is beyond the displacement capacity, or no failure at all
     is seen on the floor (no estimate can be below zero);
   * ``inconclusive``: neither (or nothing to compare: no isolator, no estimate, no resamples); what
     would decide it is said (:func:`records_to_decide`).

   Each isolator is tested against the floor on its own: with many candidates one may pass the 95 %
   test by chance, and the best of many estimates is biased low (the grid's neighbours are strongly
   correlated, which limits this; docs/assessment.md says so).

   A recommendation is never worse than the floor by its estimate;
5. an optimum on the edge of the grid (:func:`grid_edges`) makes the workflow extend the grid in that
   direction up to the bounds (:func:`extend_axis`, ``isorock.pipeline.design_extend``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from ..constants import G
from .case import CaseEvaluation, Settings, evaluate

__all__ = [
    "P_DECIDE",
    "VERDICTS",
    "GRID_BOUNDS",
    "Candidate",
    "candidate_params",
    "evaluate_candidates",
    "paired",
    "rank",
    "records_to_decide",
    "grid_axes",
    "grid_edges",
    "extend_axis",
]

#: share of the resamples in which one base must beat another for the difference to count
P_DECIDE = 0.95
#: the verdicts of a design level
VERDICTS = ("isolate", "fixed_base", "inconclusive")
#: default bounds of a design grid's extension, per parameter [s, -, -, m]: a broad range (a user sets
#: what the supplier makes: ``design_grid.bounds``)
GRID_BOUNDS: dict[str, tuple[float, float]] = {
    "Tb_s": (1.0, 6.0),
    "xi_b": (0.02, 0.5),
    "mu_b": (0.02, 0.2),
    "R_b_m": (0.5, 6.0),
}


@dataclass
class Candidate:
    """A base the design search compares.

    Attributes
    ----------
    name : str
        ``none`` for the fixed base, the case name, or ``grid-<k>``.
    source : str
        ``floor``, ``case`` or ``grid``.
    params : dict
        ``isolation`` (none, linear, fp), ``Tb_s``, ``xi_b``, ``mu_b``, ``R_b_m``, ``rho`` (None where
        they do not apply).
    runs : pandas.DataFrame
        Its runs.
    grid_index : tuple of int or None
        Position on the grid's two axes (grid candidates).
    grid_shape : tuple of int or None
        Sizes of the grid's two axes.
    evaluation : CaseEvaluation or None
        Filled by :func:`evaluate_candidates`.
    """

    name: str
    source: str
    params: dict[str, Any]
    runs: pd.DataFrame = field(repr=False)
    grid_index: tuple[int, int] | None = None
    grid_shape: tuple[int, int] | None = None
    evaluation: CaseEvaluation | None = field(default=None, repr=False)

    @property
    def period_s(self) -> float:
        """Isolation period [s] (0 for the fixed base): ``Tb`` (linear), ``2 pi sqrt(R_b / g)`` (FP)."""
        p = self.params
        if p["isolation"] == "none":
            return 0.0
        if p["isolation"] == "fp":
            return 2.0 * math.pi * math.sqrt(float(p["R_b_m"]) / G)
        return float(p["Tb_s"])

    @property
    def on_edge(self) -> bool:
        """A grid isolator at the end of one of the grid's axes (with more than one value)."""
        return bool(self.edge_sides)

    @property
    def edge_sides(self) -> list[tuple[int, str]]:
        """The grid's ends this isolator lies on: ``(axis, "low" | "high")`` for each axis of more than
        one value whose first or last value it has."""
        if self.grid_index is None or self.grid_shape is None:
            return []
        out = []
        for ax, (i, n) in enumerate(zip(self.grid_index, self.grid_shape, strict=True)):
            if n > 1 and i == 0:
                out.append((ax, "low"))
            if n > 1 and i == n - 1:
                out.append((ax, "high"))
        return out


def candidate_params(iso: Any) -> dict[str, Any]:
    """The candidate columns of an isolation object (:mod:`isorock.model`): ``isolation`` (none, linear,
    fp), ``Tb_s`` [s], ``xi_b``, ``mu_b``, ``R_b_m`` [m], ``rho`` (None where they do not apply)."""
    kind = iso.kind
    return {
        "isolation": kind,
        "Tb_s": float(iso.Tb) if kind != "none" else None,
        "xi_b": float(iso.xi_b) if kind == "linear" else None,
        "mu_b": float(iso.mu_b) if kind == "fp" else None,
        "R_b_m": float(iso.R_b) if kind == "fp" else None,
        "rho": float(iso.rho) if kind != "none" else None,
    }


def evaluate_candidates(candidates: Sequence[Candidate], settings: Settings) -> None:
    """Assess every candidate (fills ``evaluation``) on the same records, in the same order, so that
    all of them see the same bootstrap resamples."""
    records = sorted({r for c in candidates for r in c.runs["record"].unique()})
    for c in candidates:
        c.evaluation = evaluate(c.runs, settings, c.params, records=records, measures=False)


def _metric(
    c: Candidate, k: int, by_rate: bool, basis: str | None = None
) -> tuple[float, Any, bool, np.ndarray]:
    """(estimate, 95 % interval, fitted, resampled values) of candidate ``c`` at design level ``k``, on
    ``basis`` ``"fitted"`` or ``"observed"`` (default: fitted where its failure fragility is estimable,
    else observed)."""
    ev = c.evaluation
    assert ev is not None
    smp = ev.samples
    if by_rate and ev.hazard is not None:
        h = ev.hazard["failure"]
        fitted = h["method"] == "fitted fragility"
        if basis == "observed" or (basis is None and not fitted):
            obs = smp.get("annual_rate_failure_observed")
            est = smp.get("annual_rate_failure_observed_est", h["annual_rate"])
            return est, (h["annual_rate_ci95"] if not fitted else None), False, _arr(obs)
        return h["annual_rate"], h["annual_rate_ci95"], True, _arr(smp.get("annual_rate_failure_fitted"))
    row = ev.levels[k]
    fitted = row["p_failure"] is not None
    if basis == "observed" or (basis is None and not fitted):
        obs = row["p_failure_observed"]
        est = math.nan if obs is None else obs
        return est, row["p_failure_observed_ci95"], False, _arr(smp["p_failure_observed"][k])
    return row["p_failure"], row["p_failure_ci95"], True, _arr(smp["p_failure_fitted"][k])


def _arr(v: Any) -> np.ndarray:
    return np.zeros(0) if v is None else np.asarray(v, dtype=float)


def _compare(a: dict[str, Any], b: dict[str, Any], k: int, by_rate: bool) -> dict[str, Any]:
    """:func:`paired` of two candidate rows on a common footing: fitted where both are, else observed."""
    basis = "fitted" if a["fitted"] and b["fitted"] else "observed"
    ea, _, _, sa = _metric(a["_c"], k, by_rate, basis)
    eb, _, _, sb = _metric(b["_c"], k, by_rate, basis)
    return {**paired(ea, sa, eb, sb), "basis": basis}


def paired(est_a: float, samples_a: np.ndarray, est_b: float, samples_b: np.ndarray) -> dict[str, Any]:
    """Candidate ``a`` against ``b`` on the same resamples (lower is better).

    Returns
    -------
    dict
        ``difference`` (``est_a - est_b``), ``difference_ci95`` (2.5th and 97.5th percentiles of the
        resampled differences; None without resamples), ``p_better`` (share of the resamples in which
        ``a`` is lower), ``p_worse`` (higher), ``n`` (resamples compared: those where both are defined).
    """
    a, b = np.asarray(samples_a, dtype=float), np.asarray(samples_b, dtype=float)
    diff = float(est_a - est_b) if math.isfinite(est_a) and math.isfinite(est_b) else math.nan
    ok = (np.isfinite(a) & np.isfinite(b)) if a.size and a.size == b.size else np.zeros(0, dtype=bool)
    if not ok.any():
        return {
            "difference": diff,
            "difference_ci95": None,
            "p_better": math.nan,
            "p_worse": math.nan,
            "n": 0,
        }
    d = a[ok] - b[ok]
    # differences below the floating-point noise of two equal estimates count as ties
    tol = 1e-12 * max(float(np.max(np.abs(a[ok]))), float(np.max(np.abs(b[ok]))), 1e-300)
    lo, hi = np.percentile(d, [2.5, 97.5])
    return {
        "difference": diff,
        "difference_ci95": [float(lo), float(hi)],
        "p_better": float(np.mean(d < -tol)),
        "p_worse": float(np.mean(d > tol)),
        "n": int(d.size),
    }


def records_to_decide(n_records: int, difference: float, samples: np.ndarray | None) -> int | None:
    """About how many records would make a paired difference decisive at :data:`P_DECIDE` (one-sided),
    were it what it is now: the bootstrap spread of the difference shrinks as one over the square root
    of the number of records, so ``n (z sd / |d|)^2`` with ``z`` the normal quantile. None when the
    difference is zero or its spread unknown (more records of the same kind would not separate
    them)."""
    if samples is None or np.asarray(samples).size < 2 or not math.isfinite(difference) or difference == 0:
        return None
    sd = float(np.nanstd(samples))
    if not sd > 0:
        return None
    z = 1.6448536269514722  # the 95 % one-sided normal quantile
    return max(n_records + 1, math.ceil(n_records * (z * sd / abs(difference)) ** 2))


def _row(c: Candidate, k: int, by_rate: bool) -> dict[str, Any]:
    ev = c.evaluation
    assert ev is not None
    lvl = ev.levels[k]
    est, ci, fitted, _ = _metric(c, k, by_rate)
    return {
        "name": c.name,
        "source": c.source,
        **c.params,
        "period_s": c.period_s,
        "estimate": est,
        "estimate_ci95": ci,
        "fitted": fitted,
        "estimate_observed": _metric(c, k, by_rate, "observed")[0],
        "p_failure": lvl["p_failure"],
        "p_failure_ci95": lvl["p_failure_ci95"],
        "p_failure_observed": lvl["p_failure_observed"],
        "p_failure_observed_ci95": lvl["p_failure_observed_ci95"],
        "p_failure_upper95": lvl["p_failure_upper95"],
        "n_failure_observed": lvl["n_failure_observed"],
        "n_failure_counted": lvl["n_failure_counted"],
        "p_overturn": lvl["p_overturn"],
        "estimable": lvl["estimable"],
        "annual_rate_failure": None if ev.hazard is None else ev.hazard["failure"]["annual_rate"],
        "annual_rate_failure_bounds": None
        if ev.hazard is None
        else ev.hazard["failure"]["annual_rate_bounds"],
        "mce_g": lvl.get("mce_g"),
        "disp_mce_m": lvl.get("disp_mce_m"),
        "disp_mce_ci95_m": lvl.get("disp_mce_ci95_m"),
        "disp_mce_statistic": lvl.get("disp_mce_statistic"),
        "n_mce_records": lvl.get("n_mce_records"),
        "n_mce_exceed_capacity": lvl.get("n_mce_exceed_capacity"),
        "p_mce_exceed_capacity": lvl.get("p_mce_exceed_capacity"),
        "p_mce_exceed_capacity_ci95": lvl.get("p_mce_exceed_capacity_ci95"),
        "n_mce_overturn": lvl.get("n_mce_overturn"),
        "n_mce_slides_beyond": lvl.get("n_mce_slides_beyond"),
        "within_capacity": bool(lvl.get("mce_within_capacity", True)),
        "residual_max_m": lvl.get("residual_max_m"),
        "recentring_ok": lvl.get("recentring_ok"),
        "on_edge": c.on_edge,
        "_c": c,
    }


def rank(candidates: Sequence[Candidate], settings: Settings) -> list[dict[str, Any]]:
    """Per design level: every candidate's row with its paired comparisons, the verdict, the
    recommendation and the edge of the grid (see the module docstring).

    Returns
    -------
    list of dict
        One per design level: ``design_g``, ``ranked_by``, ``n_records``, ``verdict``, ``reason`` (why,
        in words), ``candidates`` (rows sorted by the estimate, each with ``rank`` (0: not eligible),
        ``eligible``, ``vs_floor`` and ``vs_best`` (:func:`paired`), ``beats_floor``, ``equivalent``),
        ``recommended`` (a row; None when inconclusive), ``best`` (the eligible isolator of lowest
        estimate), ``floor``, ``equivalent`` (names of the candidates the paired test cannot tell from
        the best), ``edge_of_grid``, ``edges`` (the grid ends the best grid isolator lies on),
        ``records_to_decide`` (inconclusive: about how many records would decide, or None),
        ``beats_floor``.
    """
    by_rate = settings.hazard is not None
    out = []
    for k, x in enumerate(settings.design):
        rows = [_row(c, k, by_rate) for c in candidates]
        floor = next((r for r in rows if r["source"] == "floor"), None)
        for r in rows:
            r["eligible"] = bool(r["within_capacity"] and math.isfinite(r["estimate"]))
        eligible = [r for r in rows if r["eligible"]]
        eligible.sort(key=lambda r: (r["estimate"], (r["estimate_ci95"] or [0, math.inf])[1], r["period_s"]))
        for r in rows:
            r["rank"] = 0
        for i, r in enumerate(eligible, start=1):
            r["rank"] = i
        isolators = [r for r in eligible if r["isolation"] != "none"]
        best = isolators[0] if isolators else None
        for r in rows:
            r["vs_floor"] = _compare(r, floor, k, by_rate) if floor else None
            r["vs_best"] = _compare(r, best, k, by_rate) if best else None
            r["beats_floor"] = bool(
                floor is not None
                and r is not floor
                and r["eligible"]
                and r["estimate"] < floor["estimate"]
                and r["vs_floor"]["difference"] < 0
                and r["vs_floor"]["p_better"] >= P_DECIDE
            )
            r["equivalent"] = bool(
                best is not None
                and r["eligible"]
                and r["isolation"] != "none"
                and (r is best or not r["vs_best"]["p_worse"] >= P_DECIDE)
            )
        assessed = [r for r in rows if r["isolation"] != "none"]
        verdict, reason, rec = _verdict(floor, assessed, isolators, settings.n_boot)
        ev0 = candidates[0].evaluation if candidates else None
        n_rec = 0 if ev0 is None else len(ev0.records)
        to_decide = None
        if verdict == "inconclusive" and best is not None and floor is not None and best["vs_floor"]["n"]:
            basis = best["vs_floor"]["basis"]
            sb, sf = _metric(best["_c"], k, by_rate, basis)[3], _metric(floor["_c"], k, by_rate, basis)[3]
            to_decide = records_to_decide(n_rec, best["vs_floor"]["difference"], sb - sf)
        grid_rows = [r for r in eligible if r["source"] == "grid"]
        edges = grid_edges([r["_c"] for r in grid_rows], [r["estimate"] for r in grid_rows])
        for r in rows:
            r["recommended"] = rec is not None and r is rec
        cleaned = []
        for r in rows:
            r.pop("_c")
            cleaned.append(r)
        out.append(
            {
                "design_g": float(x),
                "ranked_by": _metric_name(by_rate),
                "n_records": n_rec,
                "verdict": verdict,
                "reason": reason,
                "candidates": sorted(cleaned, key=lambda r: (r["rank"] == 0, r["rank"])),
                "recommended": rec,
                "best": best,
                "floor": floor,
                "equivalent": [r["name"] for r in cleaned if r["equivalent"]],
                "edge_of_grid": bool(edges),
                "edges": edges,
                "records_to_decide": to_decide,
                "beats_floor": bool(rec is not None and rec is not floor),
            }
        )
    return out


def _verdict(
    floor: dict[str, Any] | None,
    assessed: list[dict[str, Any]],
    isolators: list[dict[str, Any]],
    n_boot: int,
) -> tuple[str, str, dict[str, Any] | None]:
    """(verdict, reason in words, recommended row or None) of one design level (``assessed``: every
    isolator, ``isolators``: the eligible ones)."""
    if floor is None:
        return (
            "inconclusive",
            "no fixed-base case was assessed, so nothing can be compared with doing nothing",
            None,
        )
    if not assessed:
        return "inconclusive", "no isolator was assessed (add isolation cases or a design grid)", None
    if not isolators:
        if all(not r["within_capacity"] for r in assessed):
            return (
                "fixed_base",
                "every isolator assessed is beyond the displacement capacity at the MCE",
                floor,
            )
        return "inconclusive", "no isolator has an estimate (its runs are outside the model)", None
    if floor["estimate"] == 0.0:
        return "fixed_base", "no failure is seen on the fixed base, so no isolator can do better", floor
    if n_boot <= 0 or not any(r["vs_floor"]["n"] for r in isolators):
        return "inconclusive", "no bootstrap resamples (bootstrap: 0), so no paired comparison", None
    winners = [r for r in isolators if r["beats_floor"]]
    if winners:
        same = [r for r in winners if r["equivalent"]] or [min(winners, key=lambda r: r["estimate"])]
        rec = min(same, key=lambda r: (r["period_s"], r["estimate"]))
        return "isolate", f"it beats the fixed base in at least {100 * P_DECIDE:.0f} % of the resamples", rec
    if all(r["vs_floor"]["p_worse"] >= P_DECIDE for r in isolators):
        return (
            "fixed_base",
            f"the fixed base beats every eligible isolator in at least {100 * P_DECIDE:.0f} % of the "
            "resamples",
            floor,
        )
    return (
        "inconclusive",
        f"neither the best isolator nor the fixed base is better in {100 * P_DECIDE:.0f} % of the resamples",
        None,
    )


def _metric_name(by_rate: bool) -> str:
    return (
        "annual frequency of failure (the site's hazard)"
        if by_rate
        else "probability of failure at the design level"
    )


def grid_axes(grid: Mapping[str, Any]) -> tuple[str, str]:
    """The two axes of a design grid: (Tb_s, xi_b) or (mu_b, R_b_m)."""
    return ("Tb_s", "xi_b") if grid["kind"] == "linear" else ("mu_b", "R_b_m")


def grid_edges(grid: Sequence[Candidate], estimates: Sequence[float]) -> list[tuple[int, str]]:
    """The grid ends to search beyond: those of the best grid isolators (the lowest estimate), when
    every one of them lies on an end of the grid (an interior optimum needs no extension) and the best
    estimate is above zero (nothing beats zero).

    Returns
    -------
    list of (axis, side)
        ``axis`` 0 or 1 (:func:`grid_axes`), ``side`` ``"low"`` or ``"high"``; empty: settled.
    """
    est = np.asarray(estimates, dtype=float)
    if not len(grid) or not np.isfinite(est).any():
        return []
    m = float(np.nanmin(est))
    if m <= 0.0:
        return []
    tied = [c for c, e in zip(grid, est, strict=True) if math.isfinite(e) and e <= m * (1 + 1e-12)]
    if any(not c.edge_sides for c in tied):
        return []
    return sorted({s for c in tied for s in c.edge_sides})


def extend_axis(values: Sequence[float], side: str, bound: float, spacing: str = "linear") -> float | None:
    """The next value of a grid axis beyond its ``side`` end, one step of the grid's own spacing
    (``linear``: the difference of the two end values; ``log``: their ratio), not beyond ``bound``;
    None when the end is at the bound already (or the axis has a single value)."""
    v = sorted(float(x) for x in values)
    if len(v) < 2:
        return None
    if side == "high":
        end, prev = v[-1], v[-2]
        nxt = end * (end / prev) if spacing == "log" else end + (end - prev)
        if end >= bound * (1 - 1e-9):
            return None
        return float(f"{min(nxt, bound):.10g}")  # 0.15 + 0.05 is 0.2, not 0.19999999999999998
    end, prev = v[0], v[1]
    nxt = end * (end / prev) if spacing == "log" else end - (prev - end)
    if end <= bound * (1 + 1e-9):
        return None
    return float(f"{max(nxt, bound):.10g}")
