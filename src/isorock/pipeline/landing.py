"""The landing page of the report (``results/report/landing.rst``, the Snakefile's ``report:``): the
results first, in plain language, then the method, on one screen.

With an assessment: the plain-language conclusion of the first objects and where the rest is (the
'Assessment' category: summary table, fragility, displacement and design charts). With the
minimum-overturning study: how many blocks overturn below the PGA of the record itself and how often
isolation makes overturning easier. Then what was computed and where the numbers are
(``results/isorock.h5``). The tables and figures are the categories' pages, not this one.
"""

from __future__ import annotations

import os
from pathlib import Path

import pandas as pd

from ..assessment.summary import assessment_summary
from ..store import Store, atomic_path

__all__ = ["write_landing", "landing_text"]

_METHOD = """\
Records processed (band-pass, baseline, QA) in the component the paper used; Tp by the wavelet
method; every analysis integrates the model's exact equations (rocking, impacts with base-block
interaction) in an engine validated against closed forms and an independent integrator.
"""

#: Snakemake's report centres its landing page vertically, so a page taller than the window loses its
#: top: the page stays short (the gist for the first objects, then pointers to the categories)
_MAX_OBJECTS = 4


def _clean(text: str) -> str:
    """Text safe for RST and the report's Jinja rendering."""
    return text.replace("{", "(").replace("}", ")").replace("*", "x").replace("|", "/")


def _section(title: str, char: str = "-") -> list[str]:
    return [title, char * len(title), ""]


def landing_text(store: Store, figdir: Path | None, overturn: pd.DataFrame | None) -> str:
    """The landing RST of a store (see the module docstring)."""
    lines = ["isorock results", "=" * 15, ""]
    s = assessment_summary(store)
    if s["cases"]:
        lines += _section("Assessment")
        for c in s["conclusions"][:_MAX_OBJECTS]:
            lines += [f"- {_clean(c['headline'])}", ""]
        more = len(s["conclusions"]) - _MAX_OBJECTS
        lines += [
            (f"And {more} more object(s). " if more > 0 else "")
            + "The conclusion for each object in plain words, the summary per object and isolation case, "
            "the fragility, displacement and design charts and the runs outside the model: under "
            "'Assessment'.",
            "",
        ]
    if overturn is not None and not overturn.empty:
        lines += _section("Minimum overturning PGA")
        below = overturn[overturn["overturns below the record's PGA"] != ""]
        worse = overturn[overturn["isolation worse than none"] != ""]
        lines += [
            f"{len(overturn)} blocks x records analysed: {len(below)} overturn under a record as recorded "
            f"(minimum overturning PGA below the record's PGA); in {len(worse)} an isolated base overturns "
            "at a lower PGA than the ground. Tables under 'Minimum overturning PGA', figures per record "
            "under 'Records'.",
            "",
        ]
    lines += _section("Method")
    cfg = _clean(str(store.root_attrs.get("config_name", "")))
    src = _clean(str(store.root_attrs.get("record_source", "")))
    lines += [
        _clean(_METHOD),
        "",
        f"Configuration {cfg}; records: {src}. Every number is in results/isorock.h5 (HDF5; its tables read "
        "with pandas.read_hdf).",
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
