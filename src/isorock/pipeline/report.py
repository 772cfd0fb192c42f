"""The report side of the workflow: HTML tables of the results for ``snakemake --report`` (rule
``report_tables``) and the figures (rule ``figures``), both read from the store through
:class:`isorock.store.Store`."""

from __future__ import annotations

import html
import json
import os
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import pandas as pd

from .. import figures as fig
from ..store import Store, atomic_path
from .jobs import say

__all__ = ["report_tables", "figures"]

_CSS = """
body { font-family: sans-serif; font-size: 13px; margin: 1em; }
table { border-collapse: collapse; margin-bottom: 1em; }
th, td { border: 1px solid #bbb; padding: 2px 6px; text-align: right; }
th { background: #eee; }
td:first-child, th:first-child { text-align: left; }
"""


def _html(path: Path, title: str, parts: Sequence[tuple[str, Any]], digits: int = 4) -> None:
    """Write an HTML page of (paragraph or heading text, DataFrame or None) parts, atomically.

    Floats are printed with ``digits`` significant digits.
    """
    body = [f"<h3>{html.escape(title)}</h3>"]
    for text, df in parts:
        if text:
            body.append(f"<p>{html.escape(text)}</p>")
        if df is not None:
            body.append(
                df.to_html(index=False, na_rep="-", float_format=lambda x: f"{x:.{digits}g}", border=0)
            )
    page = (
        f'<!DOCTYPE html>\n<html><head><meta charset="utf-8"><title>{html.escape(title)}</title>'
        f"<style>{_CSS}</style></head><body>\n" + "\n".join(body) + "\n</body></html>\n"
    )
    with atomic_path(path) as tmp:
        tmp.write_text(page, encoding="utf-8")


_REC_COLS = {
    "record": "record", "label": "label", "component": "component", "azimuth_deg": "azimuth [deg]",
    "component_method": "direction", "pga_g": "PGA [g]", "pgv_m_s": "PGV [m/s]", "Tp_s": "Tp wavelet [s]",
    "Tp_mp_s": "Tp MP [s]", "Tp_br_s": "Tp BR [s]", "Tp_method_s": "Tp, Table 1 method [s]",
    "table1_tp_s": "Table 1 Tp [s]", "tp_error_pct": "Tp error [%]", "pulse_like": "pulse-like",
    "table1_pga_g": "Table 1 PGA [g]", "table1_pgv_m_s": "Table 1 PGV [m/s]", "qa_passed": "QA passed",
    "component_qa": "QA mark", "source_file": "file",
}  # fmt: skip
#: a Tp within this relative error of the catalog's counts as reproduced
TP_TOLERANCE = 0.15


def _files(source_file: str, rotated_from: str) -> str:
    """The file name(s) a record comes from: both of a rotation."""
    try:
        parts = json.loads(rotated_from) if isinstance(rotated_from, str) and rotated_from else []
    except ValueError:
        parts = []
    return " + ".join(Path(p["file"]).name for p in parts) if parts else Path(source_file).name


def tp_agreement(rec: pd.DataFrame) -> tuple[int, int]:
    """Records with a catalog Tp, and those whose Tp by the catalog's method is within
    :data:`TP_TOLERANCE` of it (substitute files left out)."""
    have = rec[rec["table1_tp_s"].notna() & rec["Tp_method_s"].notna() & ~rec["substitute"].astype(bool)]
    ok = (have["Tp_method_s"] / have["table1_tp_s"] - 1.0).abs() <= TP_TOLERANCE
    return int(ok.sum()), len(have)


_MAP_COLS = ["map", "kind", "case", "amp_g", "amp_source", "nx", "ny", "no_uplift", "rocking", "overturn"]


def _overturn_pivot(df):
    piv = df.pivot_table(
        index=["record", "lambda_", "R_m"],
        columns="case",
        values="min_overturn_g",
        aggfunc="first",
        dropna=False,
    ).reset_index()
    piv.columns.name = None
    return piv.rename(columns={"lambda_": "lambda [-]", "R_m": "R [m]"})


