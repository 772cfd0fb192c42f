"""The summary of ``/assessment``: the ``isorock assess --json`` object, read from the store.

What it says in words (the verdict first, the short table, the paragraphs of the report) is
:mod:`isorock.assessment.words`; this module only assembles the numbers, every estimate with its
interval, as the tables of :func:`isorock.jobs.assessment.assessment_tables` hold them.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping, Sequence
from typing import Any

import pandas as pd

from isorock.assessment.case import MIN_RECORDS, PAIR_KEY
from isorock.assessment.formats import finite, sci
from isorock.store import Store

__all__ = ["assessment_summary", "ASSUMPTIONS", "MIN_RECORDS"]


#: what every number of an assessment rests on (stated with the results)
ASSUMPTIONS = (
    "The object is a rigid block that rocks on its base edges without sliding or jumping (each run is "
    "checked: runs where it would slide or jump are outside the model), or, when its friction is below "
    "tan alpha, slides on its base without rocking (Coulomb friction, the exact motion of such an object "
    "under horizontal input); the ground motion is one horizontal component (no second horizontal; the "
    "vertical only with records.vertical: true, where the record has one); the isolator displacement is "
    "that of the one component analysed, not the vector of two; a run that overturns the object counts "
    "the isolator's peak up to the overturn (a lower bound); a friction-pendulum isolator carries the "
    "total weight as its normal force (times (g + a_v) / g with the vertical), not the rocking block's "
    "changing load; the object-to-base mass ratio rho is the configuration's."
)


def _ci(row: Mapping[str, Any], name: str) -> list[float] | None:
    lo, hi = finite(row.get(f"{name}_lo")), finite(row.get(f"{name}_hi"))
    return None if lo is None or hi is None else [lo, hi]


def _value(v: Any) -> Any:
    if isinstance(v, bool):
        return v
    if isinstance(v, float):
        return finite(v)
    if hasattr(v, "item"):
        return _value(v.item())
    return v


def _row(row: Mapping[str, Any], flags: Sequence[str] = ()) -> dict[str, Any]:
    """A table row as JSON: ``_lo``/``_hi`` pairs of an interval or bounds
    (:data:`~isorock.assessment.case.PAIR_KEY`) back to ``[lo, hi]``, NaN as null, flags as booleans."""
    out: dict[str, Any] = {}
    for k, v in row.items():
        if k.endswith(("_lo", "_hi")) and PAIR_KEY.search(k[:-3]) and f"{k[:-3]}_lo" in row:
            if k.endswith("_lo"):
                out[k[:-3]] = _ci(row, k[:-3])
            continue
        out[k] = _value(v)
    for f in flags:
        if f in out and out[f] is not None:
            out[f] = bool(out[f])
    return out


_FRAG_KEYS: tuple[str, ...] = (
    "median_g", "beta", "median_ci95_g", "beta_ci95", "estimable", "n_runs", "n_damaged", "note", "n_boot",
    "n_boot_fitted",
)  # fmt: skip
_BM_KEYS = (
    "measure",
    "component",
    "unit",
    "period_s",
    "damage",
    "median",
    "beta",
    "median_ci95",
    "beta_ci95",
    "estimable",
)
_STRIPE_KEYS = (
    "level", "n_records", "n_overturn", "n_uplift", "n_exceed_capacity", "n_failure", "n_outside_model",
    "n_slides", "n_jumps", "disp_median_m", "disp_p84_m", "disp_mean_m", "n_slid", "n_slides_beyond",
    "slide_median_m", "slide_p84_m", "slide_max_m",
)  # fmt: skip
_LEVEL_FLAGS = (
    "estimable", "overturn_estimable", "failure_estimable", "uplift_estimable", "mce_within_capacity",
    "recentring_ok",
)  # fmt: skip
_CANDIDATE_FLAGS = (
    "fitted", "estimable", "within_capacity", "eligible", "recentring_ok", "on_edge", "equivalent",
    "beats_floor", "recommended", "adequate", "p_failure_bounded_by_overturn",
    "mce_statistic_within_capacity", "mce_fractile_within_capacity",
)  # fmt: skip


_BODY_KEYS = ("b_left_m", "b_right_m", "h_cg_m", "r_gyration_m", "tan_alpha_left", "tan_alpha_right")


def _body(o: Mapping[str, Any]) -> dict[str, Any] | None:
    """A rigid body's geometry from its objects row (None for a uniform block, or an older store)."""
    if not all(k in o and finite(o[k]) is not None for k in _BODY_KEYS):
        return None
    return {**{k: float(o[k]) for k in _BODY_KEYS}, "polarities": int(o.get("polarities", 1))}


