"""The isolation design search: is the object safe, and which base makes it so, by paired evidence.

The candidates are the fixed base (no isolation: the *floor* every recommendation is compared with),
the isolation cases of the configuration and the isolators of the design grid. Each is assessed like a
case (:func:`isorock.assessment.case.evaluate`: its runs on every record at the stripes, the design and
the MCE levels), all of them on **the same records and the same bootstrap resamples** of them. At each
design level:

1. **Adequacy** (:mod:`isorock.assessment.target`): every base is judged against the stated target
   (by default P(failure) at the MCE at most 10 %): ``adequate`` True (its estimate meets it), False
   (even the lower end of its 95 % interval misses it) or None (not shown). An isolator whose
   displacement at the MCE, times ``gamma_x``, exceeds the capacity by the codes' statistic
   (:func:`~isorock.assessment.case.displacement_statistic`) or by the stated fractile of the
   records is not *eligible*, and not adequate;
2. the **metric** that ranks the eligible bases is the mean annual frequency of failure with a hazard
   curve, else the probability of failure at the design level: fitted where a fragility can be
   fitted, else the fraction observed at that level;
3. **paired comparisons** (:mod:`isorock.assessment.paired`): every candidate is compared with the
   floor on the same resamples, on the same footing (``basis``: both fitted, else both observed); the
   test of "better" is a studentised bootstrap, corrected for the search by Westfall and Young's
   max-T over every isolator assessed (``vs_floor.p_adjusted``). With fewer than
   :data:`~isorock.assessment.case.MIN_RECORDS` records, or no failure observed on either side, the
   comparison rests on exact bounds instead (the exact 95 % intervals must separate);
4. the **verdict** (:data:`VERDICTS`):

   * ``isolate``: an eligible isolator meets the target and fails less than the fixed base by the
     familywise test (at :data:`P_DECIDE`); the recommendation is the one of lowest estimate among
     them, unless a simpler one (a shorter period) is shown **equivalent** to it by two one-sided tests
     within ``equivalence_margin`` times the fixed base's estimate ("cannot be told apart" is never
     equivalence);
   * ``fixed_base``: the fixed base meets the target and no isolator that does is shown better;
   * ``restrain``: every base assessed is clearly not adequate (restrain, relocate or redesign the
     mounting); the base closest to the target is named (``closest``);
   * ``inconclusive``: none of these; what would decide it is said (:func:`records_to_decide`).

   A recommendation is never worse than the floor by its estimate;
5. an optimum on the edge of the grid (:func:`grid_edges`) makes the workflow extend the grid in that
   direction up to the bounds (:func:`extend_axis`, ``isorock.pipeline.design_extend``).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from isorock.assessment.case import MIN_RECORDS, CaseEvaluation, Settings, evaluate
from isorock.assessment.paired import ALPHA, equivalent, familywise, paired, records_to_decide
from isorock.assessment.target import judge
from isorock.constants import G
from isorock.parallel import fork_map

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

#: the confidence of every decision: 1 - ALPHA (the familywise test of "better", each side of an
#: equivalence)
P_DECIDE = 1.0 - ALPHA
#: the verdicts of a design level
VERDICTS = ("isolate", "fixed_base", "restrain", "inconclusive")
#: default bounds of a design grid's extension, per parameter [s, -, -, m] (a user sets what the
#: supplier makes: ``design_grid.bounds``); where each comes from: docs/assessment.md, section 6
GRID_BOUNDS: dict[str, tuple[float, float]] = {
    "Tb_s": (1.0, 6.0),
    "xi_b": (0.02, 0.3),
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
    """The candidate columns of an isolation object (:mod:`isorock.physics.model`): ``isolation`` (none,
    linear,
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


def evaluate_candidates(
    candidates: Sequence[Candidate],
    settings: Settings,
    cache: dict[tuple, Any] | None = None,
    workers: int = 1,
) -> None:
    """Assess every candidate (fills ``evaluation``) on the same records, in the same order, so that
    all of them see the same bootstrap resamples.

    Parameters
    ----------
    candidates : sequence of Candidate
        The bases compared.
    settings : Settings
        The assessment's settings.
    cache : dict, optional
        Evaluations already made, kept between calls of one search (the rounds of
        :func:`isorock.jobs.design.design_extend`): a candidate of the same kind, parameters
        and runs (the same table object) on the same records gets the evaluation made before (the same
        numbers: :func:`~isorock.assessment.case.evaluate` depends on nothing else); the others are
        evaluated and added.
    workers : int
        Processes that evaluate the candidates at once (:func:`isorock.parallel.fork_map`: the same
        numbers as one).
    """
    records = sorted({r for c in candidates for r in c.runs["record"].unique()})
    todo: list[tuple[Candidate, tuple]] = []
    for c in candidates:
        key = (c.source, json.dumps(c.params, sort_keys=True), id(c.runs), len(c.runs), tuple(records))
        if cache is not None and key in cache:
            c.evaluation = cache[key]
        else:
            todo.append((c, key))

    def one(c: Candidate) -> CaseEvaluation:
        return evaluate(c.runs, settings, c.params, records=records, measures=False)

    if workers > 1 and len(todo) > 1:
        import scipy.stats  # noqa: F401  the exact intervals' module: once here, not in every worker

    for (c, key), ev in zip(todo, fork_map(one, [c for c, _ in todo], workers), strict=True):
        c.evaluation = ev
        if cache is not None:
            cache[key] = ev


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
    """:func:`paired` of two candidate rows on a common footing: fitted where both are, else observed;
    the resampled differences are kept under ``_d`` (for the familywise and equivalence tests)."""
    basis = "fitted" if a["fitted"] and b["fitted"] else "observed"
    ea, _, _, sa = _metric(a["_c"], k, by_rate, basis)
    eb, _, _, sb = _metric(b["_c"], k, by_rate, basis)
    d = sa - sb if sa.size and sa.size == sb.size else np.zeros(0)
    return {**paired(ea, sa, eb, sb), "basis": basis, "_d": d}


def _adequacy(r: dict[str, Any], lvl: Mapping[str, Any], ev: CaseEvaluation, settings: Settings) -> None:
    """The adequacy of a candidate row against the target (:func:`~isorock.assessment.target.judge`):
    ``target_estimate`` and its ``_ci95`` in the target's measure, ``target_basis`` (what it rests on),
    ``adequate`` (True, False, None); an isolator beyond its capacity at the MCE is not adequate. With
    fewer than :data:`MIN_RECORDS` records (exact bounds) a base is adequate only when the upper end of
    its exact interval meets the target (else None: not shown)."""
    t = settings.target
    exact = ev.n_records < MIN_RECORDS
    if t.kind == "p_mce":
        est, ci, basis = (
            lvl.get("p_failure_mce"),
            lvl.get("p_failure_mce_ci95"),
            lvl.get("p_failure_mce_basis"),
        )
    elif ev.hazard is not None:
        h = ev.hazard["failure"]
        ci = h["annual_rate_exact_ci95"] if exact else h["annual_rate_ci95"]
        est, basis = (
            h["annual_rate"],
            h["method"] + (" (exact bounds: fewer records than 7)" if exact else ""),
        )
        if t.kind == "p_50yr":
            from isorock.assessment.hazard import probability_in

            est = probability_in(est, 50.0)
            ci = None if ci is None else [probability_in(ci[0]), probability_in(ci[1])]
    else:
        est, ci, basis = None, None, "no hazard curve"
    r["target_estimate"] = est
    r["target_estimate_ci95"] = ci
    r["target_basis"] = basis or ""
    r["adequate"] = judge(est, ci, t.value)
    r["adequacy_note"] = ""
    if exact and r["adequate"] is True and ci is not None and ci[1] > t.value:
        # a handful of records: an estimate that meets the target says little (0 of 1 records is
        # "0 %", its exact interval 0 % to 98 %); with fewer than MIN_RECORDS records a base is shown
        # safe only when the upper end of its exact interval meets the target
        r["adequate"] = None
    if r["isolation"] != "none" and not r["within_capacity"]:
        r["adequate"] = False
        r["adequacy_note"] = "beyond the displacement capacity at the MCE"


def _exact_better(a: Mapping[str, Any], b: Mapping[str, Any]) -> bool:
    """``a`` fails less than ``b`` by exact bounds: the upper end of ``a``'s exact 95 % interval below
    the lower end of ``b``'s (the counts at the design level, or the risk integrals of the stripes'
    Clopper-Pearson bounds)."""
    ca, cb = a.get("_exact_ci"), b.get("_exact_ci")
    return bool(ca is not None and cb is not None and ca[1] < cb[0])


def _exact_ci(c: Candidate, k: int, by_rate: bool) -> list[float] | None:
    ev = c.evaluation
    assert ev is not None
    if by_rate and ev.hazard is not None:
        return ev.hazard["failure"]["annual_rate_exact_ci95"]
    return ev.levels[k].get("p_failure_observed_ci95")


def _none_observed(c: Candidate, k: int, by_rate: bool) -> bool:
    """No failure observed where the metric looks: at the design level, or at any stripe (by rate)."""
    ev = c.evaluation
    assert ev is not None
    if by_rate and ev.hazard is not None:
        return int(ev.hazard["failure"].get("n_damaged_stripes", 1)) == 0
    return not ev.levels[k].get("n_failure_observed")


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
        "n_overturn_observed": lvl.get("n_overturn_observed"),
        "p_failure_bounded_by_overturn": lvl.get("p_failure_bounded_by_overturn", False),
        "estimable": lvl["estimable"],
        "annual_rate_failure": None if ev.hazard is None else ev.hazard["failure"]["annual_rate"],
        "annual_rate_failure_bounds": None
        if ev.hazard is None
        else ev.hazard["failure"]["annual_rate_bounds"],
        "p50_failure": None if ev.hazard is None else ev.hazard["failure"]["p50"],
        "p50_failure_ci95": None if ev.hazard is None else ev.hazard["failure"]["p50_ci95"],
        "deaggregation": None if ev.hazard is None else ev.hazard["failure"]["deaggregation"],
        "mce_g": lvl.get("mce_g"),
        "disp_mce_m": lvl.get("disp_mce_m"),
        "disp_mce_ci95_m": lvl.get("disp_mce_ci95_m"),
        "disp_mce_statistic": lvl.get("disp_mce_statistic"),
        "n_mce_records": lvl.get("n_mce_records"),
        "n_mce_exceed_capacity": lvl.get("n_mce_exceed_capacity"),
        "p_mce_exceed_capacity": lvl.get("p_mce_exceed_capacity"),
        "p_mce_exceed_capacity_ci95": lvl.get("p_mce_exceed_capacity_ci95"),
        "n_mce_overturn": lvl.get("n_mce_overturn"),
        "n_mce_outside_model": lvl.get("n_mce_outside_model"),
        "n_mce_slides_beyond": lvl.get("n_mce_slides_beyond"),
        "gamma_x": lvl.get("gamma_x"),
        "disp_mce_factored_m": lvl.get("disp_mce_factored_m"),
        "disp_fractile": lvl.get("disp_fractile"),
        "disp_mce_fractile_m": lvl.get("disp_mce_fractile_m"),
        "disp_mce_fractile_factored_m": lvl.get("disp_mce_fractile_factored_m"),
        "mce_statistic_within_capacity": lvl.get("mce_statistic_within_capacity"),
        "mce_fractile_within_capacity": lvl.get("mce_fractile_within_capacity"),
        "p_failure_mce": lvl.get("p_failure_mce"),
        "p_failure_mce_ci95": lvl.get("p_failure_mce_ci95"),
        "p_failure_mce_basis": lvl.get("p_failure_mce_basis"),
        "n_failure_mce_observed": lvl.get("n_failure_mce_observed"),
        "n_failure_mce_counted": lvl.get("n_failure_mce_counted"),
        "p_failure_mce_upper95": lvl.get("p_failure_mce_upper95"),
        "within_capacity": bool(lvl.get("mce_within_capacity", True)),
        "residual_max_m": lvl.get("residual_max_m"),
        "recentring_ok": lvl.get("recentring_ok"),
        "on_edge": c.on_edge,
        "_c": c,
    }


