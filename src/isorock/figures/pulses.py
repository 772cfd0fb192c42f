"""The paper's pulse figures: Fig 3 (impact coefficients), Figs 4, 5, 7 (minimum overturning
amplitude under pulses) and Fig 6 (regime maps under pulses)."""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from isorock.figures.style import (
    _LABEL_AMIN,
    _LABEL_LAM,
    _LABEL_OMEGA,
    _LABEL_R,
    _LABEL_TB,
    _LABEL_XI,
    _SHAPES,
    SHAPE_NAMES,
    _axes_grid,
    _close,
    _colors,
    _draw_map,
    _figure,
    _isclose_col,
    _iso_label,
    _log_y,
    _map_iso_label,
    _new_figure,
    _num,
    _regime_legend,
    _save,
    _Skip,
)
from isorock.physics.model import housner_restitution
from isorock.store import RESTITUTION_RHOS, Store, StoreNotFound, restitution_table

__all__ = ["fig_3", "fig_4", "fig_5", "fig_6", "fig_7"]


# ============================================================================================ Fig 3
@_figure("Fig. 3")
def fig_3(
    h5: Any, out_path: str | os.PathLike, *, rhos: Sequence[float] | None = None, lam_max: float = 10.0
) -> Path | None:
    """Fig. 3: angular restitution ``eps`` and normalised ``beta1/h`` against slenderness for several ``rho``.

    Parameters
    ----------
    h5 : path-like or h5py object
        Store; its ``/pulses/restitution`` table is used when present, else the same table computed
        (:func:`isorock.store.restitution_table`: the closed forms of paper Eqs. 29-30, no analysis
        needed). May name a missing file.
    out_path : path-like
        Image to write.
    rhos : sequence of float, optional
        Mass ratios ``m/m_b`` [-] to draw (default: those of the table, or 0.1, 0.25, 0.5, 1, 2).
    lam_max : float
        Largest slenderness drawn [-].

    Returns
    -------
    Path or None
        The image written.
    """
    try:
        df = Store(h5).table("pulses/restitution")
    except StoreNotFound:
        df = None
    source = "store table /pulses/restitution"
    if df is None or not {"lambda_", "rho", "eps", "beta1_over_h"} <= set(df.columns):
        source = "closed forms (paper Eqs. 29-30)"
        df = restitution_table(rhos or RESTITUTION_RHOS, np.linspace(1.0, lam_max, 181))
    df = df[df["lambda_"] <= lam_max + 1e-9]
    values = sorted(df["rho"].unique()) if rhos is None else list(rhos)
    fig = _new_figure(9.5, 3.9)
    ax1, ax2 = fig.subplots(1, 2)
    for c, rho in zip(_colors(len(values)), values, strict=True):
        d = df[_isclose_col(df["rho"], rho)].sort_values("lambda_")
        if d.empty:
            continue
        lam_min = math.sqrt(2 * (rho + 1) / (rho + 4))
        d = d[d["lambda_"] > lam_min]
        ax1.plot(d["lambda_"], d["eps"], color=c, label=rf"$\rho$ = {rho:g}")
        ax2.plot(d["lambda_"], d["beta1_over_h"], color=c, label=rf"$\rho$ = {rho:g}")
    lam = np.linspace(1.0, lam_max, 181)
    ax1.plot(
        lam,
        [housner_restitution(math.atan(1.0 / x)) for x in lam],
        "k--",
        lw=1,
        label=r"Housner, rigid base ($\rho \to 0$)",
    )
    ax1.set_xlabel(_LABEL_LAM)
    ax1.set_ylabel(r"angular restitution $\varepsilon = \dot\theta^+/\dot\theta^-$ [-]")
    ax1.set_title(r"(a) coefficient of angular restitution $\varepsilon$ (Eq. 29)")
    ax1.set_ylim(top=1.0)
    ax1.legend(loc="lower right")
    ax2.set_xlabel(_LABEL_LAM)
    ax2.set_ylabel(r"$\bar\beta_1 = \beta_1/h$ [-]")
    ax2.set_title(r"(b) coefficient of linear restitution $\bar\beta_1 = \beta_1/h$ (Eq. 30)")
    ax2.set_ylim(bottom=0.0)
    ax2.legend(loc="upper right")
    fig.suptitle(f"Fig. 3 - impact coefficients against slenderness ({source})")
    return _save(fig, out_path)


