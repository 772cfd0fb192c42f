"""The paper's record figures: Fig 8 (minimum overturning PGA of records against block size), Figs 9,
10, 13 (lambda-R regime maps of records), Figs 11, 12 (Tb-xi maps), and three figures per record: its
acceleration, velocity and extracted pulse; its minimum overturning PGA against block size beside its
own PGA; all its regime maps."""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
from scipy.integrate import cumulative_trapezoid

from isorock.constants import G
from isorock.figures.style import (
    _ISO_ORDER,
    _LABEL_LAM,
    _LABEL_R,
    _LABEL_TB,
    _LABEL_XI,
    FIG8_RECORDS,
    FIG9_RECORDS,
    FIG10_RECORDS,
    FIG11_RECORDS,
    FIG12_RECORD,
    FIG13_RECORDS,
    _axes_grid,
    _close,
    _colors,
    _draw_map,
    _figure,
    _isclose_col,
    _iso_label,
    _letter,
    _map_iso_label,
    _match_record,
    _missing_text,
    _new_figure,
    _num,
    _pick_records,
    _record_title,
    _regime_legend,
    _save,
    _Skip,
)
from isorock.store import MapInfo, Store

__all__ = [
    "fig_8",
    "fig_9",
    "fig_10",
    "fig_11",
    "fig_12",
    "fig_13",
    "fig_record",
    "fig_record_overturn",
    "fig_record_maps",
]


# ============================================================================================ maps
def _lr_maps_for(store: Store, source: str, isos: Sequence[str] | None = None) -> list[MapInfo]:
    out = [
        m
        for m in store.maps()
        if m.kind == "lambda-R" and m.source == source and (isos is None or m.isolation in isos)
    ]
    return sorted(
        out, key=lambda m: (_ISO_ORDER.get(m.isolation, 9), m.Tb_s if math.isfinite(m.Tb_s) else 0, m.case)
    )


def _record_lr_figure(
    store: Store, out_path, *, wanted: Sequence[str], isolations: Sequence[str], title: str, what: str
) -> Path:
    sources = sorted({m.source for m in store.maps() if m.kind == "lambda-R" and m.source_kind == "record"})
    if not sources:
        raise _Skip(f"{what}: no lambda-R maps of records in {store.path} (rule regime_maps)")
    found, missing = _pick_records(wanted, sources)
    found = [r for r in found if _lr_maps_for(store, r, isolations)]
    missing += [w for w in wanted if _match_record(w, found) is None and w not in missing]
    if not found:
        raise _Skip(
            f"{what}: none of the records {', '.join(wanted)} has lambda-R maps with isolation "
            f"{' / '.join(isolations)} (records with maps: {', '.join(sources)})"
        )
    per = {r: _lr_maps_for(store, r, isolations) for r in found}
    ncol = max(len(v) for v in per.values())
    fig = _new_figure(3.1 * ncol + 0.5, 2.9 * len(found) + 1.0)
    axs = _axes_grid(fig, len(found), ncol, sharex=True, sharey=True)
    rhos, xis = set(), set()
    for i, rid in enumerate(found):
        for j in range(ncol):
            ax = axs[i, j]
            if j >= len(per[rid]):
                ax.set_visible(False)
                continue
            info = per[rid][j]
            _draw_map(
                ax,
                store.read_map(info),
                _LABEL_LAM if i == len(found) - 1 else "",
                _LABEL_R if j == 0 else "",
            )
            if math.isfinite(info.rho):
                rhos.add(info.rho)
            ax.set_title(
                f"{_letter(wanted, rid, i)} {_record_title(store, rid)}\n"
                f"{_map_iso_label(info)}, PGA = {info.amp_g:.2f} g",
                fontsize=8,
            )
            if math.isfinite(info.xi_b):
                xis.add(info.xi_b)
    _regime_legend(fig)
    extra = ", ".join([rf"$\rho$ = {r:g}" for r in sorted(rhos)])
    fig.suptitle(title + (f" ({extra})" if extra else "") + _missing_text(missing))
    return _save(fig, out_path)


