"""Figures of the assessment of an object (``/assessment`` of the store): fragility curves, isolator
displacement demand, and the isolation design chart."""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from isorock.figures.style import REGIME_COLORS, _colors, _figure, _new_figure, _save, _Skip
from isorock.store import Store

__all__ = ["fig_fragility", "fig_modes", "fig_displacement", "fig_design", "fig_sliding"]

#: colour of the non-isolated case in the assessment figures (then one colour per isolated case)
_NONE_COLOR = "0.2"
#: colour of a slide beyond the allowance (the paper's code has none for sliding: red is overturning)
_SLIDE_COLOR = "#8e44ad"


def _tables(h5: Any, *names: str) -> list:
    store = h5 if isinstance(h5, Store) else Store(h5)
    out = []
    for n in names:
        df = store.table(f"assessment/{n}")
        if df is None:
            raise _Skip(f"no /assessment/{n} in the store")
        out.append(df)
    return out


def _axis(h5: Any, what: str = "") -> str:
    """The x label of the stripes' measure: "SA(1.0) RotD50 [g]", "stripe PGA (analysed component) [g]"
    (a store of layout 6 or older: PGA of the analysed component)."""
    store = h5 if isinstance(h5, Store) else Store(h5)
    m = store.table("assessment/measure")
    imt, comp, unit = (
        ("PGA", "analysed", "g")
        if m is None
        else (str(m["imt"].iloc[0]), str(m["component"].iloc[0]), str(m["unit"].iloc[0]))
    )
    name = f"{imt} (analysed component)" if comp == "analysed" else f"{imt} {comp}"
    return f"{what}{name} [{unit}]"


def _case_colors(cases: list[str], kinds: dict[str, str]) -> dict[str, Any]:
    iso = [c for c in cases if kinds.get(c) != "none"]
    cols = dict(zip(iso, _colors(len(iso)), strict=True))
    return {c: (_NONE_COLOR if kinds.get(c) == "none" else cols[c]) for c in cases}


def _object_title(obj: dict) -> str:
    if obj.get("height_m") and math.isfinite(obj["height_m"]):
        size = f"{obj['height_m']:g} m x {obj['width_m']:g} m"
    else:
        size = f"R = {obj['R_m']:.3g} m"
    return f"{obj['object']}: {size}, lambda = {obj['lambda_']:.3g}, friction {obj['friction']:g}"


