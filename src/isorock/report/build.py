"""The report side of the workflow: the pages of ``snakemake --report`` (rule ``report_tables``) and
the figures (rule ``figures``), read from the store through :class:`isorock.store.Store`.

Pages: ``assessment.html`` (the assessment of the objects: the verdicts and their short tables first,
then the conclusions, the summary table, fragility, displacement and design figures), ``paper.html``
(where this model departs from the paper's conclusions, with the cases and the mechanism),
``overturn.html`` (minimum overturning PGA per record, block and
isolation case, beside the record's PGA, with the blocks that overturn below it and the cases where
isolation makes things worse; all of it in ``overturn.csv``), ``records.html`` (records, component,
Tp), ``maps.html`` (every map's regime counts, also in ``maps.csv``, each record's maps and the pulse
maps) and ``records/<id>.html`` (one page per record: its quantities, one per row, its tables and its
figures). A record's figures are linked from ``results/figures``, not embedded: inside the Snakemake
report they are under 'Figures', grouped, so that the report embeds each figure once. Every page links
back to the report it belongs to (``report``). The landing page of the report
(:mod:`isorock.report.landing`) opens with the results.

Each page is a Jinja2 template of ``isorock/report/templates`` (``<page>.html.j2``, extending
``base.html.j2``: head, CSS, navigation, footer), rendered with autoescaping by
:mod:`isorock.report.html`; this module computes the values and the tables. The report embeds every
page as a data URL, and Chromium shows none longer than 2 MiB: a page stays under
:data:`MAX_PAGE_BYTES` (tables longer than :data:`MAX_TABLE_ROWS` rows are cut, with the whole table in
a CSV file beside the page; then figures are left out, naming where they are).
"""

from __future__ import annotations

import base64
import json
import math
import os
import re
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from markupsafe import Markup

from isorock import figures as fig
from isorock.assessment.summary import assessment_summary
from isorock.assessment.tables import LEGEND, candidates_table, short_table, summary_table
from isorock.control.joblog import say
from isorock.report.html import render_html, table_html
from isorock.store import Store, atomic_path

__all__ = [
    "report_tables",
    "figures",
    "overturn_table",
    "tp_agreement",
    "TP_TOLERANCE",
    "MAX_PAGE_BYTES",
    "MAX_TABLE_ROWS",
]

#: the largest page written (its data URL in the report is 4/3 as long; Chromium's limit is 2 MiB)
MAX_PAGE_BYTES = 1024 * 1024
#: rows of a table printed on a page; the whole table goes to a CSV file beside the page
MAX_TABLE_ROWS = 400


@dataclass
class Table:
    """A table of a page: its HTML (:func:`isorock.report.html.table_html`), its rows, and where it
    was cut at :data:`MAX_TABLE_ROWS`, the rows shown and the CSV file beside the page with all of them."""

    html: Markup
    rows: int
    shown: int
    csv: str | None = None


@dataclass
class Figure:
    """A figure of a page: the PNG file's name and its base64 data, or left out to keep the page small."""

    name: str
    data: str
    left_out: bool = False