def _frag(f: pd.DataFrame, damage: str) -> dict[str, Any]:
    if damage not in f.index:
        return {"median_g": None, "beta": None, "estimable": False, "note": "not computed"}
    r = _row(f.loc[damage].to_dict(), ("estimable",))
    return {k: r.get(k) for k in _FRAG_KEYS}


def _hazard(h: pd.DataFrame | None, obj: str, case: str) -> dict[str, Any] | None:
    if h is None:
        return None
    g = h[(h["object"] == obj) & (h["case"] == case)]
    if g.empty:
        return None
    out: dict[str, Any] = {}
    for r in g.to_dict("records"):
        j = _row(r, ("tails_differ", "first_point_matters"))
        d = r["damage"]
        out[f"annual_rate_{d}"] = j["annual_rate"]
        out[f"annual_rate_{d}_ci95"] = j.get("annual_rate_ci95")
        out[f"annual_rate_{d}_bounds"] = j.get("annual_rate_bounds")
        out[f"tails_differ_{d}"] = j.get("tails_differ")
        out[f"p50_{d}"] = j["p50"]
        out[f"p50_{d}_ci95"] = j.get("p50_ci95")
        out[f"method_{d}"] = j["method"]
        out[f"above_last_max_{d}"] = j["above_last_max"]
        out[f"p_at_first_{d}"] = j["p_at_first"]
        out[f"first_point_matters_{d}"] = j.get("first_point_matters")
        out[f"annual_rate_{d}_exact_ci95"] = j.get("annual_rate_exact_ci95")
        out[f"deaggregation_{d}"] = json.loads(r.get("deaggregation") or "[]")
    return out


def _records(store: Store) -> list[dict[str, Any]]:
    recs = store.table("summary/records")
    out = []
    for r in [] if recs is None else recs.to_dict("records"):
        files = [r["source_file"]]
        try:
            rot = json.loads(r.get("rotated_from") or "[]")
        except ValueError:
            rot = []
        if rot:
            files = [p["file"] for p in rot]
        out.append(
            {"id": r["record"], "file": r["source_file"], "files": files, "component": r.get("component", ""),
             "pga_g": finite(r["pga_g"])}
        )  # fmt: skip
    return out


def _case(obj: str, case: str, st: pd.DataFrame, tabs: Mapping[str, Any]) -> dict[str, Any]:
    frag, levels, validity = tabs["fragility"], tabs["design_levels"], tabs["validity"]
    f = frag[(frag["object"] == obj) & (frag["case"] == case)].set_index("damage")
    dl = (
        levels[(levels["object"] == obj) & (levels["case"] == case)] if levels is not None else pd.DataFrame()
    )
    va = validity[(validity["object"] == obj) & (validity["case"] == case)].iloc[0]
    out = {
        "object": obj,
        "isolation": case,
        "kind": str(st["isolation"].iloc[0]),
        "mode": str(va["mode"]) if "mode" in va else "rocking",
        "fragility": _frag(f, "overturn"),
        "fragility_failure": _frag(f, "failure"),
        "uplift_fragility": _frag(f, "uplift"),
        "stripes": [{k: _value(r[k]) for k in _STRIPE_KEYS if k in r} for r in st.to_dict("records")],
        "design_levels": [
            {k: v for k, v in _row(r, _LEVEL_FLAGS).items() if k not in ("object", "case", "isolation")}
            for r in dl.to_dict("records")
        ],
        "validity": {
            "friction": finite(va["friction"]),
            "tan_alpha": finite(va.get("tan_alpha")),
            "n_runs": int(va["n_runs"]),
            "n_slides": int(va["n_slides"]),
            "n_jumps": int(va["n_jumps"]),
            "n_outside_model": int(va["n_outside_model"]),
            "mu_required_max": finite(va["mu_required_max"]),
            "outside_model_rule": str(va.get("outside_model_rule", "exclude")),
        },
    }
    hz = _hazard(tabs.get("hazard"), obj, case)
    if hz is not None:
        out["hazard"] = hz
    bm = tabs.get("fragility_by_measure")
    if bm is not None:
        g = bm[(bm["object"] == obj) & (bm["case"] == case)]
        out["beta_by_measure"] = [
            {k: v for k, v in _row(r, ("estimable",)).items() if k in _BM_KEYS} for r in g.to_dict("records")
        ]
    return out


