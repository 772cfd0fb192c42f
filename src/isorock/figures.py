"""The paper's figures (Figs 3-13) and one figure per record, drawn from the HDF5 store.

Every function reads only the store (layout in :mod:`isorock.store`), writes one image (the format
follows the suffix of ``out_path``: ``.png``, ``.pdf``, ``.svg``) with matplotlib's Agg canvas (no
pyplot, no global backend change) and returns its path; when the data it needs are not in the
store it writes nothing, logs one line saying what is missing (logger ``isorock.figures``, level
WARNING) and returns None.

==========  ===================================================================================
figure      data read from the store
==========  ===================================================================================
Fig 3       ``/pulses/restitution`` (``lambda``, ``rho``, ``eps``, ``beta1_over_h``); when absent the
            closed forms of :func:`isorock.model.impact_coefficients` (no analysis needed)
Fig 4       ``/pulses/overturn_R`` (``series == "td"``) and ``/pulses/overturn_omega``
            (``series == "R"``): the three pulses, ``isolation`` "none" and "linear"
Fig 5       ``/pulses/overturn_isolation`` (``param`` "Tb_s" / "xi_b" / "rho" / "none"): full-sine
            pulse, curves of fixed ``R`` (``series == "R"``) and of fixed ``td`` (``series == "td"``)
Fig 6       lambda-R maps of pulse sources (``/maps/pulse-<shape>-td<td>/lambda_R-<case>``)
Fig 7       as Fig 4, full-sine pulse, ``isolation`` "linear" against "fp"
Fig 8       ``/overturn/<id>`` (or ``/summary/overturn``) of the records BRI, EMO, PKC, CH3W
Figs 9, 10  lambda-R maps of the records TAB, EMO, CH3W, PKC (9) and C02, NWS, AEG-L, AEG-T (10)
Fig 11      Tb-xi maps (``lambda`` 4, ``R`` 6 m) of the records BRI, EMO, CH3W, PKC
Fig 12      Tb-xi maps of the PKC record with ``lambda`` 3, one panel per ``R``
Fig 13      lambda-R maps, linear against FP isolator, records EMO and E05
record      ``/records/<id>/acc`` (attr ``dt_s``) and ``/records/<id>/pulse/{velocity,
            pulse_velocity, mp_velocity}``; also accepted: ``vel``, ``pulse_vel`` and attr ``dt``
==========  ===================================================================================

Maps are found by their group attributes (``kind``, ``source``, ``source_kind``, ``isolation``,
``pulse_shape``, ``td_s``, ``lambda``, ``R_m``, the ``fixed`` JSON), not by their names; records by
their catalog ids (``NOR94-PKC``), or by the station code when the store uses other ids. Regime maps
use the paper's colours: cyan no uplift, green rocking, red overturning.

Example
-------
>>> from isorock.figures import make_all
>>> paths = make_all("results/isorock.h5", "results/figures")  # doctest: +SKIP
"""

from __future__ import annotations

import functools
import json
import logging
import math
import os
import re
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

__all__ = [
    "REGIME_COLORS",
    "REGIME_LABELS",
    "fig_3",
    "fig_4",
    "fig_5",
    "fig_6",
    "fig_7",
    "fig_8",
    "fig_9",
    "fig_10",
    "fig_11",
    "fig_12",
    "fig_13",
    "fig_record",
    "make_all",
    "FIGURES",
]

log = logging.getLogger(__name__)

#: colours of the regimes 0 (no uplift), 1 (rocking), 2 (overturning), as in the paper
REGIME_COLORS = ("#00e5ee", "#2ecc40", "#e8251f")
#: legend names of the regimes
REGIME_LABELS = ("No uplift", "Rocking", "Overturning")

SHAPE_NAMES = {"rect": "rectangular pulse", "halfsine": "half-sine pulse", "fullsine": "full-sine pulse"}
_SHAPES = ("rect", "halfsine", "fullsine")