class _Page:
    """A page of ``results/report``, written from its template (``templates/<page>.html.j2``).

    Its tables and figures are made by :meth:`table` and :meth:`figure`, in the order they appear on
    the page: a table of more than :data:`MAX_TABLE_ROWS` rows is cut there, the whole of it written to
    ``<page>.csv`` (the first such table; the next ``<page>-2.csv`` ...); a page still over
    :data:`MAX_PAGE_BYTES` loses its figures, last first, each replaced by a line naming it.
    """

    def __init__(
        self, path: Path, *, digits: int = 4, root: str = "", report: str | os.PathLike | None = None
    ) -> None:
        self.path, self.digits, self.root = path, digits, root
        #: the way from the page to the report it links back to ('' when none is named)
        self.back = (
            ""
            if report is None
            else Path(os.path.relpath(Path(report).resolve(), path.parent.resolve())).as_posix()
        )
        self.figures: list[Figure] = []
        self.n_csv = 0

    def table(self, df: pd.DataFrame | None) -> Table | None:
        """``df`` on the page, floats with the page's significant digits, a record's own quantities
        (:data:`RECORD_COLUMNS`) with :data:`RECORD_DIGITS` on every page (None: no table)."""
        if df is None:
            return None
        rows, csv = len(df), None
        if rows > MAX_TABLE_ROWS:
            self.n_csv += 1
            p = self.path.with_name(f"{self.path.stem}{'' if self.n_csv == 1 else f'-{self.n_csv}'}.csv")
            with atomic_path(p) as tmp:
                df.to_csv(tmp, index=False)
            df, csv = df.head(MAX_TABLE_ROWS), p.name
        digits = self.digits
        own = {c: _number(RECORD_DIGITS) for c in df.columns if c in RECORD_COLUMNS}
        return Table(table_html(df, lambda x: f"{x:.{digits}g}", own), rows, len(df), csv)

    def figure(self, path: str | os.PathLike | None) -> Figure | None:
        """The image file ``path`` embedded in the page (base64), or None if it does not exist."""
        if path is None or not Path(path).is_file():
            return None
        self.figures.append(Figure(Path(path).name, base64.b64encode(Path(path).read_bytes()).decode()))
        return self.figures[-1]

    def write(self, template: str, title: str, **values: Any) -> Path:
        """Render ``template`` with ``values`` and write the page atomically; returns its path."""
        values = {
            "title": title, "current": template.removesuffix(".j2"), "root": self.root, "back": self.back,
            **values,
        }  # fmt: skip
        page = render_html(template, **values)
        for figure in reversed(self.figures):
            if len(page.encode()) <= MAX_PAGE_BYTES:
                break
            figure.left_out = True
            page = render_html(template, **values)
        with atomic_path(self.path) as tmp:
            tmp.write_text(page, encoding="utf-8")
        return self.path


_REC_COLS = {
    "record": "record", "label": "label", "component": "component", "azimuth_deg": "azimuth [deg]",
    "component_method": "direction", "pga_g": "PGA [g]", "pgv_m_s": "PGV [m/s]", "Tp_s": "Tp wavelet [s]",
    "Tp_mp_s": "Tp MP [s]", "Tp_br_s": "Tp BR [s]", "Tp_method_s": "Tp, Table 1 method [s]",
    "table1_tp_s": "Table 1 Tp [s]", "tp_error_pct": "Tp error [%]", "pulse_like": "pulse-like",
    "table1_pga_g": "Table 1 PGA [g]", "table1_pgv_m_s": "Table 1 PGV [m/s]", "qa_passed": "QA passed",
    "component_qa": "QA mark", "source_file": "file",
}  # fmt: skip
#: significant digits of a record's own quantities (PGA, PGV, Tp ...), the same on every page that
#: prints them: the records table, a record's page and the record's PGA beside the overturning PGA
RECORD_DIGITS = 4
#: the columns of a record's own quantities, printed with :data:`RECORD_DIGITS`
RECORD_COLUMNS = frozenset(v for k, v in _REC_COLS.items() if k not in ("record", "label")) | {
    "record PGA [g]"
}


def _number(digits: int):
    """A cell's text: a float with ``digits`` significant digits, '-' for a missing one."""

    def fmt(x: Any) -> str:
        if isinstance(x, (float, np.floating)):
            return "-" if not math.isfinite(x) else f"{x:.{digits}g}"
        return "-" if x is None else str(x)

    return fmt


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


