"""Shared pieces of the figures: the paper's colour code, axis labels, the figure style, drawing
helpers, and the matching of the paper's record ids to the records of a store."""

from __future__ import annotations

import functools
import logging
import math
import os
import re
from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from isorock.constants import PULSE_SHAPES
from isorock.errors import CatalogError
from isorock.records.catalog import load_catalog
from isorock.store import MapInfo, Store, StoreNotFound

log = logging.getLogger("isorock.figures")

REGIME_COLORS = ("#00e5ee", "#2ecc40", "#e8251f")
#: legend names of the regimes
REGIME_LABELS = ("No uplift", "Rocking", "Overturning")

SHAPE_NAMES = {"rect": "rectangular pulse", "halfsine": "half-sine pulse", "fullsine": "full-sine pulse"}
_SHAPES = PULSE_SHAPES

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


def _num(v: Any) -> float:
    """A value as float (NaN when it is not a number)."""
    try:
        return float(v)
    except (TypeError, ValueError):
        return math.nan


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
    """Table 1 rows by id, for labels of stores that lack them (empty when the catalog is unreadable)."""
    try:
        return {r["id"]: r for r in load_catalog().to_dict("records")}
    except CatalogError:
        return {}


def _record_title(store: Store, rid: str, tp: float = math.nan) -> str:
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


def _map_iso_label(m: MapInfo, short: bool = False) -> str:
    return _iso_label(m.isolation, m.Tb_s, m.xi_b, m.mu_b, m.R_b_m, short=short)


# ============================================================================================ drawing
def _new_figure(width: float, height: float, margins: Mapping[str, float] | None = None):
    """A figure of ``width`` x ``height`` inches, laid out by matplotlib's constrained layout, or with
    fixed ``margins`` (:meth:`~matplotlib.figure.Figure.subplots_adjust`'s fractions of the figure):
    the layout costs a figure a second drawing, which a figure drawn once per record cannot afford."""
    from matplotlib.figure import Figure

    if margins is None:
        return Figure(figsize=(width, height), layout="constrained")
    fig = Figure(figsize=(width, height))
    fig.subplots_adjust(**margins)
    return fig


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
            except (_Skip, StoreNotFound) as exc:
                log.warning("%s skipped: %s", name, exc)
                return None

        return wrapper

    return deco


def _close(a: float, b: float, rtol: float = 1e-6) -> bool:
    return math.isfinite(a) and math.isfinite(b) and abs(a - b) <= rtol * max(abs(a), abs(b), 1e-12)


def _isclose_col(s, value: float, rtol: float = 1e-6):
    return np.isclose(s.astype(float), value, rtol=rtol, atol=1e-12)