def report_tables(h5: str | os.PathLike, outdir: str | os.PathLike) -> list[Path]:
    """Rule ``report_tables``: HTML tables of the results for the Snakemake report.

    Writes into ``outdir``: ``records.html`` (record, PGA, PGV, Tp), ``overturn.html`` (minimum
    overturning PGA [g] per record, block and isolation case), ``maps.html`` (regime counts of every
    map) and ``records/<id>.html`` (one page per record: its values, Tp, its minimum overturning
    PGA per block and its maps).
    """
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    store = Store(h5)
    src = str(store.root_attrs.get("record_source", ""))
    rec = store.table("summary/records")
    ovt = store.table("summary/overturn")
    mps = store.table("summary/maps")
    tp_note = ""
    if rec is not None:
        ok, n = tp_agreement(rec)
        if n:
            tp_note = (
                f" Tp by the method of each Table 1 source is within {100 * TP_TOLERANCE:.0f} % of "
                f"Table 1 for {ok} of {n} records."
            )
        rec = rec.copy()
        rec["tp_error_pct"] = (100.0 * (rec["Tp_method_s"] / rec["table1_tp_s"] - 1.0)).round(1)
        rec["source_file"] = [
            _files(f, r) for f, r in zip(rec["source_file"], rec["rotated_from"], strict=True)
        ]
        rec = rec[list(_REC_COLS)]
    out = []
    note_tp = (
        "Tp: velocity-pulse period by the db4 wavelet (Baker 2007), the Mavroeidis-Papageorgiou (2003) fit "
        "(MP) and twice the PGV half-cycle (Bray & Rodriguez-Marek 2004, BR); 'Table 1 method' is the "
        "definition of the row's published value. Component: the direction analysed (SN/SP rotated from "
        "two recorded components, provided, or a recorded one; a QA mark says when it is not the "
        "paper's)."
    )
    p = outdir / "records.html"
    _html(
        p,
        "Records",
        [
            (f"Processed records ({src or 'none'}). {note_tp}{tp_note}", None),
            ("", rec.rename(columns=_REC_COLS) if rec is not None else pd.DataFrame({"record": []})),
        ],
    )
    out.append(p)
    res = None if ovt is None else ovt["resolution"].dropna()
    res_txt = (
        f" Each value is uncertain by the scan step of the search, {100 * res.max():.2g} % (printed "
        "to 3 significant digits)."
        if res is not None and len(res)
        else ""
    )
    note_ov = (
        "Smallest PGA [g] of the scaled record that overturns the block, per block (lambda = h/b, "
        "R = half-diagonal) and isolation case; '-' = no overturn up to the largest PGA searched." + res_txt
    )
    p = outdir / "overturn.html"
    _html(
        p,
        "Minimum overturning PGA [g]",
        [(note_ov, _overturn_pivot(ovt) if ovt is not None else pd.DataFrame({"record": []}))],
        digits=3,
    )
    out.append(p)
    p = outdir / "maps.html"
    note_maps = "Number of grid points in each regime (no uplift, rocking, overturn) of every map."
    cols = ["source"] + _MAP_COLS + ["seconds"]
    _html(
        p, "Response-regime maps", [(note_maps, mps[cols] if mps is not None else pd.DataFrame({"map": []}))]
    )
    out.append(p)
    pages = outdir / "records"
    pages.mkdir(exist_ok=True)
    for r in [] if rec is None else rec.to_dict("records"):
        rid = r["record"]
        one = pd.DataFrame([r]).rename(columns=_REC_COLS)
        parts = [(note_tp, one)]
        if ovt is not None and (ovt["record"] == rid).any():
            parts.append((note_ov, _overturn_pivot(ovt[ovt["record"] == rid]).drop(columns="record")))
        if mps is not None and (mps["source"] == rid).any():
            parts.append((note_maps, mps[mps["source"] == rid][_MAP_COLS]))
        q = pages / f"{rid}.html"
        _html(q, f"{rid}: {r['label']}", parts, digits=3)
        out.append(q)
    return out


def figures(h5: str | os.PathLike, outdir: str | os.PathLike) -> list[Path]:
    """Rule ``figures``: the paper's figures from the store (:func:`isorock.figures.make_all`)."""
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        paths = fig.make_all(h5, outdir)
    say(f"{len(paths)} figures in {outdir}")
    return [Path(p) for p in paths]