def overturn_table(ovt: pd.DataFrame) -> pd.DataFrame:
    """The minimum overturning PGA [g] per record and block (rows) and isolation case (columns, in the
    configuration's order: ``none`` first), beside the block's dimensions and the record's PGA, with
    two flags: the cases whose block overturns below the record's PGA (the record as recorded
    overturns it), and the isolated cases whose minimum is lower than the non-isolated block's by more
    than the search's resolution (isolation makes things worse)."""
    cases = list(dict.fromkeys(ovt["case"]))
    kinds = dict(zip(ovt["case"], ovt["isolation"], strict=False))
    rows = []
    for (rid, lam, R), g in ovt.groupby(["record", "lambda_", "R_m"], sort=False):
        g = g.set_index("case")
        first = g.iloc[0]
        pga = float(first["record_pga_g"])
        row = {
            "record": rid,
            "record PGA [g]": pga,
            "lambda [-]": lam,
            "R [m]": R,
            "b [m]": float(first["b_m"]),
            "h [m]": float(first["h_m"]),
        }
        for c in cases:
            row[c] = float(g.loc[c, "min_overturn_g"]) if c in g.index else math.nan
        below = [c for c in cases if row[c] < pga]
        res = float(g["resolution"].max()) if g["resolution"].notna().any() else 0.0
        none = next((row[c] for c in cases if kinds[c] == "none"), math.nan)
        worse = [
            c
            for c in cases
            if kinds[c] != "none"
            and math.isfinite(row[c])
            and math.isfinite(none)
            and row[c] < none * (1 - res)
        ]
        row["overturns below the record's PGA"] = ", ".join(below)
        row["isolation worse than none"] = ", ".join(f"{c} ({row[c]:.3g} vs {none:.3g} g)" for c in worse)
        rows.append(row)
    return pd.DataFrame(rows)


