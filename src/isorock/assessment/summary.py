"""What the assessment tells a user: the summary of ``/assessment`` (the ``isorock assess --json``
object), a plain-language conclusion per object, and the summary table of the report."""

from __future__ import annotations

import json
import math
import os
from typing import Any

import pandas as pd

from ..store import Store

__all__ = ["assessment_summary", "conclusions", "summary_table", "pct"]


def _num(x: Any) -> float | None:
    try:
        v = float(x)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


def pct(p: float | None) -> str:
    """A probability in words with the precision it has: "< 0.1 %", "12 %", "> 99.9 %"."""
    if p is None or not math.isfinite(p):
        return "n/a"
    if p < 0.001:
        return "< 0.1 %"
    if p > 0.999:
        return "> 99.9 %"
    return f"{100 * p:.2g} %" if p < 0.1 else f"{100 * p:.0f} %"


def assessment_summary(h5: str | os.PathLike | Store) -> dict[str, Any]:
    """The assessment of a store as one JSON-ready object.

    Keys: ``records`` (``id``, ``file``: the file used, ``files`` (both of a rotation), ``component``,
    ``pga_g``), ``objects`` (the objects with ``lambda``, ``R_m``, ``friction``), ``cases`` (one per
    object and isolation case: ``object``, ``isolation`` (the case name), ``kind``, ``fragility``
    (``median_g``, ``beta``, ``note``), ``uplift_fragility``, ``stripes`` (``pga_g``, ``n_records``,
    ``n_overturn``, ``n_uplift``, ``disp_median_m``, ``disp_p84_m``, ``n_exceed_capacity``,
    ``n_outside_model``), ``design_levels`` (``pga_g``, ``p_overturn``, ``p_uplift``, ``disp_median_m``,
    ``disp_p84_m``, ``frac_exceed_capacity``), ``validity`` (runs, sliding, jumping, outside the model)),
    ``design`` (per object and design level: the recommended isolator and the runners-up),
    ``capacity_m``, ``conclusions``.
    """
    store = h5 if isinstance(h5, Store) else Store(h5)
    cfg = json.loads(str(store.root_attrs.get("config_json", "{}")) or "{}")
    a = cfg.get("assessment") or {}
    objs = store.table("assessment/objects")
    if objs is None:
        return {"records": [], "cases": [], "objects": [], "design": [], "conclusions": []}
    recs = store.table("summary/records")
    records = []
    for r in [] if recs is None else recs.to_dict("records"):
        files = [r["source_file"]]
        try:
            rot = json.loads(r.get("rotated_from") or "[]")
        except ValueError:
            rot = []
        if rot:
            files = [p["file"] for p in rot]
        records.append(
            {"id": r["record"], "file": r["source_file"], "files": files, "component": r.get("component", ""),
             "pga_g": _num(r["pga_g"])}
        )  # fmt: skip
    stripes = store.table("assessment/stripes")
    frag = store.table("assessment/fragility")
    levels = store.table("assessment/design_levels")
    validity = store.table("assessment/validity")
    cases = []
    for (obj, case), st in [] if stripes is None else stripes.groupby(["object", "case"], sort=False):
        assert frag is not None and validity is not None  # merged together with the stripes
        f = frag[(frag["object"] == obj) & (frag["case"] == case)].set_index("damage")
        dl = (
            levels[(levels["object"] == obj) & (levels["case"] == case)]
            if levels is not None
            else pd.DataFrame()
        )
        va = validity[(validity["object"] == obj) & (validity["case"] == case)].iloc[0]
        cases.append(
            {
                "object": obj,
                "isolation": case,
                "kind": str(st["isolation"].iloc[0]),
                "fragility": _frag(f.loc["overturn"]),
                "uplift_fragility": _frag(f.loc["uplift"]),
                "stripes": [
                    {k: (_num(v) if isinstance(v, float) else int(v)) for k, v in row.items()}
                    for row in st[
                        [
                            "pga_g",
                            "n_records",
                            "n_overturn",
                            "n_uplift",
                            "disp_median_m",
                            "disp_p84_m",
                            "n_exceed_capacity",
                            "n_outside_model",
                        ]
                    ].to_dict("records")
                ],  # fmt: skip
                "design_levels": [
                    {k: (_num(v) if isinstance(v, float) else int(v)) for k, v in row.items()}
                    for row in dl[
                        [
                            "pga_g",
                            "p_overturn",
                            "p_uplift",
                            "p_overturn_observed",
                            "disp_median_m",
                            "disp_p84_m",
                            "frac_exceed_capacity",
                            "n_records",
                        ]
                    ].to_dict("records")
                ],  # fmt: skip
                "validity": {
                    "friction": _num(va["friction"]),
                    "n_runs": int(va["n_runs"]),
                    "n_slides": int(va["n_slides"]),
                    "n_jumps": int(va["n_jumps"]),
                    "n_outside_model": int(va["n_outside_model"]),
                    "mu_required_max": _num(va["mu_required_max"]),
                },
            }
        )
    design = []
    dt = store.table("assessment/design")
    if dt is not None:
        for (obj, xd), g in dt.groupby(["object", "design_g"], sort=False):
            ranked = g[g["rank"] > 0].sort_values("rank")
            design.append(
                {
                    "object": obj,
                    "design_g": float(xd),
                    "n_isolators": len(g),
                    "n_within_capacity": int(g["within_capacity"].sum()),
                    "ranked": [_isolator(r) for r in ranked.to_dict("records")],
                }
            )
    out = {
        "records": records,
        "objects": [
            {
                "name": o["object"],
                "lambda": float(o["lambda_"]),
                "R_m": float(o["R_m"]),
                "height_m": _num(o["height_m"]),
                "width_m": _num(o["width_m"]),
                "friction": float(o["friction"]),
                "tan_alpha": float(o["tan_alpha"]),
            }
            for o in objs.to_dict("records")
        ],  # fmt: skip
        "capacity_m": a.get("capacity_m"),
        "stripes_g": a.get("stripes_g"),
        "design_g": a.get("design_g"),
        "cases": cases,
        "design": design,
    }
    out["conclusions"] = conclusions(out)
    return out