FIG8_RECORDS = ("BUC77-BRI", "IMV79-EMO", "NOR94-PKC", "PKF04-CH3W")
FIG9_RECORDS = ("TAB78-TAB", "IMV79-EMO", "PKF04-CH3W", "NOR94-PKC")
FIG10_RECORDS = ("PKF66-C02", "NOR94-NWS", "AIG95-AEGL", "AIG95-AEGT")
FIG11_RECORDS = ("BUC77-BRI", "IMV79-EMO", "PKF04-CH3W", "NOR94-PKC")
FIG12_RECORD = "NOR94-PKC"
FIG13_RECORDS = ("IMV79-EMO", "IMV79-E05")

_ISO_ORDER = {"none": 0, "linear": 1, "fp": 2}
_LABEL_LAM = r"slenderness $\lambda = h/b$ [-]"
_LABEL_R = r"block size $R$ [m]"
_LABEL_TB = r"isolation period $T_b$ [s]"
_LABEL_XI = r"isolation damping $\xi_b$ [-]"
_LABEL_OMEGA = r"pulse frequency $\omega_p = \pi/t_d$ [rad/s]"
_LABEL_AMIN = r"$A_{g0,\min}\,/\,(g\tan\alpha)$ [-]"
_RC = {
    "font.size": 9,
    "axes.titlesize": 9,
    "axes.labelsize": 9,
    "legend.fontsize": 8,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "figure.titlesize": 11,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "savefig.dpi": 150,
}


class _Skip(Exception):
    """The data a figure needs are not in the store (the message says which)."""


# ============================================================================================ store access
def _h5_path(h5: Any) -> Path:
    """Path of the store, given a path or an open h5py object."""
    if hasattr(h5, "file") and hasattr(h5.file, "filename"):
        return Path(h5.file.filename)
    return Path(os.fspath(h5))


def _text(v: Any) -> Any:
    if isinstance(v, bytes):
        v = v.decode()
    if isinstance(v, np.ndarray) and v.size == 1:
        v = v.item()
    if isinstance(v, np.generic):
        v = v.item()
    return v


def _num(v: Any) -> float:
    v = _text(v)
    try:
        x = float(v)
    except (TypeError, ValueError):
        return math.nan
    return x


@dataclass
class _MapInfo:
    """A regime map of the store, described by its attributes."""

    path: str
    kind: str
    source: str
    source_kind: str
    case: str
    isolation: str
    Tb_s: float
    xi_b: float
    rho: float
    mu_b: float
    R_b_m: float
    lam: float
    R_m: float
    pulse: str
    td_s: float
    amp_g: float
    Tp_s: float