@_figure("Fig. 9")
def fig_9(
    h5: Any,
    out_path: str | os.PathLike,
    *,
    records: Sequence[str] = FIG9_RECORDS,
    isolations: Sequence[str] = ("none", "linear"),
) -> Path | None:
    """Fig. 9: lambda-R regime maps of the records TAB, EMO, CH3W and PKC, non-isolated and isolated.

    Parameters
    ----------
    h5 : path-like or h5py object
        Store with record maps ``/maps/<id>/lambda_R-<case>``.
    out_path : path-like
        Image to write.
    records : sequence of str
        Catalog ids of the rows (those absent from the store are listed in a footnote).
    isolations : sequence of str
        Isolation kinds of the columns.
    """
    return _record_lr_figure(
        Store(h5),
        out_path,
        wanted=records,
        isolations=isolations,
        title="Fig. 9 - response-regime spectra under pulse-type records",
        what="Fig. 9",
    )


@_figure("Fig. 10")
def fig_10(
    h5: Any,
    out_path: str | os.PathLike,
    *,
    records: Sequence[str] = FIG10_RECORDS,
    isolations: Sequence[str] = ("none", "linear"),
) -> Path | None:
    """Fig. 10: lambda-R regime maps of the records C02, NWS, AEG-Long and AEG-Tran.

    Parameters
    ----------
    h5 : path-like or h5py object
        Store with record maps ``/maps/<id>/lambda_R-<case>``.
    out_path : path-like
        Image to write.
    records : sequence of str
        Catalog ids of the rows.
    isolations : sequence of str
        Isolation kinds of the columns.
    """
    return _record_lr_figure(
        Store(h5),
        out_path,
        wanted=records,
        isolations=isolations,
        title="Fig. 10 - response-regime spectra under pulse-type records",
        what="Fig. 10",
    )


@_figure("Fig. 13")
def fig_13(
    h5: Any,
    out_path: str | os.PathLike,
    *,
    records: Sequence[str] = FIG13_RECORDS,
    isolations: Sequence[str] = ("linear", "fp"),
) -> Path | None:
    """Fig. 13: lambda-R regime maps with the linear and the FP (bilinear hysteretic) isolator.

    Parameters
    ----------
    h5 : path-like or h5py object
        Store with record maps ``/maps/<id>/lambda_R-<case>`` for linear and FP cases.
    out_path : path-like
        Image to write.
    records : sequence of str
        Catalog ids of the rows (paper: Imperial Valley EMO and E05).
    isolations : sequence of str
        Isolation kinds of the columns.
    """
    return _record_lr_figure(
        Store(h5),
        out_path,
        wanted=records,
        isolations=isolations,
        title="Fig. 13 - response-regime spectra, linear vs FP isolation",
        what="Fig. 13",
    )


def _tbxi_maps(store: Store, rid: str, lam: float | None, R: float | None) -> list[MapInfo]:
    out = [
        m
        for m in store.maps()
        if m.kind == "Tb-xi"
        and m.source == rid
        and (lam is None or _close(m.lam, lam, 1e-6))
        and (R is None or _close(m.R_m, R, 1e-6))
    ]
    return sorted(out, key=lambda m: (m.R_m, m.lam))


