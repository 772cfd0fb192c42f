"""The landing page of the report (``results/report/landing.rst``, the Snakefile's ``report:``): the
results first, in plain language, then the method.

With an assessment: a conclusion per object, the summary table and the fragility, displacement and
design figures. With the minimum-overturning study: the blocks that overturn below the PGA of the
record itself and the cases where isolation makes overturning easier. Then what was computed and how,
and where the numbers are (``results/isorock.h5``).
"""

from __future__ import annotations

import math
import os
import re
from pathlib import Path

import pandas as pd

from ..store import Store, atomic_path
from .assess_report import assessment_summary, summary_table

__all__ = ["write_landing", "landing_text"]

_METHOD = """\
Records were processed (detrend, taper, acausal band-pass, polynomial baseline, QA checks) in the
component the paper used for the Table 1 rows (strike-normal or strike-parallel, rotated from two
recorded components when both are present); their velocity pulse and pulse period Tp were extracted
(db4 wavelet; Mavroeidis-Papageorgiou fit; Bray & Rodriguez-Marek). Every analysis integrates the
model's exact equations (full contact, rocking, impacts with base-block interaction) in a compiled
engine validated against closed forms and an independent scipy integrator.
"""


def _clean(text: str) -> str:
    """Text safe for RST and the report's Jinja rendering."""
    return text.replace("{", "(").replace("}", ")").replace("*", "x").replace("|", "/")


def _list_table(df: pd.DataFrame, title: str) -> list[str]:
    lines = [f".. list-table:: {title}", "   :header-rows: 1", ""]

    def cell(v: object) -> str:
        if isinstance(v, float):
            return "-" if not math.isfinite(v) else f"{v:.3g}"
        return _clean(str(v)) if str(v) else "-"

    lines.append("   * - " + "\n     - ".join(_clean(str(c)) for c in df.columns))
    for row in df.itertuples(index=False):
        lines.append("   * - " + "\n     - ".join(cell(v) for v in row))
    return lines + [""]


def _image(path: Path | None) -> list[str]:
    if path is None or not path.is_file():
        return []
    return [f".. embeddedimage:: {path.resolve()}", "   :width: 100%", ""]


def _section(title: str, char: str = "-") -> list[str]:
    return [title, char * len(title), ""]


def landing_text(store: Store, figdir: Path | None, overturn: pd.DataFrame | None) -> str:
    """The landing RST of a store (see the module docstring)."""
    lines = ["isorock: rocking of free-standing objects on isolated bases", "=" * 59, ""]
    s = assessment_summary(store)
    if s["cases"]:
        lines += _section("Assessment")
        for c in s["conclusions"]:
            lines += [_clean(c["text"]), ""]
        lines += _list_table(summary_table(s), "Summary per object and isolation case")
        for o in s["objects"]:
            safe = re.sub(r"[^0-9A-Za-z_.+-]", "_", o["name"])
            for kind in ("fragility", "displacement", "design"):
                lines += _image(figdir / f"assessment_{kind}_{safe}.png" if figdir else None)
        lines += [
            "The probabilities come from lognormal fragility functions fitted by maximum likelihood to the "
            "stripes (every record scaled to every stripe PGA; Baker 2015); the displacement is the peak "
            "isolator displacement over the records (84th percentile). A result is outside the model when "
            "the friction it needs exceeds the object's or the block would leave the floor. Tables: "
            "/assessment/* of results/isorock.h5.",
            "",
        ]
    if overturn is not None and not overturn.empty:
        lines += _section("Minimum overturning PGA of the records")
        below = overturn[overturn["overturns below the record's PGA"] != ""]
        worse = overturn[overturn["isolation worse than none"] != ""]
        n = len(overturn)
        lines += [
            f"{n} blocks x records analysed. {len(below)} overturn under a record as recorded (their minimum "
            f"overturning PGA is below the record's PGA); in {len(worse)} isolation makes overturning easier "
            "than on the ground. The full table is under 'Minimum overturning PGA'; every record's figures "
            "are on its page under 'Records'.",
            "",
        ]
        if len(below):
            lines += _list_table(
                below[
                    ["record", "record PGA [g]", "lambda [-]", "R [m]", "overturns below the record's PGA"]
                ].head(15),
                "Blocks that overturn below the record's own PGA (first 15)",
            )
        if len(worse):
            lines += _list_table(
                worse[["record", "lambda [-]", "R [m]", "isolation worse than none"]].head(15),
                "Isolation makes overturning easier (first 15)",
            )
    lines += _section("Method")
    lines += [_clean(_METHOD), ""]
    cfg = _clean(str(store.root_attrs.get("config_name", "")))
    src = _clean(str(store.root_attrs.get("record_source", "")))
    lines += [
        f"Configuration: {cfg}; records: {src}. "
        "All results are in results/isorock.h5 (HDF5, layout in isorock.store; the tables read with "
        "pandas.read_hdf).",
        "",
    ]
    return "\n".join(lines)


def write_landing(
    store: Store, path: str | os.PathLike, figdir: Path | None, overturn: pd.DataFrame | None
) -> Path:
    """Write :func:`landing_text` atomically; returns the path."""
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_text(landing_text(store, figdir, overturn), encoding="utf-8")
    return path