class _Store:
    """Read-only access to the store: tables, maps and records, read once."""

    def __init__(self, h5: Any):
        self.path = _h5_path(h5)
        if not self.path.is_file():
            raise _Skip(f"no store at {self.path}")
        import h5py

        self._keys: set[str] = set()
        with h5py.File(self.path, "r") as f:
            f.visit(self._keys.add)
        self._maps: list[_MapInfo] | None = None
        self._tables: dict[str, Any] = {}

    def has(self, key: str) -> bool:
        return key.strip("/") in self._keys

    def table(self, key: str):
        """A pandas table of the store, or None when it is absent."""
        key = key.strip("/")
        if key not in self._tables:
            if not self.has(key):
                self._tables[key] = None
            else:
                from .store import read_table

                try:
                    self._tables[key] = read_table(self.path, key)
                except (KeyError, TypeError, ValueError) as exc:
                    log.warning("isorock.figures: cannot read table /%s: %s", key, exc)
                    self._tables[key] = None
        return self._tables[key]

    def overturn(self):
        """All record overturn tables stacked (``/summary/overturn``, else the ``/overturn/<id>`` tables)."""
        import pandas as pd

        df = self.table("summary/overturn")
        if df is not None:
            return df
        parts = []
        for k in sorted(self._keys):
            m = re.fullmatch(r"overturn/([^/]+)", k)
            if m:
                t = self.table(k)
                if t is not None:
                    t = t.copy()
                    if "record" not in t.columns:
                        t["record"] = m.group(1)
                    parts.append(t)
        return pd.concat(parts, ignore_index=True) if parts else None

    # ------------------------------------------------------------------ maps
    def maps(self) -> list[_MapInfo]:
        if self._maps is None:
            self._maps = self._read_maps()
        return self._maps

    def _read_maps(self) -> list[_MapInfo]:
        import h5py

        out = []
        with h5py.File(self.path, "r") as f:
            paths = [k for k in self._keys if k.startswith("maps/") and k.endswith("/codes")]
            for p in sorted(paths):
                g = f[p.rsplit("/", 1)[0]]
                a = {k: _text(v) for k, v in g.attrs.items()}
                try:
                    fixed = json.loads(a.get("fixed", "{}"))
                except (TypeError, ValueError):
                    fixed = {}

                def get(name: str, *alt: str, _a=a, _fixed=fixed) -> Any:
                    for k in (name, *alt):
                        if k in _a:
                            return _a[k]
                        if k in _fixed:
                            return _fixed[k]
                    return None

                parts = g.name.strip("/").split("/")
                source = str(get("source") or (parts[1] if len(parts) > 2 else ""))
                shape = str(get("pulse_shape", "pulse") or "")
                td = _num(get("td_s"))
                m = re.fullmatch(r"pulse-(rect|halfsine|fullsine)-td([0-9.eE+-]+)", source)
                if m:
                    shape = shape or m.group(1)
                    td = td if math.isfinite(td) else _num(m.group(2))
                kind_src = str(get("source_kind") or ("pulse" if shape else "record"))
                out.append(
                    _MapInfo(
                        path=g.name,
                        kind=str(get("kind") or ""),
                        source=source,
                        source_kind=kind_src,
                        case=str(get("case") or ""),
                        isolation=str(get("isolation") or ""),
                        Tb_s=_num(get("Tb_s")),
                        xi_b=_num(get("xi_b")),
                        rho=_num(get("rho")),
                        mu_b=_num(get("mu_b")),
                        R_b_m=_num(get("R_b_m")),
                        lam=_num(get("lambda")),
                        R_m=_num(get("R_m")),
                        pulse=shape,
                        td_s=td,
                        amp_g=_num(get("amp_g")),
                        Tp_s=_num(get("Tp_s")),
                    )
                )
        return out

    def read_map(self, info: _MapInfo):
        import h5py

        from .store import read_map

        with h5py.File(self.path, "r") as f:
            return read_map(f[info.path])

    # ------------------------------------------------------------------ records
    def record_ids(self) -> list[str]:
        return sorted(k.split("/")[1] for k in self._keys if re.fullmatch(r"records/[^/]+", k))

    def record_sources(self) -> list[str]:
        """Ids of records present anywhere in the store (records, overturn tables, maps)."""
        ids = set(self.record_ids())
        ids |= {k.split("/")[1] for k in self._keys if re.fullmatch(r"overturn/[^/]+", k)}
        ids |= {m.source for m in self.maps() if m.source_kind == "record"}
        return sorted(ids)

    def record_attrs(self, rid: str) -> dict[str, Any]:
        import h5py

        if not self.has(f"records/{rid}"):
            return {}
        with h5py.File(self.path, "r") as f:
            return {k: _text(v) for k, v in f[f"records/{rid}"].attrs.items()}


def _norm(s: str) -> str:
    return re.sub(r"[^0-9a-z]", "", str(s).lower())


def _match_record(wanted: str, available: Iterable[str]) -> str | None:
    """The id in ``available`` that stands for the catalog id ``wanted`` (exact, then station code)."""
    available = list(available)
    for a in available:
        if _norm(a) == _norm(wanted):
            return a
    station = wanted.split("-", 1)[-1]
    hits = [a for a in available if station.lower() in {t.lower() for t in re.split(r"[^0-9A-Za-z]+", a)}]
    if len(hits) == 1:
        return hits[0]
    hits = [a for a in available if _norm(station) in _norm(a)]
    return hits[0] if len(hits) == 1 else None