def _tests(
    rows: list[dict[str, Any]], floor: dict[str, Any] | None, assessed: list[dict[str, Any]], n_rec: int
) -> int:
    """The familywise test of every eligible isolator against the fixed base, on the same resamples
    (``vs_floor.p_adjusted``, ``n_family``, ``decided_by``), and ``beats_floor`` of every row: by that
    test, or by exact bounds with fewer than :data:`MIN_RECORDS` records or no failure observed on
    either side. Returns the size of the family."""
    # the family: every isolator the search could recommend (within the capacity at the MCE, with an
    # estimate); one beyond the capacity is never chosen, whatever its test says
    family = [r for r in assessed if r["vs_floor"] is not None and r["eligible"]]
    padj = familywise([r["vs_floor"]["difference"] for r in family], [r["vs_floor"]["_d"] for r in family])
    n_family = sum(p is not None for p in padj)
    for r, p in zip(family, padj, strict=True):
        r["vs_floor"]["p_adjusted"] = p
    for r in rows:
        vs = r["vs_floor"]
        # exact bounds where the resamples cannot decide: few records, no failure on either side, or
        # a difference with no spread at all (every resample the same: outcomes separated by the bases)
        flat = bool(
            vs is not None
            and vs.get("p_single") is None
            and math.isfinite(vs["difference"])
            and vs["difference"] != 0
        )
        exact = bool(n_rec < MIN_RECORDS or (floor is not None and r["_none"] and floor["_none"]) or flat)
        if vs is not None and r is not floor:
            vs["decided_by"] = "exact bounds" if exact else "bootstrap"
            vs.setdefault("p_adjusted", None)
            vs["n_family"] = n_family
        shown = (
            _exact_better(r, floor)
            if exact and floor is not None
            else bool(vs is not None and vs.get("p_adjusted") is not None and vs["p_adjusted"] <= ALPHA)
        )
        r["beats_floor"] = bool(
            floor is not None
            and r is not floor
            and r["eligible"]
            and r["estimate"] < floor["estimate"]
            and (vs or {}).get("difference", math.nan) < 0
            and shown
        )
    return n_family