def _frag(row: pd.Series) -> dict[str, Any]:
    return {"median_g": _num(row["median_g"]), "beta": _num(row["beta"]), "note": str(row["note"])}


def _isolator(r: dict) -> dict[str, Any]:
    keys = (
        "isolation",
        "Tb_s",
        "xi_b",
        "mu_b",
        "R_b_m",
        "p_overturn",
        "disp_p84_m",
        "median_g",
        "beta",
        "rank",
    )
    return {k: (_num(r[k]) if isinstance(r[k], float) else r[k]) for k in keys}


def _describe_isolator(r: dict) -> str:
    if r["isolation"] == "linear":
        return f"a linear isolator with Tb = {r['Tb_s']:.3g} s and xi_b = {r['xi_b']:.2g}"
    return f"an FP isolator with mu_b = {r['mu_b']:.3g} and R_b = {r['R_b_m']:.3g} m"


def conclusions(summary: dict[str, Any]) -> list[dict[str, str]]:
    """One plain-language paragraph per object, and its gist in one sentence (the report's landing
    page): ``{"object", "text", "headline"}``."""
    out = []
    cap = summary.get("capacity_m")
    n_rec = len(summary.get("records", []))
    for o in summary.get("objects", []):
        name = o["name"]
        cs = [c for c in summary["cases"] if c["object"] == name]
        if not cs:
            continue
        size = (
            f"{o['height_m']:g} m high and {o['width_m']:g} m wide"
            if o.get("height_m")
            else f"R = {o['R_m']:.3g} m"
        )
        parts = [
            f"{name} ({size}, slenderness {o['lambda']:.3g}, friction {o['friction']:g}), {n_rec} records."
        ]
        levels = sorted({d["pga_g"] for c in cs for d in c["design_levels"]})
        head: list[str] = []
        for x in levels:
            rows = []
            for c in cs:
                d = next((d for d in c["design_levels"] if d["pga_g"] == x), None)
                if d is None:
                    continue
                disp = ""
                if c["kind"] != "none" and d.get("disp_p84_m") is not None:
                    over = cap is not None and d["disp_p84_m"] > cap
                    disp = f", isolator displacement {d['disp_p84_m']:.2f} m at the 84th percentile" + (
                        f" ({'beyond' if over else 'within'} the {cap:g} m capacity)" if cap else ""
                    )
                rows.append((c, d, f"{c['isolation']}: {pct(d['p_overturn'])}{disp}"))
            if not rows:
                continue
            parts.append(
                f"At {x:g} g the probability of overturning is " + "; ".join(r[2] for r in rows) + "."
            )
            if not head:
                head.append(
                    f"probability of overturning at {x:g} g: "
                    + ", ".join(f"{pct(r[1]['p_overturn'])} on {r[0]['isolation']}" for r in rows)
                )
            ok = [r for r in rows if not (cap and r[0]["kind"] != "none" and (r[1]["disp_p84_m"] or 0) > cap)]
            base = next((r for r in rows if r[0]["kind"] == "none"), None)
            if ok:
                best = min(ok, key=lambda r: r[1]["p_overturn"] if r[1]["p_overturn"] is not None else 1.0)
                if base is not None and best[0]["kind"] != "none":
                    pb, pi = base[1]["p_overturn"] or 0.0, best[1]["p_overturn"] or 0.0
                    if pi < pb:
                        verdict = f"isolation on {best[0]['isolation']} lowers it ({pct(pb)} -> {pct(pi)})"
                    elif pi > pb:
                        verdict = (
                            f"no isolation case lowers it; {best[0]['isolation']} raises it to {pct(pi)}"
                        )
                    else:
                        verdict = "isolation does not change it"
                    parts.append(f"Of the cases within the displacement capacity, {verdict}.")
                elif base is not None:
                    parts.append("No isolation case within the displacement capacity does better than none.")
        m_none = _median(_none(cs))
        worse = [
            c["isolation"] for c in cs
            if c["kind"] != "none" and m_none is not None and (m := _median(c)) is not None and m < m_none
        ]  # fmt: skip
        if worse:
            parts.append(
                f"Isolation makes overturning more likely for {', '.join(worse)} (lower median "
                "overturning PGA than without isolation)."
            )
        for d in summary.get("design", []):
            if d["object"] == name and d["ranked"]:
                r = d["ranked"][0]
                head.append(f"recommended isolator (within the capacity): {_describe_isolator(r)}")
                parts.append(
                    f"Design search at {d['design_g']:g} g ({d['n_isolators']} isolators, "
                    f"{d['n_within_capacity']} within the capacity): recommended {_describe_isolator(r)} "
                    f"(P(overturn) {pct(r['p_overturn'])}, 84th-percentile displacement "
                    f"{r['disp_p84_m']:.2f} m)."
                )
            elif d["object"] == name:
                parts.append(
                    f"Design search at {d['design_g']:g} g: no isolator of the grid stays within the "
                    "capacity."
                )
        n_out = sum(c["validity"]["n_outside_model"] for c in cs)
        n_runs = sum(c["validity"]["n_runs"] for c in cs)
        if n_out:
            slides = sum(c["validity"]["n_slides"] for c in cs)
            jumps = sum(c["validity"]["n_jumps"] for c in cs)
            parts.append(
                f"{n_out} of {n_runs} analyses fall outside the model ({slides} would slide: friction "
                f"needed above {o['friction']:g}; {jumps} would jump): treat those results with caution."
            )
        else:
            parts.append(
                f"All {n_runs} analyses stay within the model (no sliding at friction {o['friction']:g}, "
                "no jumping)."
            )
        head.append(
            f"{n_out} of {n_runs} analyses outside the model" if n_out else "all analyses within the model"
        )
        out.append({"object": name, "text": " ".join(parts), "headline": f"{name}: " + "; ".join(head) + "."})
    return out