def _pick_records(wanted: Sequence[str], available: Iterable[str]) -> tuple[list[str], list[str]]:
    """(ids found in the store, in the order of ``wanted``; catalog ids not found)."""
    available = list(available)
    found, missing = [], []
    for w in wanted:
        a = _match_record(w, available)
        if a is None or a in found:
            missing.append(w)
        else:
            found.append(a)
    return found, missing


def _letter(wanted: Sequence[str], rid: str, default: int) -> str:
    """Panel letter of a record: its position in the paper's list ``wanted`` (``a)``, ``b)`` ...)."""
    for i, w in enumerate(wanted):
        if _match_record(w, [rid]) == rid:
            return f"{chr(97 + i)})"
    return f"{chr(97 + default)})"


@functools.lru_cache(maxsize=1)
def _catalog_rows() -> dict[str, dict]:
    try:
        from .catalog import load_catalog

        return {r["id"]: r for r in load_catalog().to_dict("records")}
    except Exception:  # noqa: BLE001 - labels only: a broken catalog must not stop a figure
        return {}


def _record_title(store: _Store, rid: str, tp: float = math.nan) -> str:
    """``Event year, Station / component (Tp = .. s)`` from the store's record attributes or the catalog."""
    a = store.record_attrs(rid)
    label = str(a.get("label") or "")
    tp1 = _num(a.get("table1_tp_s"))
    if not label:
        row = _catalog_rows().get(rid)
        if row:
            label = f"{row['event']} {row['year']}, {row['station']} / {row['component']}"
            tp1 = _num(row.get("tp_s"))
        else:
            label = rid
    tp = tp1 if math.isfinite(tp1) else (tp if math.isfinite(tp) else _num(a.get("Tp_s")))
    return f"{label} ($T_p$ = {tp:.2f} s)" if math.isfinite(tp) else label


def _iso_label(
    iso: str,
    Tb: float = math.nan,
    xi: float = math.nan,
    mu: float = math.nan,
    Rb: float = math.nan,
    *,
    short: bool = False,
) -> str:
    """Readable name of an isolation case."""
    if iso == "none":
        return "non-isolated"
    if iso == "linear":
        s = rf"$T_b$ = {Tb:g} s, $\xi_b$ = {xi:g}"
        return s if short else f"linear isolator, {s}"
    if iso == "fp":
        s = rf"$\mu_b$ = {mu:g}, $R_b$ = {Rb:.2f} m"
        return s if short else f"FP isolator, {s}"
    return iso or "?"


def _map_iso_label(m: _MapInfo, short: bool = False) -> str:
    return _iso_label(m.isolation, m.Tb_s, m.xi_b, m.mu_b, m.R_b_m, short=short)


# ============================================================================================ drawing
def _new_figure(width: float, height: float):
    from matplotlib.figure import Figure

    return Figure(figsize=(width, height), layout="constrained")


def _save(fig, out_path: str | os.PathLike) -> Path:
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    out = Path(out_path)
    out.parent.mkdir(parents=True, exist_ok=True)
    FigureCanvasAgg(fig)
    fig.savefig(out, dpi=_RC["savefig.dpi"])
    return out


def _edges(v: np.ndarray) -> np.ndarray:
    """Cell edges around grid values (midpoints; half a step beyond the ends)."""
    v = np.asarray(v, dtype=float)
    if v.size == 1:
        d = 0.5 * abs(v[0]) or 0.5
        return np.array([v[0] - d, v[0] + d])
    mid = 0.5 * (v[1:] + v[:-1])
    lo = v[0] - (mid[0] - v[0])
    if v[0] > 0 > lo:  # a positive axis (R, Tb) does not start below zero
        lo = 0.0
    return np.concatenate([[lo], mid, [v[-1] + (v[-1] - mid[-1])]])


def _draw_map(ax, m, xlabel: str, ylabel: str) -> None:
    """A regime map as coloured cells (x along the first axis of ``codes``)."""
    from matplotlib.colors import BoundaryNorm, ListedColormap

    cmap = ListedColormap(list(REGIME_COLORS))
    norm = BoundaryNorm([-0.5, 0.5, 1.5, 2.5], cmap.N)
    ax.pcolormesh(
        _edges(m.x), _edges(m.y), np.asarray(m.codes).T, cmap=cmap, norm=norm, shading="flat", rasterized=True
    )
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(False)
    ax.set_xlim(_edges(m.x)[[0, -1]])
    ax.set_ylim(_edges(m.y)[[0, -1]])