def rank(candidates: Sequence[Candidate], settings: Settings) -> list[dict[str, Any]]:
    """Per design level: every candidate's row with its adequacy and paired comparisons, the verdict,
    the recommendation and the edge of the grid (see the module docstring).

    Returns
    -------
    list of dict
        One per design level: ``design_g``, ``ranked_by``, ``n_records``, ``verdict``, ``reason`` (why,
        in words), ``target`` (:meth:`~isorock.assessment.target.Target.to_dict`), ``decided_by``
        (``bootstrap``: the familywise test on the resamples; ``exact bounds``: fewer than 7 records or
        no failure observed on either side), ``candidates`` (rows sorted by the estimate, each with
        ``rank`` (0: not eligible), ``eligible``, ``adequate``, ``target_estimate``, ``vs_floor`` and
        ``vs_best`` (:func:`paired`; ``vs_floor`` with ``p_adjusted``, the familywise p-value),
        ``beats_floor``, ``equivalent``), ``recommended`` (a row; None unless isolate or fixed_base),
        ``best`` (the eligible isolator of lowest estimate), ``floor``, ``closest`` (the base nearest
        the target, within the capacity where one is), ``equivalent`` (names of the isolators shown
        equivalent to the recommended one), ``edge_of_grid``, ``edges``, ``records_to_decide``
        (inconclusive: about how many records would decide, or None), ``beats_floor``, ``n_family``
        (isolators in the familywise test), ``equivalence_margin`` (absolute, in the metric's unit).
    """
    by_rate = settings.hazard is not None
    out = []
    for k, x in enumerate(settings.design):
        rows = [_row(c, k, by_rate) for c in candidates]
        floor = next((r for r in rows if r["source"] == "floor"), None)
        ev0 = candidates[0].evaluation if candidates else None
        n_rec = 0 if ev0 is None else len(ev0.records)
        for r, c in zip(rows, candidates, strict=True):
            assert c.evaluation is not None
            r["eligible"] = bool(r["within_capacity"] and math.isfinite(r["estimate"]))
            _adequacy(r, c.evaluation.levels[k], c.evaluation, settings)
            r["_exact_ci"] = _exact_ci(c, k, by_rate)
            r["_none"] = _none_observed(c, k, by_rate)
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
        assessed = [r for r in rows if r["isolation"] != "none"]
        n_family = _tests(rows, floor, assessed, n_rec)
        margin = settings.equivalence_margin * (floor["estimate"] if floor is not None else math.nan)
        verdict, reason, rec, closest = _verdict(floor, assessed, isolators, settings, (k, by_rate))
        for r in rows:
            vr = r.get("vs_rec")
            r["equivalent"] = bool(
                rec is not None
                and rec["isolation"] != "none"
                and (r is rec or (vr is not None and equivalent(vr["difference"], vr["_d"], margin)))
            )
        to_decide = None
        if verdict == "inconclusive" and best is not None and floor is not None and best["vs_floor"]["n"]:
            to_decide = records_to_decide(n_rec, best["vs_floor"]["difference"], best["vs_floor"]["_d"])
        # the ends of the grid towards the best eligible isolator; with none eligible, towards the best
        # estimate of all (beyond an end of the grid may lie isolators within the capacity)
        grid_rows = [r for r in eligible if r["source"] == "grid"] or [
            r for r in rows if r["source"] == "grid" and math.isfinite(r["estimate"])
        ]
        edges = grid_edges([r["_c"] for r in grid_rows], [r["estimate"] for r in grid_rows])
        for r in rows:
            r["recommended"] = rec is not None and r is rec
        shown = rec if rec is not None and rec is not floor else best
        decided = str(((shown or {}).get("vs_floor") or {}).get("decided_by") or "bootstrap")
        if n_rec < MIN_RECORDS:
            decided = "exact bounds"
        cleaned = []
        for r in rows:
            for key in ("_c", "_exact_ci", "_none", "vs_rec"):
                r.pop(key, None)
            for key in ("vs_floor", "vs_best"):
                if r.get(key):
                    r[key].pop("_d", None)
            cleaned.append(r)
        out.append(
            {
                "design_g": float(x),
                "ranked_by": _metric_name(by_rate),
                "n_records": n_rec,
                "verdict": verdict,
                "reason": reason,
                "target": settings.target.to_dict(),
                "decided_by": decided,
                "candidates": sorted(cleaned, key=lambda r: (r["rank"] == 0, r["rank"])),
                "recommended": rec,
                "best": best,
                "floor": floor,
                "closest": closest,
                "equivalent": [r["name"] for r in cleaned if r["equivalent"]],
                "edge_of_grid": bool(edges),
                "edges": edges,
                "records_to_decide": to_decide,
                "beats_floor": bool(rec is not None and rec is not floor),
                "n_family": n_family,
                "equivalence_margin": margin if math.isfinite(margin) else None,
            }
        )
    return out