def report_tables(
    h5: str | os.PathLike,
    outdir: str | os.PathLike,
    figdir: str | os.PathLike | None = None,
    report: str | os.PathLike | None = None,
) -> list[Path]:
    """Rule ``report_tables``: the report's pages (see the module docstring) and its landing text.

    Parameters
    ----------
    h5 : path-like
        The store.
    outdir : path-like
        Directory of the pages (``results/report``).
    figdir : path-like, optional
        The figures of rule ``figures`` (``results/figures``), embedded in the pages.
    report : path-like, optional
        The report the pages belong to (``report.html``, the one ``isorock report`` writes): every
        page links back to it (none: no link).
    """
    from isorock.report.landing import write_landing

    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    figdir = Path(figdir) if figdir is not None else None
    store = Store(h5)
    src = str(store.root_attrs.get("record_source", ""))
    rec = store.table("summary/records")
    ovt = store.table("summary/overturn")
    mps = store.table("summary/maps")
    out = [_assessment_page(store, outdir / "assessment.html", figdir, report)]
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
        # a QA mark is written only where the direction analysed is not the catalog row's: a column
        # empty on every row says nothing, and is left out
        if not rec["component_qa"].fillna("").astype(str).str.strip().any():
            rec = rec.drop(columns="component_qa")
    note_tp = (
        "Tp: velocity-pulse period by the db4 wavelet (Baker 2007), the Mavroeidis-Papageorgiou (2003) fit "
        "(MP) and twice the PGV half-cycle (Bray & Rodriguez-Marek 2004, BR); 'Table 1 method' is the "
        "definition of the row's published value. Component: the direction analysed (SN/SP rotated from "
        "two recorded components, provided, or a recorded one"
        + (
            "; a QA mark says when it is not the paper's)."
            if rec is not None and "component_qa" in rec
            else ")."
        )
    )
    page = _Page(outdir / "records.html", report=report)
    records = rec.rename(columns=_REC_COLS) if rec is not None else pd.DataFrame({"record": []})
    out.append(
        page.write(
            "records.html.j2", "Records", source=src, tp_note=note_tp, tp_agreement=tp_note,
            records=page.table(records),
        )
    )  # fmt: skip
    res = None if ovt is None else ovt["resolution"].dropna()
    res_txt = (
        f" Each value is uncertain by the scan step of the search, {100 * res.max():.2g} % (printed "
        "to 3 significant digits)."
        if res is not None and len(res)
        else ""
    )
    note_ov = (
        "Smallest PGA [g] of the scaled record that overturns the block, per block (lambda = h/b, R = "
        "half-diagonal, b and h the half-width and half-height) and isolation case; '-' = no overturn "
        "up to the largest PGA searched. A block that overturns below the record's own PGA overturns "
        "under the record as recorded; 'isolation worse' lists the isolated cases that need a lower "
        "PGA to overturn than the block on the ground." + res_txt
    )
    table = overturn_table(ovt) if ovt is not None else None
    _csv(outdir / "overturn.csv", ovt, _OVT_CSV)
    page = _Page(outdir / "overturn.html", digits=3, report=report)
    ovt_table = page.table(table if table is not None else pd.DataFrame({"record": []}))
    out.append(
        page.write("overturn.html.j2", "Minimum overturning PGA [g]", note=note_ov, overturn=ovt_table)
    )
    note_maps = "Number of grid points in each regime (no uplift, rocking, overturn) of every map."
    cols = ["source"] + _MAP_COLS + ["seconds"]
    _csv(outdir / "maps.csv", mps, cols)
    page = _Page(outdir / "maps.html", report=report)
    maps = page.table(mps[cols] if mps is not None else pd.DataFrame({"map": []}))
    pulse_maps = mps is not None and bool(mps["source"].str.startswith("pulse-").any())
    pulses = page.figure(_fig(figdir, "fig06_maps_pulses", None)) if pulse_maps else None
    # the maps of each record, linked from results/figures as on a record's page (embedded, they are
    # the report's 'Figures', per record: regime maps)
    sources = [] if mps is None else list(dict.fromkeys(mps["source"]))
    record_maps = _linked(figdir, outdir, [(r, f"maps_{_safe(r)}.png") for r in sources])
    out.append(
        page.write("maps.html.j2", "Response-regime maps", note=note_maps, maps=maps, pulse_maps=pulse_maps,
                   pulses=pulses, record_maps=record_maps)
    )  # fmt: skip
    pages = outdir / "records"
    pages.mkdir(exist_ok=True)
    for r in [] if rec is None else rec.to_dict("records"):
        rid = r["record"]
        page = _Page(pages / f"{rid}.html", digits=3, root="../", report=report)
        # one record: a quantity per row (as a row of 19 columns it was cut at the frame's edge)
        fmt = _number(RECORD_DIGITS)
        one = page.table(
            pd.DataFrame({"quantity": [_REC_COLS[k] for k in r], "value": [fmt(v) for v in r.values()]})
        )
        # the figures of a record are under 'Figures' (one per group): embedded here too they would
        # double the report's size, so the page shows them from results/figures by a relative link
        safe = _safe(rid)
        names = [f"{kind}_{safe}.png" for kind in ("record", "overturn", "maps")]
        shown = _linked(figdir, pages, [(n, n) for n in names])
        if figdir is not None:  # only the figures drawn (an assessment draws no maps of a record)
            names = [f["name"] for f in shown]
        rec_ov = None
        if table is not None and (table["record"] == rid).any():
            rec_ov = page.table(table[table["record"] == rid].drop(columns="record"))
        rec_maps = None
        if mps is not None and (mps["source"] == rid).any():
            rec_maps = page.table(mps[mps["source"] == rid][_MAP_COLS])
        out.append(
            page.write(
                "record.html.j2", f"{rid}: {r['label']}", current="records.html", tp_note=note_tp, record=one,
                figures=names, shown=shown, overturn_note=note_ov, overturn=rec_ov, maps_note=note_maps,
                maps=rec_maps,
            )
        )  # fmt: skip
    vt = vertical_table(ovt, store.table("summary/records"), vertical_down_g(store))
    out.append(_paper_page(outdir / "paper.html", table, vt, report))
    out.append(write_landing(store, outdir / "landing.rst", figdir, table))
    return out


