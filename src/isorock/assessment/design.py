"""The isolation design search: which base to choose, compared with doing nothing.

The candidates are the fixed base (no isolation: the floor every recommendation is compared with), the
isolation cases of the configuration and the isolators of the design grid. Each is assessed like a
case (:func:`isorock.assessment.case.evaluate`: its runs on every record at the stripes, the design and
the MCE levels), and at each design level:

1. a candidate whose displacement at the maximum considered earthquake (the codes' statistic,
   :func:`~isorock.assessment.case.displacement_statistic`) exceeds the capacity is not eligible;
2. the eligible ones are ranked by the mean annual frequency of failure with a hazard curve, else by
   the probability of failure (overturn or displacement beyond the capacity) at the design level:
   fitted where a fragility can be fitted, else the fraction observed at that level;
3. the candidates whose 95 % interval overlaps the best one's are *equivalent* to it, and of those the
   simplest is recommended: no isolation, then the shorter isolation period (the smaller isolator),
   then the lower estimate;
4. an optimum on the edge of the grid (the best grid isolator at the end of an axis) is flagged: the
   grid should be extended.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import pandas as pd

from ..constants import G
from .case import CaseEvaluation, Settings, evaluate

__all__ = ["Candidate", "evaluate_candidates", "rank"]


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
        if self.grid_index is None or self.grid_shape is None:
            return False
        return any(n > 1 and i in (0, n - 1) for i, n in zip(self.grid_index, self.grid_shape, strict=True))


def evaluate_candidates(candidates: Sequence[Candidate], settings: Settings) -> None:
    """Assess every candidate (fills ``evaluation``)."""
    for c in candidates:
        c.evaluation = evaluate(c.runs, settings, c.params)


def _metric(c: Candidate, k: int, by_rate: bool) -> tuple[float, list[float] | None, str, bool]:
    """(estimate, 95 % interval, what it is, fitted) of candidate ``c`` at design level ``k``."""
    ev = c.evaluation
    assert ev is not None
    if by_rate and ev.hazard is not None:
        h = ev.hazard["failure"]
        fitted = h["method"] == "fitted fragility"
        return h["annual_rate"], h["annual_rate_ci95"], "annual frequency of failure [1/yr]", fitted
    row = ev.levels[k]
    if row["p_failure"] is not None:
        return row["p_failure"], row["p_failure_ci95"], "P(failure) at the design level (fitted)", True
    obs = row["p_failure_observed"]
    return (
        math.nan if obs is None else obs,
        row["p_failure_observed_ci95"],
        "P(failure) at the design level (observed fraction)",
        False,
    )


def _overlap(a: Sequence[float] | None, b: Sequence[float] | None) -> bool:
    if a is None or b is None:
        return False
    return a[0] <= b[1] and b[0] <= a[1]


def rank(candidates: Sequence[Candidate], settings: Settings) -> list[dict[str, Any]]:
    """Per design level: every candidate's row, the recommendation, the equivalent ones, the edge flag.

    Returns
    -------
    list of dict
        One per design level: ``design_g``, ``ranked_by``, ``candidates`` (rows sorted by the
        estimate, each with ``rank`` (0: not eligible), ``eligible``, ``equivalent``), ``recommended``
        (a row, or None), ``best`` (the lowest estimate among the eligible), ``equivalent`` (names),
        ``edge_of_grid``, ``beats_floor``.
    """
    by_rate = settings.hazard is not None
    out = []
    for k, x in enumerate(settings.design):
        rows = []
        for c in candidates:
            ev = c.evaluation
            assert ev is not None
            lvl = ev.levels[k]
            est, ci, what, fitted = _metric(c, k, by_rate)
            rows.append(
                {
                    "name": c.name,
                    "source": c.source,
                    **c.params,
                    "period_s": c.period_s,
                    "estimate": est,
                    "estimate_ci95": ci,
                    "fitted": fitted,
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
                    "mce_g": lvl.get("mce_g"),
                    "disp_mce_m": lvl.get("disp_mce_m"),
                    "disp_mce_statistic": lvl.get("disp_mce_statistic"),
                    "within_capacity": bool(lvl.get("mce_within_capacity", True)),
                    "residual_max_m": lvl.get("residual_max_m"),
                    "recentring_ok": lvl.get("recentring_ok"),
                    "on_edge": c.on_edge,
                    "_c": c,
                }
            )
        eligible = [r for r in rows if r["within_capacity"] and math.isfinite(r["estimate"])]
        eligible.sort(key=lambda r: (r["estimate"], (r["estimate_ci95"] or [0, math.inf])[1], r["period_s"]))
        for r in rows:
            r["rank"] = 0
        for i, r in enumerate(eligible, start=1):
            r["rank"] = i
        best = eligible[0] if eligible else None
        equivalent = [
            r
            for r in eligible
            if best is not None and (r is best or _overlap(r["estimate_ci95"], best["estimate_ci95"]))
        ]
        for r in rows:
            r["equivalent"] = r in equivalent
        # the simplest of the equivalent ones: no isolation, then the shorter period, then the estimate
        rec = min(equivalent, key=lambda r: (r["period_s"], r["estimate"])) if equivalent else None
        floor = next((r for r in rows if r["source"] == "floor"), None)
        grid_best = next((r for r in eligible if r["source"] == "grid"), None)
        for r in rows:
            r.pop("_c")
        out.append(
            {
                "design_g": float(x),
                "ranked_by": _metric_name(by_rate),
                "candidates": sorted(rows, key=lambda r: (r["rank"] == 0, r["rank"])),
                "recommended": rec,
                "best": best,
                "equivalent": [r["name"] for r in equivalent],
                "edge_of_grid": bool(grid_best is not None and grid_best["on_edge"]),
                "beats_floor": bool(rec is not None and floor is not None and rec is not floor),
                "floor": floor,
            }
        )
    return out


def _metric_name(by_rate: bool) -> str:
    return (
        "annual frequency of failure (the site's hazard)"
        if by_rate
        else "probability of failure at the design level"
    )


def grid_axes(grid: Mapping[str, Any]) -> tuple[str, str]:
    """The two axes of a design grid: (Tb_s, xi_b) or (mu_b, R_b_m)."""
    return ("Tb_s", "xi_b") if grid["kind"] == "linear" else ("mu_b", "R_b_m")