def _none(cs: list[dict]) -> dict | None:
    return next((c for c in cs if c["kind"] == "none"), None)


def _median(c: dict | None) -> float | None:
    return None if c is None else c["fragility"]["median_g"]


def summary_table(summary: dict[str, Any]) -> pd.DataFrame:
    """The report's summary: one row per object and isolation case."""
    cap = summary.get("capacity_m")
    rows = []
    for c in summary["cases"]:
        f = c["fragility"]
        row = {
            "object": c["object"],
            "isolation": c["isolation"],
            "median overturning PGA [g]": f["median_g"] if f["median_g"] is not None else f["note"],
            "beta [-]": f["beta"],
        }
        for d in c["design_levels"]:
            x = d["pga_g"]
            row[f"P(overturn) at {x:g} g"] = pct(d["p_overturn"])
            row[f"P(uplift) at {x:g} g"] = pct(d["p_uplift"])
            if c["kind"] != "none":
                row[f"displacement p84 at {x:g} g [m]"] = d["disp_p84_m"]
                if cap:
                    row[f"records beyond {cap:g} m"] = pct(d["frac_exceed_capacity"])
        v = c["validity"]
        row["outside the model"] = f"{v['n_outside_model']} of {v['n_runs']}"
        rows.append(row)
    return pd.DataFrame(rows)