#: where this model departs from the paper's conclusion on the uplift (the numbers are asserted by
#: tests/analysis/test_paper_claims.py, test_c1_disagrees_*)
PAPER_DEPARTURE = (
    "The paper concludes that seismic isolation raises the acceleration needed to start rocking "
    "'regardless of block size and excitation period'. This model, whose engine is checked against an "
    "independent oscillator and closed forms, shows where it does not. The mechanism: a damped isolator "
    "amplifies the total acceleration of the base for an input long compared with its own period or close "
    "to it (the overshoot of a damped oscillator), and a block starts rocking when the base's "
    "acceleration, not the ground's, exceeds g tan(alpha). The more damping, the larger that "
    "overshoot for a step-like input, and the larger the share of a short pulse passed on through the "
    "damper. The isolator does raise the uplift acceleration under short pulses and under the broad-band "
    "records tried with enough damping; a design must check its own case, which the assessment does."
)
_PAPER_CASES = pd.DataFrame(
    [
        {
            "input": "full-sine pulse, half-cycle 1.5 s (period 3 s)",
            "isolator": "linear, Tb 3 s, xi 0.35, rho 0.5",
            "the paper": "uplift raised",
            "this model": "the base amplifies the input 1.57 times: uplift at 0.636 g tan(alpha), "
            "lower than on the ground",
        },
        {
            "input": "Imperial Valley 1979, El Centro Meloland (IMV79-EMO, strike-normal)",
            "isolator": "linear, Tb 2 s, xi 0.2, rho 0.5",
            "the paper": "uplift raised",
            "this model": "uplift at a PGA of 0.243 g against 0.25 g on the ground (lambda 4); with xi "
            "0.35 it is raised (x 1.25)",
        },
    ]
)


def vertical_down_g(store: Store) -> dict[str, float]:
    """The largest downward vertical acceleration of each record that has a vertical [g] (processed,
    unscaled): ``-min(a_v) / g``; the block leaves its base where the scaled value passes 1."""
    import h5py

    from isorock.constants import G

    out: dict[str, float] = {}
    with h5py.File(store.path, "r") as h:
        for rid, g in h.get("records", {}).items():
            if "vertical" in g:
                out[rid] = float(-np.min(g["vertical"][()])) / G
    return out


def vertical_table(
    ovt: pd.DataFrame | None, rec: pd.DataFrame | None, down_g: dict[str, float] | None = None
) -> pd.DataFrame | None:
    """The vertical's effect on the minimum overturning PGA [g]: one row per record that has a vertical,
    block and isolation case, horizontal only beside with the vertical (scaled with the horizontal),
    their ratio, the vertical's peak, and whether its largest downward value (``down_g``: per record,
    unscaled [g], :func:`vertical_down_g`) lifts the block off at that PGA; None when no record has
    one."""
    if ovt is None or "min_overturn_hv_g" not in ovt:
        return None
    v = ovt[np.isfinite(ovt["min_overturn_hv_g"].to_numpy(dtype=float))]
    if v.empty:
        return None
    peaks = {} if rec is None else dict(zip(rec["record"], rec.get("vertical_pga_g", []), strict=False))
    comp = {} if rec is None else dict(zip(rec["record"], rec.get("vertical_component", []), strict=False))
    out = pd.DataFrame(
        {
            "record": v["record"],
            "vertical": [comp.get(r, "") for r in v["record"]],
            "vertical peak / record PGA [-]": [
                peaks.get(r, math.nan) / p for r, p in zip(v["record"], v["record_pga_g"], strict=True)
            ],
            "lambda [-]": v["lambda_"],
            "R [m]": v["R_m"],
            "case": v["case"],
            "horizontal only [g]": v["min_overturn_h_g"],
            "with the vertical [g]": v["min_overturn_hv_g"],
        }
    )
    out["ratio [-]"] = out["with the vertical [g]"] / out["horizontal only [g]"]
    out["vertical peak there [g]"] = out["vertical peak / record PGA [-]"] * out["with the vertical [g]"]
    # g + a_v < 0 needs a downward vertical beyond g, at the scale of the overturning PGA
    down = np.array(
        [(down_g or {}).get(r, math.nan) / p for r, p in zip(v["record"], v["record_pga_g"], strict=True)]
    )
    out["downward peak there [g]"] = down * out["with the vertical [g]"].to_numpy(dtype=float)
    out["jumps"] = np.where(out["downward peak there [g]"] > 1.0, "yes (g + a_v < 0)", "")
    return out