def _paired(r: dict[str, Any], name: str) -> None:
    """The ``<name>_*`` columns of a candidate row as one object ``r[name]`` (None where not compared)."""
    keys = (
        "difference", "difference_ci95", "p_better", "p_worse", "n", "n_better", "n_worse", "basis",
        "p_single", "p_adjusted", "n_family", "decided_by",
    )  # fmt: skip
    vals = {k: r.pop(f"{name}_{k}", None) for k in keys}
    r[name] = None if vals["difference"] is None and vals["p_better"] is None else vals


def _design(dt: pd.DataFrame | None, vt: pd.DataFrame | None) -> list[dict[str, Any]]:
    out: list[dict[str, Any]] = []
    if dt is None:
        return out
    verdicts = {} if vt is None else {(r["object"], float(r["design_g"])): r for r in vt.to_dict("records")}
    for (obj, xd), g in dt.groupby(["object", "design_g"], sort=False):
        rows = [_row(r, (*_CANDIDATE_FLAGS, "edge_of_grid", "has_floor")) for r in g.to_dict("records")]
        for r in rows:
            for k in ("object", "design_g", "edge_of_grid", "ranked_by", "has_floor"):
                r.pop(k, None)
            _paired(r, "vs_floor")
            _paired(r, "vs_best")
            if isinstance(r.get("deaggregation"), str):
                r["deaggregation"] = json.loads(r["deaggregation"])
        rec = next((r for r in rows if r.get("recommended")), None)
        first = g.iloc[0]
        v = verdicts.get((obj, float(xd)), {})
        grid_rows = [r for r in rows if r["source"] == "grid"]
        best = next((r for r in rows if r["name"] == v.get("best")), None)
        grid = json.loads(v.get("grid") or "{}")
        out.append(
            {
                "object": obj,
                "design_g": float(xd),
                "design_basis": v.get("design_basis", ""),
                "mce_g": finite(v.get("mce_g")),
                "mce_basis": v.get("mce_basis", ""),
                "ranked_by": str(first["ranked_by"]),
                "verdict": v.get("verdict", "inconclusive"),
                "reason": v.get("reason", ""),
                "target": json.loads(v.get("target") or "null"),
                "decided_by": v.get("decided_by", ""),
                "n_family": int(v.get("n_family", 0) or 0),
                "equivalence_margin": finite(v.get("equivalence_margin")),
                "equivalence_margin_fraction": finite(v.get("equivalence_margin_fraction")),
                "gamma_x": finite(v.get("gamma_x")),
                "disp_fractile": finite(v.get("disp_fractile")),
                "closest": next((r for r in rows if r["name"] == v.get("closest")), None),
                "n_records": int(v.get("n_records", 0)),
                "n_boot": int(v.get("n_boot", 0)),
                "records_to_decide": None
                if finite(v.get("records_to_decide")) is None
                else int(v["records_to_decide"]),
                "candidates": rows,
                "recommended": rec,
                "best": best,
                "equivalent": [r["name"] for r in rows if r.get("equivalent")],
                "edge_of_grid": bool(first["edge_of_grid"]),
                "edges": json.loads(v.get("edges") or "[]"),
                "grid": {
                    "extended": bool(grid.get("extended", False)),
                    "bounds_reached": grid.get("bounds_reached", []),
                    **{k: grid[k] for k in ("axes", "rounds", "added", "extend") if k in grid},
                }
                if v.get("has_grid", True) and grid
                else {"extended": False, "bounds_reached": []},
                "has_grid": bool(v.get("has_grid", bool(grid_rows))),
                "has_floor": bool(first.get("has_floor", True)),
                "floor": next((r for r in rows if r["source"] == "floor"), None),
                "n_isolators": len(grid_rows),
                "n_within_capacity": int(sum(bool(r["within_capacity"]) for r in grid_rows)),
                "ranked": sorted((r for r in rows if r["rank"]), key=lambda r: r["rank"])[:3],
            }
        )
    return out


