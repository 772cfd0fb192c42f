"""Sphinx extension of isorock's documentation: pages generated from the code at every build.

* ``reference/_generated/store.md``: the store's layout, from :mod:`isorock.store.layout` (the layout
  version and its history, the attributes of ``/records/<id>`` with their units, the tables' columns and
  their units);
* ``_generated/timings.md``: the measured timings, from :mod:`isorock.timings` (the one place a timing
  printed anywhere comes from).

The files are written before Sphinx reads the sources (``builder-inited``) and only when their text
changed, so an incremental build does not rebuild every page.
"""

from __future__ import annotations

from pathlib import Path

from sphinx.application import Sphinx


def _write(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_text() != text:
        path.write_text(text)


def _cell(text: object) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def store_page() -> str:
    """The store's layout as Markdown, from :mod:`isorock.store.layout`."""
    from isorock.store import layout as L

    out = [
        "<!-- generated from isorock.store.layout by docs/_ext/isorock_docs.py: do not edit -->",
        "",
        f"## Layout version {L.LAYOUT_VERSION}",
        "",
        "| version | what it changed |",
        "|---|---|",
    ]
    out += [f"| {v} | {_cell(t)} |" for v, t in sorted(L.LAYOUT_HISTORY.items())]
    out += [
        "",
        "## Attributes of `/records/<id>`",
        "",
        "`RECORD_ATTRS`: written by the job named, in this order; those marked *summary* are also the "
        "columns of `/summary/records`, after its column `record`.",
        "",
        "| attribute | unit | stored as | written by | summary | description |",
        "|---|---|---|---|---|---|",
    ]
    for a in L.RECORD_ATTRS:
        out.append(
            f"| `{a.name}` | {a.unit or ''} | {a.kind} | {a.job} | {'yes' if a.summary else ''} | "
            f"{_cell(a.description)} |"
        )
    tables = [
        ("`/overturn/<id>` and `/summary/overturn`", L.OVERTURN_COLUMNS),
        ("`/pulses/overturn_*`", L.PULSE_COLUMNS),
        ("`/summary/maps`", L.MAP_INDEX_COLUMNS),
        ("`/summary/records`", L.RECORD_SUMMARY_COLUMNS),
    ]
    out += ["", "## Table columns", ""]
    for title, cols in tables:
        out += [f"### {title}", "", "| column | unit |", "|---|---|"]
        out += [f"| `{c}` | {L.COLUMN_UNITS.get(c, '')} |" for c in cols]
        out.append("")
    out += ["## Units of the columns", "", "| column | unit |", "|---|---|"]
    out += [f"| `{c}` | {u} |" for c, u in L.COLUMN_UNITS.items()]
    out += ["", "## Units of the map axes", "", "| axis | unit |", "|---|---|"]
    out += [f"| `{c}` | {u} |" for c, u in L.MAP_AXIS_UNITS.items()]
    out += ["", "## Outcome codes", "", "| code | meaning |", "|---|---|"]
    for item in L.OUTCOME_LEGEND.split(","):  # "0 = no uplift, 1 = rocking, 2 = overturn"
        code, meaning = item.split("=")
        out.append(f"| {code.strip()} | {meaning.strip()} |")
    return "\n".join(out) + "\n"


def timings_page() -> str:
    """The measured timings as a Markdown table, from :mod:`isorock.timings`."""
    from isorock.timings import TIMINGS

    out = [
        "<!-- generated from isorock.timings by docs/_ext/isorock_docs.py: do not edit -->",
        "",
        "| what | time | measured by | on |",
        "|---|---|---|---|",
    ]
    for t in TIMINGS.values():
        out.append(f"| {_cell(t.what)} | {t.text} | `{t.command}` | {_cell(t.measured_on)} |")
    return "\n".join(out) + "\n"


def _generate(app: Sphinx) -> None:
    src = Path(app.srcdir)
    _write(src / "reference" / "_generated" / "store.md", store_page())
    _write(src / "_generated" / "timings.md", timings_page())


def setup(app: Sphinx) -> dict:
    app.connect("builder-inited", _generate)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