#: what the paper page says of the vertical ground motion
VERTICAL_NOTE = (
    "The vertical ground motion, which the paper leaves out: the minimum overturning PGA of each record "
    "that has a vertical component, horizontal only and with its vertical (scaled with the horizontal, so "
    "their ratio stays the recorded one), for the blocks and isolation cases of the study. With the "
    "vertical, g becomes g + a_v in the block's equations, in the uplift threshold (g + a_v) tan(alpha) and "
    "in the friction pendulum's forces; a ratio below 1 means the vertical makes overturning easier. "
    "Vertical positive up as the file gives it (PEER's NGA-West2 vertical files are named '-up'). Where "
    "the vertical's largest downward value at the overturning PGA passes 1 g (column 'jumps'), g + a_v "
    "falls below zero at some instant: the block would leave its base, which the model excludes, and "
    "that row is outside it. The analyses of the other pages use the vertical only with "
    "records.vertical: true in the configuration."
)


def _linked(figdir: Path | None, page_dir: Path, figures: list[tuple[str, str]]) -> list[dict[str, str]]:
    """The figures (caption, file name) found in ``figdir``, each with its link from ``page_dir``."""
    if figdir is None:
        return []
    return [
        {"name": name, "src": Path(os.path.relpath(figdir / file, page_dir)).as_posix()}
        for name, file in figures
        if (figdir / file).is_file()
    ]


def _paper_page(
    path: Path,
    overturn: pd.DataFrame | None,
    vertical: pd.DataFrame | None = None,
    report: str | os.PathLike | None = None,
) -> Path:
    """The page 'The paper': where this model departs from the paper's conclusions, with the cases and
    the mechanism, what this run's minimum-overturning study shows of it, and the vertical's effect
    (:func:`vertical_table`) where records have one; it links back to ``report``."""
    page = _Page(path, report=report)
    cases = page.table(_PAPER_CASES)
    in_this_run = ""
    if overturn is not None and not overturn.empty and "isolation worse than none" in overturn:
        worse = overturn["isolation worse than none"].astype(str)
        n = int((worse != "").sum())
        in_this_run = (
            f"In this run: {n} of {len(overturn)} record-block pairs overturn at a lower PGA on at least "
            "one isolator than on the ground (the column 'isolation worse than none' of 'Minimum "
            "overturning PGA')."
        )
    if vertical is not None:
        r = vertical["ratio [-]"].to_numpy(dtype=float)
        jumps = (vertical["jumps"] != "").to_numpy()
        ok = np.isfinite(r) & ~jumps
        summary = (
            f" Over the {int(ok.sum())} rows where both overturn and the block does not jump: the ratio runs "
            f"from {r[ok].min():.3g} to {r[ok].max():.3g} (median {np.median(r[ok]):.3g})"
            if ok.any()
            else " No row overturns both ways without jumping"
        ) + f"; {int(jumps.sum())} of {len(r)} rows jump."
        vertical_note = VERTICAL_NOTE + summary
    else:
        vertical_note = VERTICAL_NOTE + " No record of this run has a vertical component."
    return page.write(
        "paper.html.j2", "Where this model departs from the paper", departure=PAPER_DEPARTURE, cases=cases,
        in_this_run=in_this_run, vertical_note=vertical_note, vertical=page.table(vertical),
    )  # fmt: skip


_OVT_CSV = ["record", "lambda_", "R_m", "b_m", "h_m", "case", "isolation", "min_overturn_g", "record_pga_g"]


def _csv(path: Path, df: pd.DataFrame | None, cols: list[str]) -> None:
    """``df[cols]`` as a CSV file (only the header when there is no table), atomically."""
    out = pd.DataFrame(columns=cols) if df is None else df[[c for c in cols if c in df.columns]]
    with atomic_path(path) as tmp:
        out.rename(columns={"lambda_": "lambda"}).to_csv(tmp, index=False)


def _safe(name: str) -> str:
    return re.sub(r"[^0-9A-Za-z_.+-]", "_", name)