@_figure("Fig. 11")
def fig_11(
    h5: Any,
    out_path: str | os.PathLike,
    *,
    records: Sequence[str] = FIG11_RECORDS,
    lam: float = 4.0,
    R: float = 6.0,
) -> Path | None:
    """Fig. 11: Tb-xi regime maps of the isolated block under the records BRI, EMO, CH3W and PKC.

    Parameters
    ----------
    h5 : path-like or h5py object
        Store with ``/maps/<id>/Tb_xi-lam<lambda>-R<R>``.
    out_path : path-like
        Image to write.
    records : sequence of str
        Catalog ids of the panels.
    lam, R : float
        The block: slenderness [-] and size [m] (paper: 4 and 6 m).
    """
    store = Store(h5)
    sources = sorted({m.source for m in store.maps() if m.kind == "Tb-xi"})
    if not sources:
        raise _Skip(f"no Tb-xi maps in {store.path} (rule regime_maps, maps.Tb_xi)")
    found, missing = _pick_records(records, sources)
    panels = [(rid, _tbxi_maps(store, rid, lam, R)) for rid in found]
    missing += [rid for rid, ms in panels if not ms]
    panels = [(rid, ms[0]) for rid, ms in panels if ms]
    if not panels:
        raise _Skip(
            f"no Tb-xi map with lambda = {lam:g}, R = {R:g} m for the records {', '.join(records)} "
            f"(records with Tb-xi maps: {', '.join(sources)})"
        )
    n = len(panels)
    ncol = 2 if n > 1 else 1
    nrow = math.ceil(n / ncol)
    fig = _new_figure(4.4 * ncol + 0.4, 3.5 * nrow + 0.9)
    axs = _axes_grid(fig, nrow, ncol, sharex=True, sharey=True)
    rho = math.nan
    for k, (rid, info) in enumerate(panels):
        ax = axs[k // ncol, k % ncol]
        _draw_map(ax, store.read_map(info), _LABEL_TB, _LABEL_XI)
        rho = info.rho
        ax.set_title(f"{_letter(records, rid, k)} {_record_title(store, rid)}\nPGA = {info.amp_g:.2f} g")
    for k in range(n, nrow * ncol):
        axs[k // ncol, k % ncol].set_visible(False)
    _regime_legend(fig)
    fig.suptitle(
        rf"Fig. 11 - response-regime spectra in the $T_b$-$\xi_b$ plane ($\lambda$ = {lam:g}, "
        rf"$R$ = {R:g} m, $\rho$ = {rho:g})" + _missing_text(missing)
    )
    return _save(fig, out_path)


@_figure("Fig. 12")
def fig_12(
    h5: Any, out_path: str | os.PathLike, *, record: str = FIG12_RECORD, lam: float = 3.0
) -> Path | None:
    """Fig. 12: Tb-xi regime maps of blocks of several sizes ``R`` under one record (paper: PKC).

    Parameters
    ----------
    h5 : path-like or h5py object
        Store with ``/maps/<id>/Tb_xi-lam<lambda>-R<R>`` for several ``R``.
    out_path : path-like
        Image to write.
    record : str
        Catalog id of the record.
    lam : float
        Slenderness of the blocks [-] (paper: 3).
    """
    store = Store(h5)
    sources = sorted({m.source for m in store.maps() if m.kind == "Tb-xi"})
    rid = _match_record(record, sources)
    if rid is None:
        raise _Skip(
            f"no Tb-xi maps of record {record} in {store.path} "
            f"(records with Tb-xi maps: {', '.join(sources) or 'none'})"
        )
    maps = _tbxi_maps(store, rid, lam, None)
    if not maps:
        lams = sorted({m.lam for m in store.maps() if m.kind == "Tb-xi" and m.source == rid})
        raise _Skip(f"no Tb-xi map of {rid} with lambda = {lam:g} (lambda present: {lams})")
    n = len(maps)
    ncol = min(n, 3)
    nrow = math.ceil(n / ncol)
    fig = _new_figure(4.0 * ncol + 0.4, 3.4 * nrow + 0.9)
    axs = _axes_grid(fig, nrow, ncol, sharex=True, sharey=True)
    for k, info in enumerate(maps):
        ax = axs[k // ncol, k % ncol]
        _draw_map(ax, store.read_map(info), _LABEL_TB, _LABEL_XI)
        ax.set_title(rf"$R$ = {info.R_m:g} m (PGA = {info.amp_g:.2f} g)")
    for k in range(n, nrow * ncol):
        axs[k // ncol, k % ncol].set_visible(False)
    _regime_legend(fig)
    fig.suptitle(
        f"Fig. 12 - $T_b$-$\\xi_b$ spectra for blocks of varying size, "
        f"{_record_title(store, rid)} ($\\lambda$ = {lam:g}, $\\rho$ = {maps[0].rho:g})"
    )
    return _save(fig, out_path)


# ============================================================================================ Fig 8
@_figure("Fig. 8")
def fig_8(
    h5: Any, out_path: str | os.PathLike, *, records: Sequence[str] = FIG8_RECORDS, lam: float = 4.0
) -> Path | None:
    """Fig. 8: minimum overturning PGA of records against block size, non-isolated and isolated.

    Parameters
    ----------
    h5 : path-like or h5py object
        Store with ``/overturn/<id>`` tables (or ``/summary/overturn``).
    out_path : path-like
        Image to write.
    records : sequence of str
        Catalog ids of the panels (paper: BRI, EMO, PKC, CH3W).
    lam : float
        Slenderness of the blocks [-] (paper: 4).
    """
    from matplotlib.lines import Line2D

    store = Store(h5)
    df = store.overturn()
    if df is None or df.empty:
        raise _Skip(f"no /overturn/<id> tables in {store.path} (rule min_overturn)")
    df = df[_isclose_col(df["lambda_"], lam)]
    if df.empty:
        raise _Skip(f"the overturn tables hold no block with lambda = {lam:g}")
    found, missing = _pick_records(records, sorted(df["record"].unique()))
    if not found:
        raise _Skip(
            f"no overturn table for the records {', '.join(records)} "
            f"(records present: {', '.join(sorted(df['record'].unique()))})"
        )
    n = len(found)
    ncol = 2 if n > 1 else 1
    nrow = math.ceil(n / ncol)
    fig = _new_figure(4.8 * ncol + 0.4, 3.4 * nrow + 1.0)
    axs = _axes_grid(fig, nrow, ncol)
    styles = {"none": ("-", "k"), "linear": ("--", None), "fp": ("-.", None)}
    handles: dict[str, Line2D] = {}
    rho = math.nan
    case_col = "case" if "case" in df.columns else "isolation"
    cases = list(
        dict.fromkeys(
            df.sort_values(
                ["isolation", "Tb_s"],
                key=lambda s: s.map(lambda v: _ISO_ORDER.get(v, 9) if isinstance(v, str) else v),
            )[case_col]
        )
    )
    iso_cases = [c for c in cases if (df[df[case_col] == c]["isolation"] != "none").any()]
    palette = dict(zip(iso_cases, _colors(len(iso_cases)), strict=True))
    for k, rid in enumerate(found):
        ax = axs[k // ncol, k % ncol]
        d = df[df["record"] == rid]
        for case in cases:
            dc = d[d[case_col] == case].sort_values("R_m")
            if dc.empty:
                continue
            r0 = dc.iloc[0]
            iso = str(r0["isolation"])
            ls, color = styles.get(iso, (":", None))
            color = color or palette.get(case, "C0")
            ax.plot(dc["R_m"], dc["min_overturn_g"], ls=ls, color=color, marker=".", ms=3, lw=1.4)
            if math.isfinite(_num(r0.get("rho"))):
                rho = _num(r0["rho"])
            label = _iso_label(
                iso, _num(r0.get("Tb_s")), _num(r0.get("xi_b")), _num(r0.get("mu_b")), _num(r0.get("R_b_m"))
            )
            handles.setdefault(label, Line2D([], [], ls=ls, color=color, lw=1.6, label=label))
        ax.set_xlabel(_LABEL_R)
        ax.set_ylabel(r"minimum overturning PGA [g]")
        ax.set_ylim(bottom=0)
        ax.set_title(f"{_letter(records, rid, k)} {_record_title(store, rid)}")
    for k in range(n, nrow * ncol):
        axs[k // ncol, k % ncol].set_visible(False)
    fig.legend(
        handles=list(handles.values()), loc="outside lower center", ncol=min(3, len(handles)), frameon=False
    )
    fig.suptitle(
        rf"Fig. 8 - minimum overturning acceleration under pulse-type records ($\lambda$ = {lam:g}"
        + (rf", $\rho$ = {rho:g})" if math.isfinite(rho) else ")")
        + _missing_text(missing)
    )
    return _save(fig, out_path)


# ============================================================================================ records
#: the record figure's margins (fractions of its 10 x 6 in): its two-line title, labels and ticks
_RECORD_MARGINS = {"left": 0.075, "right": 0.985, "bottom": 0.085, "top": 0.885, "hspace": 0.08}


@_figure("record figure")
def fig_record(h5: Any, record_id: str, out_path: str | os.PathLike) -> Path | None:
    """Processed acceleration and velocity of one record with the extracted velocity pulse overlaid.

    Parameters
    ----------
    h5 : path-like or h5py object
        Store with ``/records/<id>``: ``acc`` [m/s^2] (attribute ``dt_s`` [s]) and
        ``pulse/velocity``, ``pulse/pulse_velocity``, ``pulse/mp_velocity`` [m/s].
    record_id : str
        The record's group name.
    out_path : path-like
        Image to write.

    Notes
    -----
    Signature ``fig_record(h5, record_id, out_path)``: the record id comes before the output path.
    """
    from matplotlib.lines import Line2D

    store = Store(h5)
    if not store.has(f"records/{record_id}"):
        raise _Skip(
            f"no /records/{record_id} in {store.path} (records: {', '.join(store.record_ids()) or 'none'})"
        )
    series = store.record_series(record_id)
    a, pa = series["attrs"], series["pulse_attrs"]
    acc, dt = series["acc"], series["dt_s"]
    vel, pulse, mp = series["velocity"], series["pulse_velocity"], series["mp_velocity"]
    if acc is None:
        raise _Skip(f"/records/{record_id} has no acc dataset")
    if not (math.isfinite(dt) and dt > 0):
        raise _Skip(f"/records/{record_id}: no time step (attribute dt_s)")
    t = np.arange(acc.size) * dt
    if vel is None:
        vel = cumulative_trapezoid(acc, dx=dt, initial=0.0)
    # fixed margins: the layout engine would draw each of these figures twice
    fig = _new_figure(10.0, 6.0, _RECORD_MARGINS)
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    ax1.plot(t, acc, color="0.35", lw=0.6, label="processed acceleration")
    if pulse is not None and np.any(pulse):
        ax1.plot(
            t[: pulse.size],
            np.gradient(pulse, dt),
            color="C3",
            lw=1.3,
            label="pulse acceleration (d/dt of the wavelet pulse)",
        )
    ax1.set_ylabel(r"ground acceleration [m/s$^2$]")
    ax1.legend(loc="upper right")
    ax2.plot(t[: vel.size], vel, color="0.35", lw=0.8, label="ground velocity")
    tp = _num(a.get("Tp_s", pa.get("Tp_s")))
    tpm = _num(a.get("Tp_mp_s", pa.get("Tp_mp_s")))
    handles = [Line2D([], [], color="0.35", lw=0.8, label="ground velocity")]
    if pulse is not None:
        ax2.plot(t[: pulse.size], pulse, color="C3", lw=1.6)
        handles.append(
            Line2D(
                [],
                [],
                color="C3",
                lw=1.6,
                label="extracted pulse (db4 wavelet)"
                + (f", $T_p$ = {tp:.2f} s" if math.isfinite(tp) else ""),
            )
        )
    if mp is not None and np.any(mp):
        ax2.plot(t[: mp.size], mp, color="C0", lw=1.2, ls="--")
        handles.append(
            Line2D(
                [],
                [],
                color="C0",
                lw=1.2,
                ls="--",
                label="Mavroeidis-Papageorgiou fit"
                + (f", $T_p$ = {tpm:.2f} s" if math.isfinite(tpm) else ""),
            )
        )
    ax2.set_ylabel("ground velocity [m/s]")
    ax2.set_xlabel("time [s]")
    ax2.legend(handles=handles, loc="upper right")
    pga = _num(a.get("pga_g"))
    pga = pga if math.isfinite(pga) else float(np.max(np.abs(acc))) / G
    pgv = _num(a.get("pgv_m_s"))
    pgv = pgv if math.isfinite(pgv) else float(np.max(np.abs(vel)))
    tp1 = _num(a.get("table1_tp_s"))
    # 4 significant digits, as the report's pages print a record's quantities (RECORD_DIGITS)
    sub = f"PGA = {pga:.4g} g, PGV = {pgv:.4g} m/s"
    if math.isfinite(tp1):
        sub += f", Table 1 $T_p$ = {tp1:.2f} s"
    label = str(a.get("label") or record_id)
    fig.suptitle(f"Record {record_id}: {label}\n{sub}")
    return _save(fig, out_path)


@_figure("record overturning figure")
def fig_record_overturn(h5: Any, record_id: str, out_path: str | os.PathLike) -> Path | None:
    """Minimum overturning PGA of one record against block size, one curve per isolation case and
    slenderness, with the record's own PGA: a block whose curve passes below it overturns under the
    record as recorded (marked)."""
    store = Store(h5)
    df = store.overturn()
    if df is None or df.empty or not (df["record"] == record_id).any():
        raise _Skip(f"no minimum-overturning table of {record_id} (rule min_overturn)")
    d = df[df["record"] == record_id]
    pga = _num(store.record_attrs(record_id).get("pga_g"))
    lams = sorted(d["lambda_"].unique())
    fig = _new_figure(4.6 * len(lams) + 0.4, 3.6)
    axs = _axes_grid(fig, 1, len(lams), sharey=True)
    cases = list(dict.fromkeys(d["case"]))  # the configuration's order
    iso = dict(zip(d["case"], d["isolation"], strict=False))
    palette = dict(
        zip(
            [c for c in cases if iso[c] != "none"], _colors(sum(iso[c] != "none" for c in cases)), strict=True
        )
    )
    for k, lam in enumerate(lams):
        ax = axs[0, k]
        dl = d[_isclose_col(d["lambda_"], lam)]
        for case in cases:
            dc = dl[dl["case"] == case].sort_values("R_m")
            if dc.empty:
                continue
            r0 = dc.iloc[0]
            color = "k" if iso[case] == "none" else palette[case]
            params = [_num(r0.get(k)) for k in ("Tb_s", "xi_b", "mu_b", "R_b_m")]
            name = _iso_label(iso[case], *params, short=True) if iso[case] != "none" else "non-isolated"
            label = f"{case}: {name}"
            ax.plot(dc["R_m"], dc["min_overturn_g"], "-", marker=".", ms=4, color=color, lw=1.4, label=label)
            below = dc[dc["min_overturn_g"] < pga]
            ax.plot(below["R_m"], below["min_overturn_g"], "o", mfc="none", mec="#e8251f", ms=8)
        if math.isfinite(pga):
            ax.axhline(pga, color="#e8251f", ls="--", lw=1.2, label=f"record PGA {pga:.2f} g")
        ax.plot([], [], "o", mfc="none", mec="#e8251f", label="overturns below the record's PGA")
        ax.set_xlabel(_LABEL_R)
        ax.set_ylim(bottom=0)
        ax.set_title(rf"$\lambda$ = {lam:g}", fontsize=8)
        ax.legend(fontsize=7)
    axs[0, 0].set_ylabel("minimum overturning PGA [g]")
    fig.suptitle(f"{_record_title(store, record_id)}: minimum overturning PGA", fontsize=9)
    return _save(fig, out_path)


@_figure("record maps figure")
def fig_record_maps(h5: Any, record_id: str, out_path: str | os.PathLike) -> Path | None:
    """Every response-regime map of one record (lambda-R maps per isolation case, then Tb-xi maps),
    in the paper's colours."""
    store = Store(h5)
    maps = [m for m in store.maps() if m.source == record_id]
    if not maps:
        raise _Skip(f"no regime maps of {record_id} (rule regime_maps)")
    maps.sort(key=lambda m: (m.kind != "lambda-R", _ISO_ORDER.get(m.isolation, 9), m.case, m.lam, m.R_m))
    n = len(maps)
    ncol = min(3, n)
    nrow = math.ceil(n / ncol)
    fig = _new_figure(3.2 * ncol + 0.4, 2.9 * nrow + 1.0)
    axs = _axes_grid(fig, nrow, ncol)
    for k, info in enumerate(maps):
        ax = axs[k // ncol, k % ncol]
        if info.kind == "lambda-R":
            _draw_map(ax, store.read_map(info), _LABEL_LAM, _LABEL_R)
            name = _map_iso_label(info, short=True) if info.isolation != "none" else "non-isolated"
            ax.set_title(f"{name}\nPGA = {info.amp_g:.2f} g", fontsize=8)
        else:
            _draw_map(ax, store.read_map(info), _LABEL_TB, _LABEL_XI)
            head = rf"linear isolator, $\lambda$ = {info.lam:g}, R = {info.R_m:g} m"
            ax.set_title(f"{head}\nPGA = {info.amp_g:.2f} g", fontsize=8)
    for k in range(n, nrow * ncol):
        axs[k // ncol, k % ncol].set_visible(False)
    _regime_legend(fig)
    fig.suptitle(f"{_record_title(store, record_id)}: response-regime maps", fontsize=9)
    return _save(fig, out_path)
