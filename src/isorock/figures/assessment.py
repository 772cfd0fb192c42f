"""Figures of the assessment of an object (``/assessment`` of the store): fragility curves, isolator
displacement demand, and the isolation design chart."""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from ..store import Store
from .style import _colors, _figure, _new_figure, _save, _Skip

__all__ = ["fig_fragility", "fig_displacement", "fig_design"]

#: colour of the non-isolated case in the assessment figures (then one colour per isolated case)
_NONE_COLOR = "0.2"


def _tables(h5: Any, *names: str) -> list:
    store = h5 if isinstance(h5, Store) else Store(h5)
    out = []
    for n in names:
        df = store.table(f"assessment/{n}")
        if df is None:
            raise _Skip(f"no /assessment/{n} in the store")
        out.append(df)
    return out


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


@_figure("assessment fragility")
def fig_fragility(h5: Any, obj: str, out_path: str | os.PathLike) -> Path | None:
    """P(overturn) and P(uplift) against the PGA of one object, one curve per isolation case: the
    fitted lognormal (lines) and the fraction of records at each stripe (points)."""
    from scipy.stats import norm

    objs, stripes, frag, design = _tables(h5, "objects", "stripes", "fragility", "design_levels")
    o = objs[objs["object"] == obj]
    if o.empty:
        raise _Skip(f"object {obj!r} not assessed")
    st = stripes[stripes["object"] == obj]
    fr = frag[frag["object"] == obj]
    cases = list(dict.fromkeys(st["case"]))
    kinds = dict(zip(st["case"], st["isolation"], strict=True))
    colors = _case_colors(cases, kinds)
    fig = _new_figure(7.2, 3.4)
    axs = fig.subplots(1, 2, sharey=True)
    xmax = float(st["pga_g"].max()) * 1.15
    x = np.linspace(1e-3, xmax, 300)
    for ax, damage, col in ((axs[0], "overturn", "n_overturn"), (axs[1], "uplift", "n_uplift")):
        for c in cases:
            s = st[st["case"] == c]
            f = fr[(fr["case"] == c) & (fr["damage"] == damage)].iloc[0]
            ax.plot(s["pga_g"], s[col] / s["n_records"], "o", color=colors[c], ms=4)
            if math.isfinite(f["median_g"]):
                p = norm.cdf(np.log(x / f["median_g"]) / f["beta"])
                lab = f"{c}: median {f['median_g']:.2g} g, beta {f['beta']:.2f}"
            else:
                p = np.full_like(x, 0.0 if f["n_damaged"] == 0 else 1.0)
                lab = f"{c}: {f['note'].split(':')[0]}"
            ax.plot(x, p, "-", color=colors[c], lw=1.5, label=lab)
        for xd in design[design["object"] == obj]["pga_g"].unique():
            ax.axvline(xd, color="0.5", ls="--", lw=0.8)
        ax.set_xlim(0, xmax)
        ax.set_ylim(-0.02, 1.02)
        ax.set_xlabel("PGA [g]")
        ax.set_title(f"P({damage})")
        ax.legend(loc="upper left", fontsize=7)
    axs[0].set_ylabel("probability [-]")
    fig.suptitle(
        _object_title(o.iloc[0].to_dict())
        + "\nfragility: lines fitted (lognormal, MLE), points = fraction of "
        "records per stripe; dashed: design level",
        fontsize=9,
    )
    return _save(fig, out_path)


