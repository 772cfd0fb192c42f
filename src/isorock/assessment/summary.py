"""What the assessment tells a user: the summary of ``/assessment`` (the ``isorock assess --json``
object), a plain-language conclusion per object that opens with the answer, and the summary table of
the report.

Every estimate is printed with its 95 % interval and, beside a fitted probability, what was observed
at that level; a probability that cannot be estimated is said to be so, with the count observed and
its exact binomial upper bound. The assumptions the numbers rest on are stated with them.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Mapping, Sequence
from typing import Any

import pandas as pd

from ..store import Store
from .case import MIN_RECORDS

__all__ = [
    "assessment_summary",
    "conclusions",
    "summary_table",
    "candidates_table",
    "pct",
    "ASSUMPTIONS",
    "MIN_RECORDS",
]


#: what every number of an assessment rests on (stated with the results)
ASSUMPTIONS = (
    "The object is a rigid block that rocks on its base edges without sliding or jumping (each run is "
    "checked: runs where it would slide or jump are outside the model); the ground motion is one "
    "horizontal component (no vertical input, no second horizontal); the isolator displacement is that "
    "of the one component analysed, not the vector of two; a friction-pendulum isolator carries a "
    "constant normal force."
)


def _num(x: Any) -> float | None:
    try:
        v = float(x)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


def _m3(x: Any) -> str:
    """A displacement [m] as printed in the tables: 3 significant digits (the spread of the records'
    peaks is far wider than that), "-" where there is none."""
    v = _num(x)
    return "-" if v is None else f"{v:.3g}"


def pct(p: float | None) -> str:
    """A probability in words with the precision it has: "0.52 %", "12 %", "< 0.01 %", "> 99.9 %"."""
    if p is None or not math.isfinite(p):
        return "n/a"
    if p <= 0:
        return "0 %"
    if p < 1e-4:
        return "< 0.01 %"
    if p > 0.999:
        return "> 99.9 %"
    return f"{100 * p:.2g} %" if p < 0.1 else f"{100 * p:.0f} %"


def _interval(ci: Sequence[float] | None, fmt=pct) -> str:
    if not ci:
        return ""
    return f"95 % interval {fmt(ci[0])} to {fmt(ci[1])}"


def _ci(row: Mapping[str, Any], name: str) -> list[float] | None:
    lo, hi = _num(row.get(f"{name}_lo")), _num(row.get(f"{name}_hi"))
    return None if lo is None or hi is None else [lo, hi]


def _value(v: Any) -> Any:
    if isinstance(v, bool):
        return v
    if isinstance(v, float):
        return _num(v)
    if hasattr(v, "item"):
        return _value(v.item())
    return v


def _row(row: Mapping[str, Any], flags: Sequence[str] = ()) -> dict[str, Any]:
    """A table row as JSON: ``_lo``/``_hi`` pairs back to ``[lo, hi]``, NaN as null, flags as booleans."""
    out: dict[str, Any] = {}
    for k, v in row.items():
        if k.endswith("_ci95_lo") or k.endswith("_ci95_g_lo"):
            base = k[: -len("_lo")]
            out[base] = _ci(row, base)
        elif k.endswith("_hi") and (k.endswith("_ci95_hi") or k.endswith("_ci95_g_hi")):
            continue
        else:
            out[k] = _value(v)
    for f in flags:
        if f in out and out[f] is not None:
            out[f] = bool(out[f])
    return out


_FRAG_KEYS: tuple[str, ...] = (
    "median_g", "beta", "median_ci95_g", "beta_ci95", "estimable", "n_runs", "n_damaged", "note", "n_boot",
    "n_boot_fitted",
)  # fmt: skip
_BM_KEYS = ("measure", "unit", "period_s", "damage", "median", "beta", "estimable")
_STRIPE_KEYS = (
    "pga_g", "n_records", "n_overturn", "n_uplift", "n_exceed_capacity", "n_failure", "n_outside_model",
    "n_slides", "n_jumps", "disp_median_m", "disp_p84_m", "disp_mean_m",
)  # fmt: skip
_LEVEL_FLAGS = (
    "estimable", "overturn_estimable", "failure_estimable", "uplift_estimable", "mce_within_capacity",
    "recentring_ok",
)  # fmt: skip


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
        j = _row(r)
        d = r["damage"]
        out[f"annual_rate_{d}"] = j["annual_rate"]
        out[f"annual_rate_{d}_ci95"] = j.get("annual_rate_ci95")
        out[f"p50_{d}"] = j["p50"]
        out[f"p50_{d}_ci95"] = j.get("p50_ci95")
        out[f"method_{d}"] = j["method"]
        out[f"above_last_max_{d}"] = j["above_last_max"]
        out[f"p_at_first_{d}"] = j["p_at_first"]
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
             "pga_g": _num(r["pga_g"])}
        )  # fmt: skip
    return out


def _case(store: Store, obj: str, case: str, st: pd.DataFrame, tabs: Mapping[str, Any]) -> dict[str, Any]:
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
        "fragility": _frag(f, "overturn"),
        "fragility_failure": _frag(f, "failure"),
        "uplift_fragility": _frag(f, "uplift"),
        "stripes": [{k: _value(r[k]) for k in _STRIPE_KEYS if k in r} for r in st.to_dict("records")],
        "design_levels": [
            {k: v for k, v in _row(r, _LEVEL_FLAGS).items() if k not in ("object", "case", "isolation")}
            for r in dl.to_dict("records")
        ],
        "validity": {
            "friction": _num(va["friction"]),
            "tan_alpha": _num(va.get("tan_alpha")),
            "n_runs": int(va["n_runs"]),
            "n_slides": int(va["n_slides"]),
            "n_jumps": int(va["n_jumps"]),
            "n_outside_model": int(va["n_outside_model"]),
            "mu_required_max": _num(va["mu_required_max"]),
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
            {
                k: _value(r[k])
                for k in ("measure", "unit", "period_s", "damage", "median", "beta", "estimable")
            }
            for r in g.to_dict("records")
        ]
    return out


def _design(dt: pd.DataFrame | None) -> list[dict[str, Any]]:
    out: list[dict[str, Any]] = []
    if dt is None:
        return out
    flags = (
        "fitted",
        "estimable",
        "within_capacity",
        "recentring_ok",
        "on_edge",
        "equivalent",
        "recommended",
    )
    for (obj, xd), g in dt.groupby(["object", "design_g"], sort=False):
        rows = [_row(r, (*flags, "edge_of_grid", "has_floor")) for r in g.to_dict("records")]
        for r in rows:
            for k in ("object", "design_g", "edge_of_grid", "ranked_by", "has_floor"):
                r.pop(k, None)
        rec = next((r for r in rows if r.get("recommended")), None)
        first = g.iloc[0]
        grid = [r for r in rows if r["source"] == "grid"]
        out.append(
            {
                "object": obj,
                "design_g": float(xd),
                "ranked_by": str(first["ranked_by"]),
                "candidates": rows,
                "recommended": rec,
                "equivalent": [r["name"] for r in rows if r.get("equivalent")],
                "edge_of_grid": bool(first["edge_of_grid"]),
                "has_floor": bool(first.get("has_floor", True)),
                "floor": next((r for r in rows if r["source"] == "floor"), None),
                "n_isolators": len(grid),
                "n_within_capacity": int(sum(bool(r["within_capacity"]) for r in grid)),
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
    the displacement and the MCE check; ``validity``; ``hazard`` with a hazard curve), ``design`` (per
    object and design level: ``candidates``, ``recommended``, ``equivalent``, ``edge_of_grid``,
    ``ranked_by``, ``floor``), ``warnings``, ``assumptions``, ``conclusions``.
    """
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
        _case(store, obj, case, st, tabs)
        for (obj, case), st in ([] if stripes is None else stripes.groupby(["object", "case"], sort=False))
    ]
    records = _records(store)
    objects = [
        {
            "name": o["object"],
            "lambda": float(o["lambda_"]),
            "R_m": float(o["R_m"]),
            "height_m": _num(o["height_m"]),
            "width_m": _num(o["width_m"]),
            "friction": float(o["friction"]),
            "tan_alpha": float(o["tan_alpha"]),
            "slides": bool(float(o["friction"]) < float(o["tan_alpha"])),
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
            "response-history analysis (ASCE/SEI 7-16 §17.3.3), and with fewer the intervals are wide"
        )
    out = {
        "records": records,
        "objects": objects,
        "capacity_m": a.get("capacity_m"),
        "stripes_g": a.get("stripes_g"),
        "design_g": a.get("design_g"),
        "mce_g": a.get("mce_g"),
        "outside_model": a.get("outside_model", "exclude"),
        "n_boot": a.get("bootstrap", 1000),
        "rho": (cfg.get("isolation") or {}).get("rho"),
        "cases": cases,
        "design": _design(store.table("assessment/design")),
        "warnings": warnings,
        "assumptions": ASSUMPTIONS,
    }
    out["conclusions"] = conclusions(out)
    return out


# ------------------------------------------------------------------------------------------------ words
def _describe(r: Mapping[str, Any]) -> str:
    """A base in words."""
    if r["isolation"] == "none":
        return "no isolation"
    if r["isolation"] == "linear":
        return f"a linear isolator with Tb = {r['Tb_s']:.3g} s and xi_b = {r['xi_b']:.2g}"
    return f"a friction pendulum with mu_b = {r['mu_b']:.3g} and R_b = {r['R_b_m']:.3g} m"


def _p_words(d: Mapping[str, Any], damage: str) -> str:
    """P(damage) at a design level, with its interval and what was observed there."""
    z, n = d.get(f"n_{damage}_observed"), d.get(f"n_{damage}_counted")
    seen = f"observed {z} of {n}" if n else "not run at this level"
    if d.get(f"p_{damage}") is not None:
        return f"{pct(d[f'p_{damage}'])} ({_interval(d.get(f'p_{damage}_ci95'))}; {seen})"
    ub = d.get(f"p_{damage}_upper95")
    bound = f", at most {pct(ub)} at 95 % confidence" if ub is not None else ""
    return f"not estimable ({seen}{bound})"


def _frag_words(f: Mapping[str, Any], what: str) -> str:
    if f.get("estimable"):
        ci, bci = f.get("median_ci95_g"), f.get("beta_ci95")
        m = f"median {what} PGA {f['median_g']:.2g} g"
        m += f" (95 % interval {ci[0]:.2g} to {ci[1]:.2g} g)" if ci else ""
        m += f", beta {f['beta']:.2f}" + (f" ({bci[0]:.2f} to {bci[1]:.2f})" if bci else "")
        return m
    return f"{what} fragility not estimable ({f.get('note', '').removeprefix('not estimable: ')})"


def _answer(o: Mapping[str, Any], design: Mapping[str, Any] | None) -> str:
    """The first sentence for an object: the answer."""
    name = o["name"]
    if o["slides"]:
        return (
            f"{name} slides before it can rock (friction {o['friction']:g} below tan alpha "
            f"{o['tan_alpha']:.3g}): the rocking results below do not describe it; restrain it against "
            "sliding first."
        )
    if design is None:
        return f"{name}: no design level was given, so no base is recommended."
    if not design["has_floor"]:
        return (
            f"{name}: no fixed-base case was assessed, so no advice can be compared with doing nothing; "
            "add the case {name: none, kind: none}."
        )
    rec = design["recommended"]
    x = design["design_g"]
    if rec is None:
        return f"{name}: no base stays within the displacement capacity at the MCE of {x:g} g."
    if rec["isolation"] == "none":
        return f"Isolation does not help {name} at {x:g} g: keep it on a fixed base."
    return f"Isolate {name} with {_describe(rec)} (design level {x:g} g)."


def _short(r: Mapping[str, Any]) -> str:
    """A candidate in a few words: ``no isolation``, ``lin3 (Tb 3 s, xi 0.2)``, ``grid (Tb 2 s, xi 0.4)``."""
    if r["isolation"] == "none":
        return "no isolation"
    name = "grid" if r["source"] == "grid" else r["name"]
    if r["isolation"] == "linear":
        return f"{name} (Tb {r['Tb_s']:.3g} s, xi {r['xi_b']:.2g})"
    return f"{name} (FP mu {r['mu_b']:.3g}, R {r['R_b_m']:.3g} m)"


def _recommendation(design: Mapping[str, Any], cap: float | None, rho: Any) -> list[str]:
    rec, floor = design["recommended"], design["floor"]
    parts: list[str] = []
    if rec is None:
        return parts
    best = next((r for r in design["candidates"] if r["rank"] == 1), rec)
    unit = " per year" if "annual" in design["ranked_by"] else ""
    fmt = (lambda v: f"{v:.2g}") if unit else pct

    def est(r: Mapping[str, Any]) -> str:
        ci = r.get("estimate_ci95")
        return f"{fmt(r['estimate'])}{unit}" + (f" ({_interval(ci, fmt)})" if ci else "")

    txt = f"Ranked by {design['ranked_by']}: {_short(rec)} {est(rec)}"
    if rec["isolation"] == "none":
        if best["name"] != rec["name"]:
            txt += (
                f"; the best isolator, {_short(best)}, {est(best)}, is equivalent within the intervals, so "
                "the simpler choice is kept"
            )
        else:
            txt += "; no isolator does better"
    elif floor is not None:
        txt += f", against {est(floor)} without isolation"
    parts.append(txt + ".")
    eq = [
        r
        for r in design["candidates"]
        if r.get("equivalent") and r["name"] not in (rec["name"], best["name"])
    ]
    if eq:
        more = f" and {len(eq) - 3} more" if len(eq) > 3 else ""
        parts.append(f"Also equivalent: {', '.join(_short(r) for r in eq[:3])}{more}.")
    if rec["isolation"] != "none":
        d = rec.get("disp_mce_m")
        parts.append(
            f"Isolator displacement at the MCE ({rec['mce_g']:g} g): {d:.3g} m ({rec['disp_mce_statistic']}, "
            f"ASCE/SEI 7-16 §17.6.3.4, EN 1998-1 §4.3.3.4.3)"
            + (f" against the capacity {cap:g} m" if cap else "")
            + f"; one horizontal component, not the vector of two; mass ratio rho = {rho}."
        )
        if rec["isolation"] == "fp" and rec.get("residual_max_m") is not None:
            parts.append(
                f"Friction pendulum: residual displacement up to mu_b R_b = {rec['residual_max_m']:.3g} m; "
                "restoring-force check of ASCE/SEI 7-16 §17.2.4.4 "
                + ("met." if rec.get("recentring_ok") else "NOT met (D / (2 R_b) < 0.025).")
            )
    grid_best = next((r for r in design["candidates"] if r["source"] == "grid" and r["rank"]), None)
    if design["edge_of_grid"] and grid_best is not None:
        parts.append(
            f"The best isolator of the grid, {_short(grid_best)}, is on the grid's edge: extend the grid "
            "before choosing."
        )
    return parts


def _object_text(o: Mapping[str, Any], cs: Sequence[Mapping[str, Any]], summary: Mapping[str, Any]) -> dict:
    name = o["name"]
    design = next((d for d in summary.get("design", []) if d["object"] == name), None)
    size = (
        f"{o['height_m']:g} m high and {o['width_m']:g} m wide"
        if o.get("height_m")
        else f"R = {o['R_m']:.3g} m"
    )
    parts = [_answer(o, design)]
    parts.append(
        f"{name}: {size}, slenderness {o['lambda']:.3g}, friction {o['friction']:g} (tan alpha "
        f"{o['tan_alpha']:.3g}); {len(summary.get('records', []))} records."
    )
    if o["slides"]:
        parts.append("The numbers below assume it does not slide; they are given for completeness only.")
    elif design is not None:
        parts += _recommendation(design, summary.get("capacity_m"), summary.get("rho"))
    levels = sorted({d["pga_g"] for c in cs for d in c["design_levels"]})
    for x in levels[:1]:
        rows = []
        for c in cs:
            d = next((d for d in c["design_levels"] if d["pga_g"] == x), None)
            if d is not None:
                rows.append(f"{c['isolation']}: {_p_words(d, 'failure')}")
        parts.append(f"P(failure: overturn or beyond the capacity) at {x:g} g: " + "; ".join(rows) + ".")
    for c in cs:
        parts.append(f"{c['isolation']}: {_frag_words(c['fragility'], 'overturning')}.")
        h = c.get("hazard")
        if h:
            parts.append(
                f"{c['isolation']} at the site: failure {h['annual_rate_failure']:.2g} per year"
                + (
                    f" ({h['annual_rate_failure_ci95'][0]:.2g} to {h['annual_rate_failure_ci95'][1]:.2g})"
                    if h.get("annual_rate_failure_ci95")
                    else ""
                )
                + f", {pct(h['p50_failure'])} in 50 years ({h['method_failure']})."
            )
    parts += _measure_words(cs)
    n_out = sum(c["validity"]["n_outside_model"] for c in cs)
    n_runs = sum(c["validity"]["n_runs"] for c in cs)
    if n_out:
        slides = sum(c["validity"]["n_slides"] for c in cs)
        jumps = sum(c["validity"]["n_jumps"] for c in cs)
        rule = cs[0]["validity"]["outside_model_rule"]
        how = "left out of the fits" if rule == "exclude" else "counted as failures"
        parts.append(
            f"{n_out} of {n_runs} stripe runs are outside the model ({slides} would slide, {jumps} would "
            f"jump): {how}."
        )
    else:
        parts.append(f"All {n_runs} stripe runs stay within the model (no sliding, no jumping).")
    parts += [w[0].upper() + w[1:] + "." for w in summary.get("warnings", [])]
    return {"object": name, "text": " ".join(parts), "headline": parts[0]}


_MEASURE_NAMES = {"pga": "PGA", "pgv": "PGV", "sa": "Sa"}


def _measure_label(b: Mapping[str, Any]) -> str:
    per = f" ({b['period_s']:.3g} s)" if b["measure"] == "sa" and b.get("period_s") else ""
    return _MEASURE_NAMES.get(b["measure"], b["measure"]) + per


def _measure_words(cs: Sequence[Mapping[str, Any]]) -> list[str]:
    """Which intensity measure predicts failure best, per case: beta of the failure fragility under each."""
    out = []
    for c in cs:
        bm = [b for b in c.get("beta_by_measure", []) if b["damage"] == "failure" and b["estimable"]]
        if len(bm) < 2:
            continue
        best = min(bm, key=lambda b: b["beta"])
        each = ", ".join(f"{b['beta']:.2f} under {_measure_label(b)}" for b in bm)
        out.append(
            f"{c['isolation']}: beta of failure {each}; {_measure_label(best)} predicts failure best "
            "(the smallest dispersion)."
        )
    return out


def conclusions(summary: dict[str, Any]) -> list[dict[str, str]]:
    """One plain-language paragraph per object that opens with the answer ("isolate with ...", "isolation
    does not help ...", "... slides before it can rock"), then the numbers with their intervals:
    ``{"object", "text", "headline"}`` (the headline is the first sentence)."""
    out = []
    for o in summary.get("objects", []):
        cs = [c for c in summary["cases"] if c["object"] == o["name"]]
        if cs:
            out.append(_object_text(o, cs, summary))
    return out


def summary_table(summary: dict[str, Any]) -> pd.DataFrame:
    """The summary: one row per object and isolation case, each estimate beside its interval and what
    was observed."""
    cap = summary.get("capacity_m")
    rows = []
    for c in summary["cases"]:
        row = {
            "object": c["object"],
            "isolation": c["isolation"],
            "median overturning PGA [g]": _median_text(c["fragility"]),
            "median failure PGA [g]": _median_text(c["fragility_failure"]),
        }
        for d in c["design_levels"]:
            x = d["pga_g"]
            for damage in ("failure", "overturn"):
                p, ci = d.get(f"p_{damage}"), d.get(f"p_{damage}_ci95")
                row[f"P({damage}) at {x:g} g"] = pct(p) if p is not None else "not estimable"
                row[f"95 % interval ({damage})"] = (
                    f"{pct(ci[0])} to {pct(ci[1])}" if ci else f"at most {pct(d.get(f'p_{damage}_upper95'))}"
                )
                row[f"observed ({damage})"] = (
                    f"{d.get(f'n_{damage}_observed')} of {d.get(f'n_{damage}_counted')}"
                )
            if c["kind"] != "none":
                row[f"MCE displacement [m] ({d.get('mce_g') or 0:g} g)"] = _m3(d.get("disp_mce_m"))
                if cap:
                    row[f"records beyond {cap:g} m at {x:g} g"] = pct(d["frac_exceed_capacity"])
        h = c.get("hazard")
        if h:
            row["failures per year"] = f"{h['annual_rate_failure']:.2g}"
            row["P(failure) in 50 years"] = pct(h["p50_failure"])
        v = c["validity"]
        row["outside the model"] = f"{v['n_outside_model']} of {v['n_runs']}"
        rows.append(row)
    return pd.DataFrame(rows)


def _median_text(f: Mapping[str, Any]) -> str:
    if not f.get("estimable"):
        return "not estimable"
    ci = f.get("median_ci95_g")
    return f"{f['median_g']:.2g}" + (f" ({ci[0]:.2g} to {ci[1]:.2g})" if ci else "")


def candidates_table(design: Mapping[str, Any], n_grid: int = 8) -> pd.DataFrame:
    """The design search's candidates at one design level, for the report: the fixed base, the cases
    and the best ``n_grid`` isolators of the grid, with their estimates and intervals."""
    rows = []
    cands = design["candidates"]
    keep = [c for c in cands if c["source"] != "grid"]
    keep += [c for c in cands if c["source"] == "grid"][:n_grid]
    rate = "annual" in design["ranked_by"]
    fmt = (lambda v: f"{v:.2g}") if rate else pct
    for c in keep:
        ci = c.get("estimate_ci95")
        rows.append(
            {
                "candidate": c["name"],
                "base": _describe(c),
                ("failures per year" if rate else "P(failure)"): fmt(c["estimate"])
                if c["estimate"] is not None
                else "n/a",
                "95 % interval": f"{fmt(ci[0])} to {fmt(ci[1])}" if ci else "",
                "fitted": "yes" if c["fitted"] else "observed fraction",
                "MCE displacement [m]": _m3(c.get("disp_mce_m")),
                "within the capacity": "yes" if c["within_capacity"] else "no",
                "rank": c["rank"] or "-",
                "advice": "recommended"
                if c.get("recommended")
                else ("equivalent" if c.get("equivalent") else ""),
            }
        )
    return pd.DataFrame(rows)