def assessment_summary(h5: str | os.PathLike | Store) -> dict[str, Any]:
    """The assessment of a store as one JSON-ready object.

    Keys: ``records`` (``id``, ``file``, ``files`` (both of a rotation), ``component``, ``pga_g``),
    ``objects`` (``lambda``, ``R_m``, ``height_m``, ``width_m``, ``friction``, ``tan_alpha``, ``slides``:
    friction below tan alpha), ``cases`` (per object and isolation case: ``fragility`` (overturning),
    ``fragility_failure`` (overturn or beyond the capacity) and ``uplift_fragility``, each ``median_g``,
    ``beta``, ``median_ci95_g``, ``beta_ci95``, ``estimable``; ``stripes`` with the counts of every
    failure mode; ``design_levels`` with ``p_overturn``, ``p_failure``, ``p_uplift``, their ``_ci95``,
    ``_observed`` (null when the level was not run), ``_observed_ci95`` and ``_upper95``, ``estimable``,
    the share of records beyond the capacity (``p_exceed_capacity`` and its ``_ci95``), the MCE check
    (``disp_mce_m``, ``disp_mce_ci95_m``, ``p_mce_exceed_capacity`` and its ``_ci95``,
    ``mce_within_capacity``, ``mce_basis``); ``validity``; ``hazard`` with a hazard curve, each rate
    with its ``_ci95`` and ``_bounds``; ``beta_by_measure`` with intervals), ``design`` (per object and
    design level: ``verdict``, ``reason``, ``n_records``, ``recommended`` (null when inconclusive),
    ``candidates`` (each with ``vs_floor`` and ``vs_best``: ``difference``, ``difference_ci95``,
    ``p_better``, ``p_worse``), ``equivalent``, ``grid`` (``extended``, ``bounds_reached``, ``axes``),
    ``edge_of_grid``, ``ranked_by``, ``floor``, ``best``, ``records_to_decide``), ``warnings``,
    ``assumptions``, ``conclusions`` (:func:`isorock.assessment.words.conclusions`).
    """
    from isorock.assessment.words import conclusions

    store = h5 if isinstance(h5, Store) else Store(h5)
    cfg = json.loads(str(store.root_attrs.get("config_json", "{}")) or "{}")
    a = cfg.get("assessment") or {}
    objs = store.table("assessment/objects")
    if objs is None:
        return {"records": [], "cases": [], "objects": [], "design": [], "conclusions": [], "warnings": []}
    names = ("fragility", "design_levels", "validity", "hazard", "fragility_by_measure")
    tabs = {n: store.table(f"assessment/{n}") for n in names}
    stripes = store.table("assessment/stripes")
    cases = [
        _case(obj, case, st, tabs)
        for (obj, case), st in ([] if stripes is None else stripes.groupby(["object", "case"], sort=False))
    ]
    records = _records(store)
    objects = [
        {
            "name": o["object"],
            "lambda": float(o["lambda_"]),
            "R_m": float(o["R_m"]),
            "height_m": finite(o["height_m"]),
            "width_m": finite(o["width_m"]),
            "friction": float(o["friction"]),
            "tan_alpha": float(o["tan_alpha"]),
            "slides": bool(float(o["friction"]) < float(o["tan_alpha"])),
            "slide_allow_m": finite(o["slide_allow_m"]) if "slide_allow_m" in o else None,
            "body": _body(o),
        }
        for o in objs.to_dict("records")
    ]
    n_rec = max(
        (c["design_levels"][0]["n_records"] for c in cases if c["design_levels"]), default=len(records)
    )
    warnings = []
    if n_rec < MIN_RECORDS:
        warnings.append(
            f"only {n_rec} records: the isolation codes ask for at least {MIN_RECORDS} ground motions in a "
            "response-history analysis (ASCE/SEI 7-16, Chapter 17), and with fewer the intervals are wide"
        )
    for c in cases:
        h = c.get("hazard") or {}
        if h.get("tails_differ_failure"):
            lo, hi = h["annual_rate_failure_bounds"]
            warnings.append(
                f"{c['object']} / {c['isolation']}: the hazard curve ends before failure is certain: "
                f"counting every exceedance of its last level as a failure raises the annual frequency "
                f"from {sci(lo)} to {sci(hi)} per year; extend the curve to higher levels"
            )
        if h.get("first_point_matters_failure"):
            warnings.append(
                f"{c['object']} / {c['isolation']}: P(failure) is {100 * h['p_at_first_failure']:.2g} % at "
                "the "
                "hazard curve's first level; the levels below it, left out, may add to the annual frequency"
            )
    out = {
        "records": records,
        "objects": objects,
        "capacity_m": a.get("capacity_m"),
        "stripes_g": a.get("stripes_g"),
        "design_g": sorted({d["level"] for c in cases for d in c["design_levels"]}),
        "mce_g": sorted(
            {d["mce_g"] for c in cases for d in c["design_levels"] if d.get("mce_g") is not None}
        ),
        "outside_model": a.get("outside_model", "exclude"),
        "gamma_x": a.get("gamma_x", 1.2),
        "n_boot": a.get("bootstrap", 1000),
        "rho": (cfg.get("isolation") or {}).get("rho"),
        "cases": cases,
        "design": _design(store.table("assessment/design"), store.table("assessment/verdicts")),
        "warnings": warnings,
        "assumptions": ASSUMPTIONS,
    }
    m = _measure(store)
    m["rotd100_over_rotd50"] = _directionality(store, m["imt"])
    out["measure"] = m
    out["imt"], out["component"] = m["imt"], m["component"]
    out["hazard"] = m["hazard"]
    for d in [*out["design"], *out["cases"]]:
        d["unit"], d["measure"] = m["unit"], m["short"]
    out["conclusions"] = conclusions(out)
    return out