# ============================================================================================ Figs 4, 7
def _pulse_tables(store: Store, what: str):
    df_r = store.table("pulses/overturn_R")
    df_w = store.table("pulses/overturn_omega")
    if df_r is None and df_w is None:
        raise _Skip(
            f"{what}: no /pulses/overturn_R or /pulses/overturn_omega table in {store.path} "
            "(rule pulse_overturn)"
        )
    return df_r, df_w


def _pick_case(df, iso: str, prefer: dict[str, float] | None = None):
    """Rows of one isolation case of kind ``iso`` (the one matching ``prefer``, else the first by name)."""
    d = df[df["isolation"] == iso]
    if d.empty or iso == "none":
        return d
    if "case" not in d.columns:
        return d
    names = list(dict.fromkeys(d["case"]))
    if prefer:
        for n in names:
            r = d[d["case"] == n].iloc[0]
            if all(_close(_num(r.get(k)), v, 1e-3) for k, v in prefer.items()):
                return d[d["case"] == n]
    return d[d["case"] == names[0]]


def _fixed_text(df, iso_rows) -> str:
    parts = []
    if "lambda_" in df.columns and df["lambda_"].nunique() == 1:
        parts.append(rf"$\lambda$ = {df['lambda_'].iloc[0]:g}")
    if iso_rows is not None and len(iso_rows):
        r = iso_rows.iloc[0]
        if math.isfinite(_num(r.get("rho"))):
            parts.append(rf"$\rho$ = {_num(r['rho']):g}")
    return ", ".join(parts)


def _curves(
    ax,
    df,
    group_col: str,
    x_col: str,
    styles: Sequence[tuple[str, Any, str]],
    group_label: Callable[[float], str],
) -> list:
    """One line per value of ``group_col`` and per (iso, rows, linestyle) style; colour = group value."""
    groups = sorted(set().union(*[set(rows[group_col].round(9)) for _, rows, _ in styles if len(rows)]))
    handles = []
    from matplotlib.lines import Line2D

    for c, gv in zip(_colors(len(groups)), groups, strict=True):
        for _, rows, ls in styles:
            d = rows[np.isclose(rows[group_col].astype(float), gv)].sort_values(x_col)
            if d.empty:
                continue
            ax.plot(d[x_col], d["min_overturn_over_tan_alpha"], ls=ls, color=c, marker=".", ms=3, lw=1.3)
        handles.append(Line2D([], [], color=c, lw=2, label=group_label(gv)))
    return handles