def _fig(figdir: Path | None, kind: str, name: str | None) -> Path | None:
    """The figure file ``<kind>_<name>.png`` (or ``<kind>.png``) of ``figdir``."""
    if figdir is None:
        return None
    return figdir / (f"{kind}_{_safe(name)}.png" if name else f"{kind}.png")


#: the words and symbols of the assessment page, each with the pattern that finds it in the page's
#: text and what it means; the page's glossary lists those it uses
GLOSSARY: tuple[tuple[str, str, str], ...] = (
    ("PGA", r"\bPGA\b", "peak ground acceleration [g]: the records are scaled to each level of it"),
    ("design level", r"\bdesign level", "the level of shaking the object is judged at (assessment.design_g)"),
    (
        "MCE",
        r"\bMCE\b",
        "maximum considered earthquake: the rarer level (assessment.mce_g, or read off "
        "the hazard curve) at which the collapse and the isolator's displacement are checked",
    ),
    (
        "S_DS, S_MS",
        r"\bS_(?:DS|MS)\b",
        "the design and MCE spectral accelerations at short periods of ASCE/SEI 7 [g]; S_MS = 1.5 S_DS",
    ),
    (
        "stripe",
        r"\bstripes?\b",
        "a level at which every record is run (assessment.stripes_g): the "
        "fragility is fitted to the failures counted at the stripes",
    ),
    (
        "fragility",
        r"\bfragility\b",
        "the probability of failure against the level of shaking: a "
        "lognormal curve of median and dispersion beta",
    ),
    (
        "beta",
        r"\bbeta\b",
        "the dispersion of a lognormal fragility: the standard deviation of the "
        "logarithm of the failure level",
    ),
    ("lambda", r"\blambda\b", "slenderness of a block, h/b (height over width)"),
    (
        "alpha, tan alpha",
        r"\balpha(?:_[a-z])?\b",
        "the angle of the block's diagonal to the vertical, "
        "tan alpha = b/h: it starts to rock when the acceleration of its base exceeds g tan alpha",
    ),
    ("mu", r"\bmu\b", "friction coefficient: of the object on its base, or of a friction-pendulum isolator"),
    ("Tb, xi", r"\b(?:Tb|xi(?:_b)?)\b", "period [s] and damping ratio of a linear isolator"),
    (
        "R",
        r"\bR \[m\]|\bR\b(?= [0-9])",
        "radius of a friction-pendulum isolator's surface [m] (of a block: its half-diagonal)",
    ),
    (
        "gamma_x",
        r"\bgamma_x\b",
        "the factor on the isolator's displacement at the MCE before it is compared with its capacity",
    ),
    (
        "not eligible (x)",
        r"not eligible|\bx not\b",
        "an isolator whose displacement at the MCE, times "
        "gamma_x, exceeds the capacity: it cannot be recommended, whatever its probability of failure",
    ),
    ("recommended (*)", r"recommended", "the eligible base of lowest estimated probability of failure"),
    ("k/n", r"\b\d+/\d+\b", "k of the n records fail"),
    (
        "adj. p",
        r"adj\. p",
        "the p-value of the test that a base fails less often than the fixed base, "
        "corrected for every isolator searched",
    ),
)


def glossary(text: str) -> list[dict[str, str]]:
    """The entries of :data:`GLOSSARY` that ``text`` (the page's words) uses, in its order."""
    return [{"term": t, "meaning": m} for t, pattern, m in GLOSSARY if re.search(pattern, text)]


#: the assessment figures of an object (one that slides gets its sliding figure first)
KINDS = ("fragility", "modes", "displacement", "design")