def _recommend(winners: list[dict[str, Any]], margin: float, k_rate: tuple[int, bool]) -> dict[str, Any]:
    """The winner of lowest estimate, unless a simpler one (a shorter isolation period) is shown
    equivalent to it within ``margin`` by two one-sided tests on the same resamples; each winner gets
    ``vs_rec``, its paired comparison with the chosen one."""
    k, by_rate = k_rate
    top = min(winners, key=lambda r: (r["estimate"], r["period_s"]))
    for r in winners:
        r["vs_rec"] = _compare(r, top, k, by_rate)
    simpler = [
        r
        for r in winners
        if r["period_s"] < top["period_s"]
        and equivalent(r["vs_rec"]["difference"], r["vs_rec"]["_d"], margin)
    ]
    rec = min(simpler, key=lambda r: (r["period_s"], r["estimate"])) if simpler else top
    if rec is not top:
        for r in winners:
            r["vs_rec"] = _compare(r, rec, k, by_rate)
    return rec


def _verdict(
    floor: dict[str, Any] | None,
    assessed: list[dict[str, Any]],
    isolators: list[dict[str, Any]],
    settings: Settings,
    k_rate: tuple[int, bool],
) -> tuple[str, str, dict[str, Any] | None, dict[str, Any] | None]:
    """(verdict, reason in words, recommended row or None, the base closest to the target or None) of
    one design level (``assessed``: every isolator, ``isolators``: the eligible ones)."""
    t = settings.target
    if floor is None:
        return (
            "inconclusive",
            "no fixed-base case was assessed, so nothing can be compared with doing nothing",
            None,
            None,
        )
    bases = [floor, *assessed]
    known = [r for r in bases if r["target_estimate"] is not None and math.isfinite(r["target_estimate"])]
    # the closest base that could be built (within the capacity), else the closest of all
    closest = min(
        [r for r in known if not r["adequacy_note"]] or known,
        key=lambda r: (r["target_estimate"], r["period_s"]),
        default=None,
    )
    if all(r["adequate"] is False for r in bases):
        return (
            "restrain",
            f"no base assessed meets the target ({t.words}): on every one even the lower end of the 95 % "
            "interval misses it, or the isolator is beyond its capacity",
            None,
            closest,
        )
    winners = [r for r in isolators if r["beats_floor"] and r["adequate"] is True]
    if winners:
        rec = _recommend(winners, settings.equivalence_margin * floor["estimate"], k_rate)
        return (
            "isolate",
            f"it meets the target ({t.words}) and fails less than the fixed base by a familywise test over "
            "every isolator assessed",
            rec,
            closest,
        )
    if floor["adequate"] is True:
        if not assessed:
            why = "no isolator was assessed"
        elif not isolators:
            why = "no isolator assessed is within the displacement capacity at the MCE"
        else:
            why = "no isolator that meets the target is shown to fail less (familywise test)"
        return "fixed_base", f"the fixed base meets the target ({t.words}); {why}", floor, closest
    if not assessed:
        return (
            "inconclusive",
            "no isolator was assessed (add isolation cases or a design grid)",
            None,
            closest,
        )
    if settings.n_boot <= 0:
        return "inconclusive", "no bootstrap resamples (bootstrap: 0), so no paired comparison", None, closest
    if not isolators:
        beyond = all(not r["within_capacity"] for r in assessed)
        return (
            "inconclusive",
            ("every isolator assessed is beyond the displacement capacity at the MCE" if beyond
             else "no isolator within the displacement capacity has an estimate")
            + ", and the fixed base's adequacy is not shown",
            None,
            closest,
        )  # fmt: skip
    fl = "clearly misses the target" if floor["adequate"] is False else "is not shown to meet the target"
    good = [r for r in isolators if r["adequate"] is True]
    if good:
        why = "an isolator meets the target but none that does is shown to fail less than the fixed base"
    else:
        why = "no isolator is shown to meet the target"
    return "inconclusive", f"the fixed base {fl} ({t.words}); {why}", None, closest


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