def _overturn_panels(
    store: Store,
    out_path,
    *,
    shapes: Sequence[str],
    isos: Sequence[str],
    prefer: dict[str, dict[str, float]],
    title: str,
    logy: bool,
    style_names: dict[str, str],
    what: str,
) -> Path:
    from matplotlib.lines import Line2D

    df_r, df_w = _pulse_tables(store, what)
    rows_done = []
    for shape in shapes:
        have = [
            (df is not None and not df[(df["pulse"] == shape) & df["isolation"].isin(isos)].empty)
            for df in (df_r, df_w)
        ]
        if any(have):
            rows_done.append(shape)
    if not rows_done:
        raise _Skip(
            f"{what}: the pulse tables hold no rows for {', '.join(shapes)} with isolation {' / '.join(isos)}"
        )
    fig = _new_figure(10.0, 3.3 * len(rows_done) + 0.6)
    axs = _axes_grid(fig, len(rows_done), 2)
    linestyles = ["-", "--", "-.", ":"]
    fixed = ""
    for i, shape in enumerate(rows_done):
        for j, (df, series, x_col, group_col, xlabel, glab) in enumerate(
            (
                (df_r, "td", "R_m", "td_s", _LABEL_R, lambda v: rf"$t_d$ = {v:g} s"),
                (df_w, "R", "omega_p_rad_s", "R_m", _LABEL_OMEGA, lambda v: rf"$R$ = {v:g} m"),
            )
        ):
            ax = axs[i, j]
            if df is None:
                ax.set_visible(False)
                continue
            d = df[df["pulse"] == shape]
            if "series" in d.columns and (d["series"] == series).any():
                d = d[d["series"] == series]
            styles = []
            for k, iso in enumerate(isos):
                rows = _pick_case(d, iso, prefer.get(iso))
                styles.append((iso, rows, linestyles[k % len(linestyles)]))
            if all(len(r) == 0 for _, r, _ in styles):
                ax.text(0.5, 0.5, "no data", transform=ax.transAxes, ha="center", va="center")
                continue
            if not fixed:
                iso_rows = next((r for iso, r, _ in styles if iso != "none" and len(r)), None)
                fixed = _fixed_text(d, iso_rows)
                pieces = []
                for iso, r, ls in styles:
                    if len(r):
                        r0 = r.iloc[0]
                        pieces.append(
                            Line2D(
                                [],
                                [],
                                color="0.2",
                                ls=ls,
                                label=style_names.get(iso, iso)
                                + (
                                    ""
                                    if iso == "none"
                                    else " ("
                                    + _iso_label(
                                        iso,
                                        _num(r0.get("Tb_s")),
                                        _num(r0.get("xi_b")),
                                        _num(r0.get("mu_b")),
                                        _num(r0.get("R_b_m")),
                                        short=True,
                                    )
                                    + ")"
                                ),
                            )
                        )
                fig.legend(handles=pieces, loc="outside lower center", ncol=len(pieces), frameon=False)
            handles = _curves(ax, d, group_col, x_col, styles, glab)
            ax.set_xlabel(xlabel)
            ax.set_ylabel(_LABEL_AMIN)
            if logy:
                _log_y(ax)
            ax.legend(handles=handles, loc="best", ncol=1 if len(handles) <= 5 else 2)
            title_ax = f"{SHAPE_NAMES.get(shape, shape)}: " + ("vs block size" if j == 0 else "vs frequency")
            amax = d["amp_max_g"].max() if "amp_max_g" in d.columns else math.nan
            if d["min_overturn_over_tan_alpha"].isna().any() and math.isfinite(amax):
                title_ax += f"\n(gaps: no overturn up to {amax:g} g)"
            ax.set_title(title_ax)
    fig.suptitle(title + (f" ({fixed})" if fixed else ""))
    return _save(fig, out_path)


@_figure("Fig. 4")
def fig_4(
    h5: Any, out_path: str | os.PathLike, *, Tb: float = 3.0, xi_b: float = 0.35, logy: bool = True
) -> Path | None:
    """Fig. 4: minimum overturning amplitude of the three pulses against ``R`` and ``omega_p``.

    Solid lines: non-isolated block; dashed: linear isolator (the case with ``Tb``, ``xi_b`` when the
    store holds several). Amplitudes normalised by ``g tan(alpha)``.

    Parameters
    ----------
    h5 : path-like or h5py object
        Store with ``/pulses/overturn_R`` and ``/pulses/overturn_omega``.
    out_path : path-like
        Image to write.
    Tb, xi_b : float
        Preferred linear case: period [s] and damping ratio [-] (paper: 3 s, 0.35).
    logy : bool
        Logarithmic amplitude axis.
    """
    store = Store(h5)
    return _overturn_panels(
        store,
        out_path,
        shapes=_SHAPES,
        isos=("none", "linear"),
        prefer={"linear": {"Tb_s": Tb, "xi_b": xi_b}},
        title="Fig. 4 - minimum overturning acceleration, simple pulses",
        logy=logy,
        style_names={"none": "solid: non-isolated", "linear": "dashed: isolated"},
        what="Fig. 4",
    )


@_figure("Fig. 7")
def fig_7(
    h5: Any,
    out_path: str | os.PathLike,
    *,
    Tb: float = 3.0,
    xi_b: float = 0.35,
    mu_b: float = 0.11,
    logy: bool = True,
) -> Path | None:
    """Fig. 7: minimum overturning amplitude, full-sine pulse, linear against FP isolator.

    Solid lines: linear visco-elastic isolator; dashed: friction pendulum (bilinear hysteretic).

    Parameters
    ----------
    h5 : path-like or h5py object
        Store with ``/pulses/overturn_R`` and ``/pulses/overturn_omega``.
    out_path : path-like
        Image to write.
    Tb, xi_b : float
        Preferred linear case [s, -] (paper: 3 s, 0.35).
    mu_b : float
        Preferred FP friction coefficient [-] (paper: 0.11, ``R_b`` = 2.24 m).
    logy : bool
        Logarithmic amplitude axis.
    """
    store = Store(h5)
    return _overturn_panels(
        store,
        out_path,
        shapes=("fullsine",),
        isos=("linear", "fp"),
        prefer={"linear": {"Tb_s": Tb, "xi_b": xi_b}, "fp": {"mu_b": mu_b}},
        title="Fig. 7 - minimum overturning acceleration, linear vs bilinear (FP) isolation",
        logy=logy,
        style_names={"linear": "solid: linear", "fp": "dashed: FP"},
        what="Fig. 7",
    )