def _directionality(store: Store, imt: str) -> list[float] | None:
    """The smallest, median and largest ratio RotD100 / RotD50 of the measure over the records that have
    both (None where none has)."""
    recs = store.table("summary/records")
    if recs is None or "rotd50" not in recs:
        return None
    ratios = []
    for a, b in zip(recs["rotd50"], recs["rotd100"], strict=True):
        try:
            lo, hi = json.loads(a or "{}").get(imt), json.loads(b or "{}").get(imt)
        except ValueError:
            continue
        if lo and hi:
            ratios.append(float(hi) / float(lo))
    if not ratios:
        return None
    ratios.sort()
    n = len(ratios)
    median = ratios[n // 2] if n % 2 else 0.5 * (ratios[n // 2 - 1] + ratios[n // 2])
    return [ratios[0], median, ratios[-1]]


def _measure(store: Store) -> dict[str, Any]:
    """The stripes' measure (``imt``, ``unit``, ``component``, ``label``, ``short``, ``basis``) and the
    hazard curve's (``hazard``: ``imt``, ``component_definition``, ``source``, ``file``, ``kind``,
    ``site``, ``vs30_m_s``, ``notes``; None without one), from ``/assessment/measure`` (a store of layout
    6 or older: PGA of the analysed component)."""
    t = store.table("assessment/measure")
    if t is None or not len(t):
        r: dict[str, Any] = {"imt": "PGA", "unit": "g", "component": "analysed", "basis": "layout 6 or older"}
    else:
        r = t.iloc[0].to_dict()
    comp = str(r["component"])
    short = str(r["imt"]) if comp == "analysed" else f"{r['imt']} {comp}"
    hz = None
    if r.get("hazard_imt"):
        vs = finite(r.get("hazard_vs30_m_s"))
        hz = {
            "imt": str(r["hazard_imt"]),
            "component_definition": str(r["hazard_component_definition"]),
            "source": str(r["hazard_source"]),
            "file": str(r["hazard_file"]),
            "kind": str(r.get("hazard_kind", "")),
            "site": str(r.get("hazard_site", "")),
            "vs30_m_s": vs,
            "notes": json.loads(str(r.get("hazard_notes") or "[]")),
        }
    return {
        "imt": str(r["imt"]),
        "unit": str(r["unit"]),
        "component": comp,
        "label": str(r.get("label") or short),
        "short": short,
        "basis": str(r.get("basis", "")),
        "hazard": hz,
    }