def _regime_legend(fig) -> None:
    from matplotlib.patches import Patch

    handles = [
        Patch(facecolor=c, edgecolor="0.3", label=lab)
        for c, lab in zip(REGIME_COLORS, REGIME_LABELS, strict=True)
    ]
    fig.legend(handles=handles, loc="outside lower center", ncol=3, frameon=False)


def _colors(n: int) -> list:
    from matplotlib import colormaps

    cmap = colormaps["viridis"]
    return [cmap(x) for x in (np.linspace(0.0, 0.85, n) if n > 1 else [0.0] * n)]


def _axes_grid(fig, nrows: int, ncols: int, **kw):
    return fig.subplots(nrows, ncols, squeeze=False, **kw)


def _log_y(ax) -> None:
    """Logarithmic y axis labelled with plain numbers (1, 2, 5, 10 ...), not powers of ten."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    ax.set_yscale("log")
    plain = FuncFormatter(lambda v, _pos: f"{v:g}")
    ax.yaxis.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
    ax.yaxis.set_major_formatter(plain)
    ax.yaxis.set_minor_formatter(NullFormatter())


def _missing_text(missing: Sequence[str]) -> str:
    """Second suptitle line naming the paper's records that are not in the store."""
    return f"\n(not in the store: {', '.join(missing)})" if missing else ""


def _figure(name: str) -> Callable:
    """Decorator: run a figure function under the figure style; turn missing data into a logged skip."""

    def deco(fn: Callable) -> Callable:
        @functools.wraps(fn)
        def wrapper(*args: Any, **kw: Any) -> Path | None:
            import matplotlib

            try:
                with matplotlib.rc_context(_RC):
                    return fn(*args, **kw)
            except _Skip as exc:
                log.warning("%s skipped: %s", name, exc)
                return None

        return wrapper

    return deco


def _close(a: float, b: float, rtol: float = 1e-6) -> bool:
    return math.isfinite(a) and math.isfinite(b) and abs(a - b) <= rtol * max(abs(a), abs(b), 1e-12)


def _isclose_col(s, value: float, rtol: float = 1e-6):
    return np.isclose(s.astype(float), value, rtol=rtol, atol=1e-12)