def _assessment_page(
    store: Store, path: Path, figdir: Path | None, report: str | os.PathLike | None = None
) -> Path:
    summary = assessment_summary(store)
    page = _Page(path, digits=3, report=report)
    if not summary["cases"]:
        return page.write("assessment.html.j2", "Assessment", assessed=False)
    # the verdicts and their short tables first, as `isorock assess` prints them
    conclusions = []
    for c in summary["conclusions"]:
        verdicts = []
        for v in c["verdicts"]:
            d = next(
                x for x in summary["design"] if x["object"] == c["object"] and x["design_g"] == v["design_g"]
            )
            text = " ".join(t for t in (v["sentence"], v["mce"], v["grid"]) if t)
            verdicts.append({"text": text, "table": page.table(short_table(d))})
        conclusions.append({"mode": c.get("mode") or "", "headline": c["headline"], "verdicts": verdicts})
    legend = LEGEND if any(c["verdicts"] for c in summary["conclusions"]) else ""
    details = [p for c in summary["conclusions"] for p in c["details"]]
    table = page.table(summary_table(summary))
    objects = []
    for o in summary["objects"]:
        kinds = ("sliding", *KINDS) if o["slides"] else KINDS
        figs = [page.figure(_fig(figdir, f"assessment_{kind}", o["name"])) for kind in kinds]
        candidates = [
            {
                "text": f"{o['name']}: the candidates at {d['design_g']:g} {d.get('unit', 'g')} "
                f"{d.get('measure', 'PGA')}, ranked by {d['ranked_by']}.",
                "table": page.table(candidates_table(d)),
            }
            for d in summary["design"]
            if d["object"] == o["name"]
        ]
        objects.append({"figures": [f for f in figs if f is not None], "candidates": candidates})
    words = [legend, summary["assumptions"], _site_words(summary), *details, str(table.html if table else "")]
    for c in conclusions:
        words += [c["mode"], c["headline"]] + [v["text"] + str(v["table"].html if v["table"] else "")
                                               for v in c["verdicts"]]  # fmt: skip
    for o in objects:
        words += [c["text"] + str(c["table"].html if c["table"] else "") for c in o["candidates"]]
    return page.write(
        "assessment.html.j2", "Assessment", assessed=True, conclusions=conclusions, legend=legend,
        assumptions=summary["assumptions"], site=_site_words(summary), details=details, summary=table,
        objects=objects, glossary=glossary("\n".join(words)),
    )  # fmt: skip


def _site_words(summary: dict) -> str:
    """The stripes' measure and the hazard curve in words: what every level of the page is."""
    m = summary.get("measure") or {}
    if not m:
        return ""
    text = f"Intensity measure: every level is {m['label']} [{m['unit']}] ({m['basis']})."
    h = summary.get("hazard")
    if h:
        vs = (
            f", Vs30 {h['vs30_m_s']:g} m/s"
            if h.get("vs30_m_s")
            else "; the file does not state the site condition (Vs30) it was computed for"
        )
        text += (
            f" The site's hazard: {h['source']}; measure {h['imt']}, component definition "
            f"{h['component_definition']}{vs}."
        )
        if h.get("notes"):
            text += " " + "; ".join(h["notes"]) + "."
    return text


def figures(h5: str | os.PathLike, outdir: str | os.PathLike, *, workers: int = 1) -> list[Path]:
    """Rule ``figures``: the paper's figures, one set per record and per assessed object
    (:func:`isorock.figures.make_all`), drawn by ``workers`` processes, each PNG reduced to 256
    colours."""
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        paths = fig.make_all(h5, outdir, workers=workers, finish=_shrink_png)
    say(f"{len(paths)} figures in {outdir}")
    return [Path(p) for p in paths]


def _shrink_png(path: Path) -> None:
    """Rewrite a PNG figure with a palette of 256 colours (on white): a quarter of the bytes of
    matplotlib's RGBA image, alike to the eye, so that the report that embeds every figure stays
    small (the default report: under 10 MB)."""
    if path.suffix.lower() != ".png":
        return
    from PIL import Image

    with Image.open(path) as im:
        rgba = im.convert("RGBA")
    flat = Image.alpha_composite(Image.new("RGBA", rgba.size, "white"), rgba).convert("RGB")
    small = flat.quantize(colors=256, method=Image.Quantize.FASTOCTREE, dither=Image.Dither.NONE)
    with atomic_path(path) as tmp:
        small.save(tmp, format="PNG", optimize=True)