def _cp(k: np.ndarray, n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two-sided 95 % Clopper-Pearson bounds of the fractions ``k / n``."""
    from isorock.assessment.fragility import clopper_pearson

    b = np.array(
        [clopper_pearson(int(a), int(m)) if m else (np.nan, np.nan) for a, m in zip(k, n, strict=True)]
    )
    return b[:, 0], b[:, 1]


_PANELS = (("overturn", "n_overturn", "P(overturn)"), ("failure", "n_failure", "P(failure)"),
           ("uplift", "n_uplift", "P(uplift)"))  # fmt: skip


@_figure("assessment fragility")
def fig_fragility(h5: Any, obj: str, out_path: str | os.PathLike) -> Path | None:
    """P(overturn), P(failure) (overturn or isolator displacement beyond the capacity) and P(uplift)
    against the stripes' measure of one object, one colour per isolation case: the fitted lognormal
    (line) with its 95 % bootstrap band (shading), and the fraction of records at each stripe (points)
    with its exact binomial 95 % interval (bars). A case whose fit is not estimable has points only."""
    objs, stripes, frag, design = _tables(h5, "objects", "stripes", "fragility", "design_levels")
    store = h5 if isinstance(h5, Store) else Store(h5)
    band = store.table("assessment/fragility_band")
    o = objs[objs["object"] == obj]
    if o.empty:
        raise _Skip(f"object {obj!r} not assessed")
    st = stripes[stripes["object"] == obj]
    fr = frag[frag["object"] == obj]
    cases = list(dict.fromkeys(st["case"]))
    kinds = dict(zip(st["case"], st["isolation"], strict=True))
    colors = _case_colors(cases, kinds)
    panels = _PANELS
    if "mode" in o and str(o["mode"].iloc[0]) == "sliding":
        # an object that slides never rocks: failure only, which is a slide beyond the allowance
        allow = float(o["slide_allow_m"].iloc[0])
        panels = (("failure", "n_failure", f"P(failure: slide beyond {allow:g} m, or beyond the capacity)"),)
    fig = _new_figure(10.0 if len(panels) == 3 else 5.6, 3.9)
    axs = np.atleast_1d(fig.subplots(1, len(panels), sharey=True))
    xmax = float(st["level"].max()) * 1.15
    for ax, (damage, col, title) in zip(axs, panels, strict=True):
        for k, c in enumerate(cases):
            s = st[st["case"] == c]
            f = fr[(fr["case"] == c) & (fr["damage"] == damage)].iloc[0]
            n, z = s["n_records"].to_numpy(), s[col].to_numpy()
            lo, hi = _cp(z, n)
            dx = (k - (len(cases) - 1) / 2) * 0.008 * xmax  # side by side, not on top of each other
            frac = z / np.maximum(n, 1)
            ax.errorbar(s["level"] + dx, frac, yerr=[frac - lo, hi - frac], fmt="o", color=colors[c], ms=3.5,
                        lw=0.8, capsize=2)  # fmt: skip
            if bool(f["estimable"]) and band is not None:
                b = band[(band["object"] == obj) & (band["case"] == c) & (band["damage"] == damage)]
                ax.fill_between(b["level"], b["p_lo"], b["p_hi"], color=colors[c], alpha=0.18, lw=0)
                ax.plot(b["level"], b["p"], "-", color=colors[c], lw=1.5,
                        label=f"{c}: median {f['median_g']:.2g} g ({f['median_ci95_g_lo']:.2g}-"
                        f"{f['median_ci95_g_hi']:.2g}), beta {f['beta']:.2f}")  # fmt: skip
            else:
                ax.plot(
                    [],
                    [],
                    "o",
                    color=colors[c],
                    label=f"{c}: not estimable ({int(z.sum())} of {int(n.sum())})",
                )
        for xd in design[design["object"] == obj]["level"].unique():
            ax.axvline(xd, color="0.5", ls="--", lw=0.8)
        ax.set_xlim(0, xmax)
        ax.set_ylim(-0.03, 1.03)
        ax.set_xlabel(_axis(h5))
        ax.set_title(title, fontsize=9)
        ax.legend(loc="best", fontsize=6.5)
    axs[0].set_ylabel("probability [-]")
    sep = "; " if len(panels) == 3 else "\n"  # one panel: the legend of the lines on lines of its own
    fig.suptitle(
        _object_title(o.iloc[0].to_dict())
        + "\nlines: lognormal fit (MLE) with its 95 % bootstrap band"
        + sep
        + "points: fraction of records per stripe with exact 95 % bars; dashed: design level",
        fontsize=8.5,
    )
    return _save(fig, out_path)


@_figure("assessment modes")
def fig_modes(h5: Any, obj: str, out_path: str | os.PathLike) -> Path | None:
    """The failure modes per stripe, one panel per isolation case: records that overturn, that move the
    isolator beyond its capacity without overturning, that stay safe; and, hatched, the runs outside
    the model (the object would slide or jump)."""
    (stripes,) = _tables(h5, "stripes")
    st = stripes[stripes["object"] == obj]
    if st.empty:
        raise _Skip(f"object {obj!r} not assessed")
    cases = list(dict.fromkeys(st["case"]))
    fig = _new_figure(3.0 * len(cases) + 0.8, 3.3)
    axs = np.atleast_1d(fig.subplots(1, len(cases), sharey=True))
    for ax, c in zip(axs, cases, strict=True):
        s = st[st["case"] == c]
        x = np.arange(len(s))
        n = s["n_records"].to_numpy()
        ov = s["n_overturn"].to_numpy()
        slid = s["n_slides_beyond"].fillna(0).to_numpy() if "n_slides_beyond" in s else np.zeros_like(ov)
        beyond = s["n_failure"].to_numpy() - ov - slid
        safe = n - ov - slid - beyond
        ax.bar(x, ov, color=REGIME_COLORS[2], label="overturn")
        if slid.any():
            ax.bar(x, slid, bottom=ov, color=_SLIDE_COLOR, label="slid beyond the allowance")
        ax.bar(x, beyond, bottom=ov + slid, color="#f39c12", label="beyond the capacity (only)")
        ax.bar(x, safe, bottom=ov + slid + beyond, color=REGIME_COLORS[1], alpha=0.6, label="no failure")
        ax.bar(
            x,
            s["n_outside_model"],
            fill=False,
            hatch="///",
            edgecolor="0.2",
            lw=0.6,
            label="outside the model",
        )
        ax.set_xticks(x, [f"{v:g}" for v in s["level"]], fontsize=7)
        ax.set_xlabel(_axis(h5, "stripe "))
        ax.set_title(f"{c} ({s['isolation'].iloc[0]})", fontsize=9)
    axs[0].set_ylabel("records [-]")
    axs[-1].legend(fontsize=6.5, loc="upper left")
    fig.suptitle(f"{obj}: failure modes per stripe", fontsize=9)
    return _save(fig, out_path)


@_figure("assessment displacement")
def fig_displacement(h5: Any, obj: str, out_path: str | os.PathLike) -> Path | None:
    """Peak isolator displacement against the stripes' measure (median, mean and 84th percentile over the
    records) for every isolated case of one object, the codes' statistic at the MCE level with its
    bootstrap interval (what eligibility is judged on), and the displacement capacity."""
    import json

    objs, stripes = _tables(h5, "objects", "stripes")
    st = stripes[(stripes["object"] == obj) & (stripes["isolation"] != "none")]
    if st.empty:
        raise _Skip(f"no isolated case for object {obj!r}")
    store = h5 if isinstance(h5, Store) else Store(h5)
    cfg = json.loads(str(store.root_attrs.get("config_json", "{}")) or "{}")
    capacity = (cfg.get("assessment") or {}).get("capacity_m")
    cases = list(dict.fromkeys(st["case"]))
    colors = _case_colors(cases, dict(zip(st["case"], st["isolation"], strict=True)))
    fig = _new_figure(5.2, 3.8)
    ax = fig.subplots()
    dl = store.table("assessment/design_levels")
    for c in cases:
        s = st[st["case"] == c]
        ax.plot(s["level"], s["disp_p84_m"], "-o", color=colors[c], ms=3, label=f"{c}: 84th percentile")
        ax.plot(s["level"], s["disp_median_m"], "--", color=colors[c], lw=1, label=f"{c}: median")
        ax.plot(s["level"], s["disp_mean_m"], ":", color=colors[c], lw=1.2, label=f"{c}: mean")
        m = dl[(dl["object"] == obj) & (dl["case"] == c)] if dl is not None else None
        if m is not None and len(m) and "disp_mce_ci95_m_lo" in m:
            lo, hi = m["disp_mce_ci95_m_lo"].to_numpy(), m["disp_mce_ci95_m_hi"].to_numpy()
            mid = m["disp_mce_m"].to_numpy()
            ax.errorbar(m["mce_g"], mid, yerr=[mid - lo, hi - mid], fmt="D", color=colors[c], ms=4, capsize=3,
                        label=f"{c}: at the MCE, the codes' statistic (95 %)")  # fmt: skip
    if capacity:
        gx = float((cfg.get("assessment") or {}).get("gamma_x", 1.2))
        ax.axhline(capacity, color="#e8251f", lw=1.2, label=f"capacity {capacity:g} m")
        if gx != 1.0:  # the analysed displacement meets capacity / gamma_x (EN 1998-1 §10.3(2))
            ax.axhline(capacity / gx, color="#e8251f", lw=1.0, ls="--",
                       label=f"capacity / gamma_x = {capacity / gx:.3g} m")  # fmt: skip
    ax.set_xlabel(_axis(h5))
    ax.set_ylabel("peak isolator displacement [m]")
    ax.set_xlim(0, None)
    ax.set_ylim(0, None)
    ax.legend(fontsize=6.5)
    ax.set_title(f"{obj}: isolator displacement demand", fontsize=9)
    return _save(fig, out_path)


@_figure("assessment design")
def fig_design(h5: Any, obj: str, out_path: str | os.PathLike) -> Path | None:
    """The isolation design of one object at its (first) design level: left, the grid's estimate (the
    probability of failure, or its annual frequency with a hazard curve) over the two grid axes, the
    configured grid outlined where the search extended it, the isolators beyond the capacity at the MCE
    crossed out, the recommended one starred; right, the paired evidence: each candidate's difference
    from the fixed base, resample by resample, with its 95 % interval and the share of resamples in
    which it is lower."""
    import json

    (design,) = _tables(h5, "design")
    d = design[design["object"] == obj]
    if d.empty:
        raise _Skip(f"no design search for object {obj!r}")
    xd = float(d["design_g"].min())
    d = d[d["design_g"] == xd]
    store = h5 if isinstance(h5, Store) else Store(h5)
    vt = store.table("assessment/verdicts")
    v = (
        {}
        if vt is None
        else next((r for r in vt.to_dict("records") if r["object"] == obj and float(r["design_g"]) == xd), {})
    )
    what = str(d["ranked_by"].iloc[0])
    grid = d[d["source"] == "grid"]
    fig = _new_figure(10.5 if not grid.empty else 5.5, 4.4)
    axs = fig.subplots(1, 2 if not grid.empty else 1, squeeze=False)[0]
    rec = d[d["recommended"].astype(bool)]
    if not grid.empty:
        _design_grid(axs[0], grid, rec, what, xd, json.loads(v.get("grid") or "{}"))
    _candidates(axs[-1], d, what)
    verdict = {
        "isolate": "isolate",
        "fixed_base": "keep the fixed base",
        "restrain": "restrain: no base is safe",
        "inconclusive": "safety not shown",
    }
    head = f" - verdict: {verdict.get(v.get('verdict', ''), v.get('verdict', ''))}" if v else ""
    import textwrap

    level = _axis(h5).rsplit(" [", 1)  # "SA(1.0) RotD50", "g]"
    title = f"{obj}: isolation design at {xd:g} {level[1].rstrip(']')} {level[0]} (ranked by {what}){head}"
    fig.suptitle("\n".join(textwrap.wrap(title, 110 if not grid.empty else 60)), fontsize=9)
    return _save(fig, out_path)


def _design_grid(ax: Any, grid: Any, rec: Any, what: str, xd: float, info: dict) -> None:
    from matplotlib.colors import Normalize
    from matplotlib.patches import Rectangle

    linear = grid["isolation"].iloc[0] == "linear"
    xcol, ycol = ("Tb_s", "xi_b") if linear else ("mu_b", "R_b_m")
    xs, ys = np.sort(grid[xcol].unique()), np.sort(grid[ycol].unique())
    P = np.full((ys.size, xs.size), np.nan)
    for _, r in grid.iterrows():
        P[int(np.searchsorted(ys, r[ycol])), int(np.searchsorted(xs, r[xcol]))] = r["estimate"]
    top = np.nanmax(P) if np.isfinite(P).any() else 1.0
    pc = ax.pcolormesh(xs, ys, P, shading="nearest", cmap="Reds", norm=Normalize(0.0, max(top, 1e-12)))
    ax.figure.colorbar(
        pc,
        ax=ax,
        label="annual frequency of failure [1/yr]" if "annual" in what else f"P(failure) at {xd:g} g [-]",
    )
    over = grid[~grid["within_capacity"].astype(bool)]
    ax.plot(over[xcol], over[ycol], "x", color="0.15", ms=7, mew=1.5, label="beyond the capacity at the MCE")
    r = rec[rec["source"] == "grid"]
    if not r.empty:
        ax.plot(r[xcol], r[ycol], "*", color="#2ecc40", mec="k", ms=16, label="recommended", clip_on=False)
    conf = info.get("configured") or {}
    if info.get("extended") and conf.get(xcol) and conf.get(ycol):
        cx, cy = conf[xcol], conf[ycol]
        dx = 0.5 * (xs[1] - xs[0]) if xs.size > 1 else 0.1
        dy = 0.5 * (ys[1] - ys[0]) if ys.size > 1 else 0.01
        ax.add_patch(Rectangle((min(cx) - dx, min(cy) - dy), max(cx) - min(cx) + 2 * dx,
                               max(cy) - min(cy) + 2 * dy, fill=False, ls="--", lw=1.2, ec="0.2",
                               label="the configured grid (extended by the search)"))  # fmt: skip
    ax.set_xlabel("isolation period $T_b$ [s]" if linear else r"friction $\mu_b$ [-]")
    ax.set_ylabel(r"damping $\xi_b$ [-]" if linear else r"radius $R_b$ [m]")
    ax.margins(0.08)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, frameon=False,
              markerscale=0.6)  # fmt: skip
    ax.set_title("the design grid", fontsize=9)


def _label(r: Any) -> str:
    lab = "no isolation" if r.isolation == "none" else ("grid" if r.source == "grid" else r.name)
    if r.isolation == "linear":
        lab += f" (Tb {r.Tb_s:.3g} s, xi {r.xi_b:.2g})"
    elif r.isolation == "fp":
        lab += f" (mu {r.mu_b:.3g}, R {r.R_b_m:.3g} m)"
    if bool(r.recommended):
        return lab + " - recommended"
    if not bool(r.within_capacity):
        return lab + " - beyond capacity"
    return lab


def _candidates(ax: Any, d: Any, what: str) -> None:
    """The paired evidence: each candidate's estimate minus the fixed base's, with the 95 % interval
    of that difference over the resamples, and the share of resamples in which it is lower."""
    grid = d[d["source"] == "grid"].copy()
    grid["_eligible"] = grid["rank"] > 0
    grid = grid.sort_values(["_eligible", "rank", "estimate"], ascending=[False, True, True]).head(5)
    rec = d[(d["source"] == "grid") & d["recommended"].astype(bool)]
    if not rec.empty and rec.iloc[0]["name"] not in set(grid["name"]):
        import pandas as pd

        grid = pd.concat([grid, rec.iloc[:1]])
    rows = [*d[d["source"] == "case"].itertuples(), *grid.itertuples()]
    rate = "annual" in what
    k = 1.0 if rate else 100.0
    for i, r in enumerate(rows):
        lo, hi, mid = r.vs_floor_difference_ci95_lo, r.vs_floor_difference_ci95_hi, r.vs_floor_difference
        color = "#1f77b4" if r.source == "case" else "#9467bd"
        if np.isfinite(lo) and np.isfinite(hi):
            ax.plot([k * lo, k * hi], [i, i], "-", color=color, lw=2)
        marker = "*" if bool(r.recommended) else ("o" if bool(r.within_capacity) else "x")
        ax.plot(k * mid, i, marker, color="#2ecc40" if bool(r.recommended) else color,
                mec="k" if bool(r.recommended) else color, ms=14 if bool(r.recommended) else 6)  # fmt: skip
        p = r.vs_floor_p_better
        if np.isfinite(p):
            from isorock.assessment.formats import share

            ax.annotate(f"lower in {share(p)}", (1.0, i), xycoords=("axes fraction", "data"),
                        xytext=(4, 0), textcoords="offset points", va="center", fontsize=6.5)  # fmt: skip
    ax.axvline(0.0, color=_NONE_COLOR, lw=1.2, ls="--")
    ax.set_yticks(range(len(rows)), [_label(r) for r in rows], fontsize=7)
    ax.invert_yaxis()
    unit = "[1/yr]" if rate else "[percentage points]"
    ax.set_xlabel(f"{'annual frequency' if rate else 'P(failure)'} minus the fixed base's {unit}")
    ax.set_title("minus the fixed base, paired over resamples (95 %);\nleft of the dashed line: better",
                 fontsize=8.5)  # fmt: skip
    ax.grid(axis="x", alpha=0.3)
    from matplotlib.ticker import MaxNLocator

    ax.xaxis.set_major_locator(MaxNLocator(5))


@_figure("assessment sliding")
def fig_sliding(h5: Any, obj: str, out_path: str | os.PathLike) -> Path | None:
    """A sliding object's peak slip on its base against the stripes' measure, one panel per isolation
    case: every record's run (dots), the median and 84th percentile over the records, and the
    allowance; the count beyond it above each stripe. Skipped for an object that rocks."""
    objs, runs, stripes = _tables(h5, "objects", "runs", "stripes")
    kinds = dict(zip(stripes["case"], stripes["isolation"], strict=False))
    o = objs[objs["object"] == obj]
    if o.empty or "mode" not in o or str(o["mode"].iloc[0]) != "sliding":
        raise _Skip(f"object {obj!r} does not slide")
    allow = float(o["slide_allow_m"].iloc[0])
    r = runs[(runs["object"] == obj) & (runs["stripe"].astype(bool))]
    cases = list(dict.fromkeys(r["case"]))
    fig = _new_figure(3.0 * len(cases) + 0.8, 3.4)
    axs = np.atleast_1d(fig.subplots(1, len(cases), sharey=True))
    floor = 1e-4  # 0.1 mm: slips below it are drawn on the floor of the logarithmic axis
    top = max(float(np.nanmax(r["sliding_peak_m"])), allow) * 2.0
    for ax, c in zip(axs, cases, strict=True):
        s = r[r["case"] == c]
        x = s["level"].to_numpy(dtype=float)
        y = s["sliding_peak_m"].to_numpy(dtype=float)
        ax.scatter(x, np.maximum(y, floor), s=6, color="0.45", alpha=0.6, lw=0, label="one record")
        g = s.groupby("level")["sliding_peak_m"]
        lv = np.array(sorted(g.groups))
        ax.plot(lv, np.maximum(g.median().to_numpy(), floor), "-o", color=_SLIDE_COLOR, ms=3, label="median")
        ax.plot(lv, np.maximum(g.quantile(0.84).to_numpy(), floor), "--", color=_SLIDE_COLOR, lw=1,
                label="84th percentile")  # fmt: skip
        ax.axhline(allow, color="0.1", lw=1.2, ls="--", label=f"allowance {allow:g} m")
        for xv, grp in s.groupby("level"):
            k = int((grp["sliding_peak_m"] > allow).sum())
            ax.text(xv, top * 0.75, f"{k}/{len(grp)}", ha="center", fontsize=6, color=_SLIDE_COLOR)
        ax.set_yscale("log")
        ax.set_ylim(floor * 0.8, top)
        ax.set_xlabel(_axis(h5, "stripe "))
        ax.set_title(f"{c} ({kinds.get(c, '?')})", fontsize=9)
    axs[0].set_ylabel("peak slip on the base [m] (0.1 mm floor)")
    axs[-1].legend(fontsize=6.5, loc="lower right")
    fig.suptitle(
        f"{obj}: sliding (friction {float(o['friction'].iloc[0]):g} < tan alpha "
        f"{float(o['tan_alpha'].iloc[0]):.3g}); numbers: records beyond the allowance",
        fontsize=9,
    )
    return _save(fig, out_path)