# ============================================================================================ Fig 3
@_figure("Fig. 3")
def fig_3(
    h5: Any, out_path: str | os.PathLike, *, rhos: Sequence[float] | None = None, lam_max: float = 10.0
) -> Path | None:
    """Fig. 3: angular restitution ``eps`` and normalised ``beta1/h`` against slenderness for several ``rho``.

    Parameters
    ----------
    h5 : path-like or h5py object
        Store; its ``/pulses/restitution`` table is used when present, else the closed forms
        (paper Eqs. 29-30; no analysis needed). May name a missing file.
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
    import pandas as pd

    from .model import housner_restitution, impact_coefficients

    df = None
    try:
        df = _Store(h5).table("pulses/restitution")
    except _Skip:
        df = None
    source = "store table /pulses/restitution"
    if df is None or not {"lambda", "rho", "eps", "beta1_over_h"} <= set(df.columns):
        source = "closed forms (paper Eqs. 29-30)"
        rows = []
        for rho in rhos or (0.1, 0.25, 0.5, 1.0, 2.0):
            for lam in np.linspace(1.0, lam_max, 181):
                eps, beta1, _ = impact_coefficients(float(lam), 1.0, float(rho))
                rows.append(
                    {
                        "lambda": lam,
                        "rho": rho,
                        "eps": eps,
                        "beta1_over_h": beta1,
                        "eps_housner": housner_restitution(math.atan(1.0 / lam)),
                    }
                )
        df = pd.DataFrame(rows)
    df = df[df["lambda"] <= lam_max + 1e-9]
    values = sorted(df["rho"].unique()) if rhos is None else list(rhos)
    fig = _new_figure(9.5, 3.9)
    ax1, ax2 = fig.subplots(1, 2)
    for c, rho in zip(_colors(len(values)), values, strict=True):
        d = df[_isclose_col(df["rho"], rho)].sort_values("lambda")
        if d.empty:
            continue
        lam_min = math.sqrt(2 * (rho + 1) / (rho + 4))
        d = d[d["lambda"] > lam_min]
        ax1.plot(d["lambda"], d["eps"], color=c, label=rf"$\rho$ = {rho:g}")
        ax2.plot(d["lambda"], d["beta1_over_h"], color=c, label=rf"$\rho$ = {rho:g}")
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
def _pulse_tables(store: _Store, what: str):
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
    if "lambda" in df.columns and df["lambda"].nunique() == 1:
        parts.append(rf"$\lambda$ = {df['lambda'].iloc[0]:g}")
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
    store: _Store,
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
    store = _Store(h5)
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
    store = _Store(h5)
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

    store = _Store(h5)
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
    lam = df["lambda"].iloc[0] if "lambda" in df.columns else math.nan
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


# ============================================================================================ maps
def _lr_maps_for(store: _Store, source: str, isos: Sequence[str] | None = None) -> list[_MapInfo]:
    out = [
        m
        for m in store.maps()
        if m.kind == "lambda-R" and m.source == source and (isos is None or m.isolation in isos)
    ]
    return sorted(
        out, key=lambda m: (_ISO_ORDER.get(m.isolation, 9), m.Tb_s if math.isfinite(m.Tb_s) else 0, m.case)
    )


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
    store = _Store(h5)
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


def _record_lr_figure(
    store: _Store, out_path, *, wanted: Sequence[str], isolations: Sequence[str], title: str, what: str
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
                f"{_letter(wanted, rid, i)} {_record_title(store, rid, info.Tp_s)}\n"
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
        _Store(h5),
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
        _Store(h5),
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
        _Store(h5),
        out_path,
        wanted=records,
        isolations=isolations,
        title="Fig. 13 - response-regime spectra, linear vs FP isolation",
        what="Fig. 13",
    )


def _tbxi_maps(store: _Store, rid: str, lam: float | None, R: float | None) -> list[_MapInfo]:
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
    store = _Store(h5)
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
        ax.set_title(
            f"{_letter(records, rid, k)} {_record_title(store, rid, info.Tp_s)}\nPGA = {info.amp_g:.2f} g"
        )
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
    store = _Store(h5)
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
        f"{_record_title(store, rid, maps[0].Tp_s)} ($\\lambda$ = {lam:g}, $\\rho$ = {maps[0].rho:g})"
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

    store = _Store(h5)
    df = store.overturn()
    if df is None or df.empty:
        raise _Skip(f"no /overturn/<id> tables in {store.path} (rule min_overturn)")
    df = df[_isclose_col(df["lambda"], lam)]
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
def _first(g, names: Sequence[str]):
    for n in names:
        if n in g:
            return g[n]
    return None


@_figure("record figure")
def fig_record(h5: Any, record_id: str, out_path: str | os.PathLike) -> Path | None:
    """Processed acceleration and velocity of one record with the extracted velocity pulse overlaid.

    Parameters
    ----------
    h5 : path-like or h5py object
        Store with ``/records/<id>``: ``acc`` [m/s^2] (attribute ``dt_s`` [s]) and
        ``pulse/velocity``, ``pulse/pulse_velocity``, ``pulse/mp_velocity`` [m/s]; also accepted:
        ``vel`` and ``pulse_vel`` next to ``acc`` and the attribute ``dt``.
    record_id : str
        The record's group name.
    out_path : path-like
        Image to write.

    Notes
    -----
    Signature ``fig_record(h5, record_id, out_path)``: the record id comes before the output path.
    """
    import h5py
    from matplotlib.lines import Line2D

    store = _Store(h5)
    if not store.has(f"records/{record_id}"):
        raise _Skip(
            f"no /records/{record_id} in {store.path} (records: {', '.join(store.record_ids()) or 'none'})"
        )
    with h5py.File(store.path, "r") as f:
        g = f[f"records/{record_id}"]
        a = {k: _text(v) for k, v in g.attrs.items()}
        dacc = _first(g, ("acc", "acceleration"))
        if dacc is None:
            raise _Skip(f"/records/{record_id} has no acc dataset")
        acc = dacc[()].astype(float)
        dt = _num(dacc.attrs.get("dt_s", a.get("dt_s", a.get("dt"))))
        pg = g["pulse"] if "pulse" in g and isinstance(g["pulse"], h5py.Group) else g
        pa = {k: _text(v) for k, v in pg.attrs.items()}
        vel = _first(pg, ("velocity", "vel"))
        vel = vel[()] if vel is not None else None
        pulse = _first(pg, ("pulse_velocity", "pulse_vel"))
        pulse = pulse[()] if pulse is not None else None
        mp = _first(pg, ("mp_velocity", "mp_vel"))
        mp = mp[()] if mp is not None else None
    if not (math.isfinite(dt) and dt > 0):
        raise _Skip(f"/records/{record_id}: no time step (attribute dt_s)")
    t = np.arange(acc.size) * dt
    if vel is None:
        from scipy.integrate import cumulative_trapezoid

        vel = cumulative_trapezoid(acc, dx=dt, initial=0.0)
    fig = _new_figure(10.0, 6.0)
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
    pga = pga if math.isfinite(pga) else float(np.max(np.abs(acc))) / 9.81
    pgv = _num(a.get("pgv_m_s"))
    pgv = pgv if math.isfinite(pgv) else float(np.max(np.abs(vel)))
    tp1 = _num(a.get("table1_tp_s"))
    sub = f"PGA = {pga:.3f} g, PGV = {pgv:.3f} m/s"
    if math.isfinite(tp1):
        sub += f", Table 1 $T_p$ = {tp1:.2f} s"
    label = str(a.get("label") or record_id)
    fig.suptitle(f"Record {record_id}: {label}\n{sub}")
    return _save(fig, out_path)


# ============================================================================================ all
#: figure number -> (function, file name)
FIGURES: dict[int, tuple[Callable[..., Path | None], str]] = {
    3: (fig_3, "fig03_restitution.png"),
    4: (fig_4, "fig04_overturn_pulses.png"),
    5: (fig_5, "fig05_isolation_parameters.png"),
    6: (fig_6, "fig06_maps_pulses.png"),
    7: (fig_7, "fig07_linear_vs_fp.png"),
    8: (fig_8, "fig08_overturn_records.png"),
    9: (fig_9, "fig09_maps_records.png"),
    10: (fig_10, "fig10_maps_records.png"),
    11: (fig_11, "fig11_maps_Tb_xi.png"),
    12: (fig_12, "fig12_maps_Tb_xi_R.png"),
    13: (fig_13, "fig13_maps_linear_fp.png"),
}


def make_all(h5_path: str | os.PathLike, outdir: str | os.PathLike) -> list[Path]:
    """Draw every figure whose data are in the store, and one figure per record.

    Parameters
    ----------
    h5_path : path-like
        The store (``results/isorock.h5``).
    outdir : path-like
        Directory of the images (created): ``fig03_restitution.png`` ... ``fig13_*.png`` and
        ``record_<id>.png``.

    Returns
    -------
    list of Path
        The images written (figures skipped for want of data are logged, not listed).
    """
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []
    for _n, (fn, name) in FIGURES.items():
        p = fn(h5_path, outdir / name)
        if p is not None:
            written.append(p)
    try:
        ids = _Store(h5_path).record_ids()
    except _Skip as exc:
        log.warning("record figures skipped: %s", exc)
        ids = []
    for rid in ids:
        safe = re.sub(r"[^0-9A-Za-z_.+-]", "_", rid)
        p = fig_record(h5_path, rid, outdir / f"record_{safe}.png")
        if p is not None:
            written.append(p)
    return written