# ============================================================================================ Fig 5
@_figure("Fig. 5")
def fig_5(
    h5: Any, out_path: str | os.PathLike, *, shape: str = "fullsine", logy: bool = False
) -> Path | None:
    """Fig. 5: minimum overturning amplitude against ``Tb``, ``xi_b`` and ``rho`` (one varied at a time).

    Left: curves of fixed ``R`` at one pulse duration; right: curves of fixed ``td`` at one ``R``.
    Dotted horizontal lines: the non-isolated block of the same colour.

    Parameters
    ----------
    h5 : path-like or h5py object
        Store with ``/pulses/overturn_isolation``.
    out_path : path-like
        Image to write.
    shape : str
        Pulse shape (paper: full-sine).
    logy : bool
        Logarithmic amplitude axis.
    """
    from matplotlib.lines import Line2D

    store = Store(h5)
    df = store.table("pulses/overturn_isolation")
    if df is None:
        raise _Skip(
            f"no /pulses/overturn_isolation table in {store.path} (rule pulse_overturn with "
            "pulses.vs_isolation)"
        )
    df = df[df["pulse"] == shape]
    if df.empty:
        raise _Skip(f"/pulses/overturn_isolation holds no {shape} rows")
    params = [("Tb_s", _LABEL_TB), ("xi_b", _LABEL_XI), ("rho", r"mass ratio $\rho = m/m_b$ [-]")]
    params = [(p, lab) for p, lab in params if (df["param"] == p).any()]
    if not params:
        raise _Skip("/pulses/overturn_isolation has no rows with param Tb_s, xi_b or rho")
    fig = _new_figure(10.0, 3.1 * len(params) + 0.7)
    axs = _axes_grid(fig, len(params), 2)
    sides = [
        ("R", "R_m", "td_s", lambda v: rf"$R$ = {v:g} m", lambda v: rf"$t_d$ = {v:g} s"),
        ("td", "td_s", "R_m", lambda v: rf"$t_d$ = {v:g} s", lambda v: rf"$R$ = {v:g} m"),
    ]
    base = df[df["param"] != "none"]
    for i, (param, xlabel) in enumerate(params):
        for j, (series, gcol, fcol, glab, flab) in enumerate(sides):
            ax = axs[i, j]
            d = df[df["series"] == series] if "series" in df.columns else df
            if d.empty:
                ax.set_visible(False)
                continue
            fixed_vals = sorted(d[fcol].round(9).unique())
            groups = sorted(d[gcol].round(9).unique())
            handles = []
            for c, gv in zip(_colors(len(groups)), groups, strict=True):
                dg = d[np.isclose(d[gcol].astype(float), gv)]
                dp = dg[dg["param"] == param].sort_values("value")
                ax.plot(dp["value"], dp["min_overturn_over_tan_alpha"], "-", marker=".", ms=3, color=c)
                ref = dg[dg["param"] == "none"]["min_overturn_over_tan_alpha"]
                if len(ref) and math.isfinite(_num(ref.iloc[0])):
                    ax.axhline(_num(ref.iloc[0]), color=c, ls=":", lw=1.0)
                handles.append(Line2D([], [], color=c, lw=2, label=glab(gv)))
            ax.set_xlabel(xlabel)
            ax.set_ylabel(_LABEL_AMIN)
            if logy:
                _log_y(ax)
            fv = ", ".join(flab(v) for v in fixed_vals)
            ax.set_title(f"varied {xlabel.split('[')[0].strip()}, {fv}")
            ax.legend(handles=handles, loc="best")
    r0 = base.iloc[0] if len(base) else None
    others = ""
    if r0 is not None:
        bt = base[base["param"] != "Tb_s"]["Tb_s"]
        bx = base[base["param"] != "xi_b"]["xi_b"]
        br = base[base["param"] != "rho"]["rho"]
        vals = []
        for sym, col, unit in ((r"$T_b$", bt, " s"), (r"$\xi_b$", bx, ""), (r"$\rho$", br, "")):
            if len(col) and col.nunique() == 1:
                vals.append(f"{sym} = {_num(col.iloc[0]):g}{unit}")
        others = "base case " + ", ".join(vals) if vals else ""
    lam = df["lambda_"].iloc[0] if "lambda_" in df.columns else math.nan
    fig.legend(
        handles=[
            Line2D([], [], color="0.3", ls="-", label="isolated (linear)"),
            Line2D([], [], color="0.3", ls=":", label="non-isolated"),
        ],
        loc="outside lower center",
        ncol=2,
        frameon=False,
    )
    fig.suptitle(
        f"Fig. 5 - influence of the isolation parameters, {SHAPE_NAMES.get(shape, shape)} "
        rf"($\lambda$ = {lam:g}; {others})"
    )
    return _save(fig, out_path)