@_figure("assessment displacement")
def fig_displacement(h5: Any, obj: str, out_path: str | os.PathLike) -> Path | None:
    """Peak isolator displacement against the PGA (median and 84th percentile over the records) for
    every isolated case of one object, with the displacement capacity."""
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
    fig = _new_figure(4.6, 3.4)
    ax = fig.subplots()
    for c in cases:
        s = st[st["case"] == c]
        ax.plot(s["pga_g"], s["disp_p84_m"], "-o", color=colors[c], ms=3, label=f"{c}: 84th percentile")
        ax.plot(s["pga_g"], s["disp_median_m"], "--", color=colors[c], lw=1, label=f"{c}: median")
    if capacity:
        ax.axhline(capacity, color="#e8251f", lw=1.2, label=f"capacity {capacity:g} m")
    ax.set_xlabel("PGA [g]")
    ax.set_ylabel("peak isolator displacement [m]")
    ax.set_xlim(0, None)
    ax.set_ylim(0, None)
    ax.legend(fontsize=7)
    ax.set_title(f"{obj}: isolator displacement demand", fontsize=9)
    return _save(fig, out_path)


@_figure("assessment design")
def fig_design(h5: Any, obj: str, out_path: str | os.PathLike) -> Path | None:
    """Isolation design chart of one object: P(overturn) at the (first) design level over the grid of
    isolators, the capacity line (84th-percentile displacement = capacity) and the recommended one."""
    import json

    from matplotlib.colors import Normalize

    (design,) = _tables(h5, "design")
    d = design[design["object"] == obj]
    if d.empty:
        raise _Skip(f"no design search for object {obj!r}")
    xd = float(d["design_g"].min())
    d = d[d["design_g"] == xd]
    linear = d["isolation"].iloc[0] == "linear"
    xcol, ycol = ("Tb_s", "xi_b") if linear else ("mu_b", "R_b_m")
    xs, ys = np.sort(d[xcol].unique()), np.sort(d[ycol].unique())
    P = np.full((ys.size, xs.size), np.nan)
    D = np.full((ys.size, xs.size), np.nan)
    for _, r in d.iterrows():
        i, j = int(np.searchsorted(ys, r[ycol])), int(np.searchsorted(xs, r[xcol]))
        P[i, j], D[i, j] = r["p_overturn"], r["disp_p84_m"]
    store = h5 if isinstance(h5, Store) else Store(h5)
    cfg = json.loads(str(store.root_attrs.get("config_json", "{}")) or "{}")
    capacity = (cfg.get("assessment") or {}).get("capacity_m")
    fig = _new_figure(5.2, 3.8)
    ax = fig.subplots()
    pc = ax.pcolormesh(
        xs, ys, P, shading="nearest", cmap="Reds", norm=Normalize(0.0, max(0.05, np.nanmax(P)))
    )
    fig.colorbar(pc, ax=ax, label=f"P(overturn) at {xd:g} g [-]")
    if xs.size > 1 and ys.size > 1 and np.nanmax(P) > 0:
        cs = ax.contour(xs, ys, P, colors="0.25", linewidths=0.8)
        ax.clabel(cs, fontsize=7, fmt="%.2f")
    if capacity and xs.size > 1 and ys.size > 1 and np.nanmin(D) < capacity < np.nanmax(D):
        ax.contour(xs, ys, D, levels=[capacity], colors="#1f4fe8", linewidths=2.0)
        ax.plot([], [], color="#1f4fe8", lw=2, label=f"84th-pct displacement = capacity {capacity:g} m")
    over = d[~d["within_capacity"].astype(bool)]
    ax.plot(over[xcol], over[ycol], "x", color="0.3", ms=5, label="beyond the capacity")
    best = d[d["rank"] == 1]
    if not best.empty:
        b = best.iloc[0]
        ax.plot(b[xcol], b[ycol], "*", color="#2ecc40", mec="k", ms=16, label="recommended")
    ax.set_ylim(bottom=max(ax.get_ylim()[0], 0.0))
    ax.set_xlim(left=max(ax.get_xlim()[0], 0.0))
    ax.set_xlabel("isolation period $T_b$ [s]" if linear else r"friction $\mu_b$ [-]")
    ax.set_ylabel(r"damping $\xi_b$ [-]" if linear else r"radius $R_b$ [m]")
    ax.legend(fontsize=7, loc="upper right")
    ax.set_title(f"{obj}: isolation design ({'linear' if linear else 'FP'} isolators)", fontsize=9)
    return _save(fig, out_path)