@_figure("Fig. 6")
def fig_6(
    h5: Any,
    out_path: str | os.PathLike,
    *,
    tds: Sequence[float] | None = None,
    isolations: Sequence[str] = ("none", "linear"),
) -> Path | None:
    """Fig. 6: lambda-R regime maps under the three pulses, non-isolated and isolated.

    Rows: pulse shapes; columns: for each ``td``, the non-isolated and the isolated block.

    Parameters
    ----------
    h5 : path-like or h5py object
        Store with pulse maps ``/maps/pulse-<shape>-td<td>/lambda_R-<case>``.
    out_path : path-like
        Image to write.
    tds : sequence of float, optional
        Pulse half-cycle durations [s] to show (default all, paper: 0.2 and 0.5 s).
    isolations : sequence of str
        Isolation kinds of the columns.
    """
    store = Store(h5)
    maps = [
        m
        for m in store.maps()
        if m.kind == "lambda-R" and m.source_kind == "pulse" and m.isolation in isolations
    ]
    if not maps:
        raise _Skip(f"no lambda-R maps of pulses in {store.path} (rule pulse_maps)")
    td_all = sorted({round(m.td_s, 9) for m in maps if math.isfinite(m.td_s)})
    tds = td_all if tds is None else [t for t in td_all if any(_close(t, x) for x in tds)]
    shapes = [s for s in _SHAPES if any(m.pulse == s and m.td_s in tds for m in maps)]
    if not shapes:
        raise _Skip(f"no pulse maps with td in {tds}")
    cols: list[tuple[float, str]] = [
        (td, iso)
        for td in tds
        for iso in isolations
        if any(m.td_s == td and m.isolation == iso for m in maps)
    ]
    fig = _new_figure(2.9 * len(cols) + 0.6, 2.7 * len(shapes) + 1.0)
    axs = _axes_grid(fig, len(shapes), len(cols), sharex=True, sharey=True)
    amps, isotext = set(), ""
    for i, shape in enumerate(shapes):
        for j, (td, iso) in enumerate(cols):
            ax = axs[i, j]
            cand = [m for m in maps if m.pulse == shape and m.td_s == td and m.isolation == iso]
            if not cand:
                ax.text(0.5, 0.5, "not in the store", transform=ax.transAxes, ha="center", va="center")
                continue
            info = sorted(cand, key=lambda m: m.case)[0]
            _draw_map(
                ax,
                store.read_map(info),
                _LABEL_LAM if i == len(shapes) - 1 else "",
                _LABEL_R if j == 0 else "",
            )
            amps.add(round(info.amp_g, 6))
            if iso != "none":
                isotext = _map_iso_label(info) + (
                    rf", $\rho$ = {info.rho:g}" if math.isfinite(info.rho) else ""
                )
            ax.set_title(
                f"{SHAPE_NAMES[shape]}, $t_d$ = {td:g} s\n"
                + ("non-isolated" if iso == "none" else "isolated" if iso == "linear" else iso)
            )
    _regime_legend(fig)
    amp = ", ".join(f"{a:g}" for a in sorted(amps))
    fig.suptitle(f"Fig. 6 - response-regime spectra under simple pulses ($A_{{g0}}$ = {amp} g; {isotext})")
    return _save(fig, out_path)
