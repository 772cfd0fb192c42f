"""``isorock assess CONFIG``: assess real objects (the configuration's ``assessment`` section).

It runs the workflow for that configuration in the current directory (``results/`` there, as
``snakemake`` does; :mod:`isorock.control.run`, as ``isorock report``), writes the report
(``report-<name>.html``) and prints per object and design level the verdict (isolate, keep the fixed
base, or no decision, with the numbers that carry it), where the design search stopped, and a short
table of the bases compared (:func:`isorock.assessment.words.text_summary`); with ``--json`` one JSON
object (:func:`isorock.assessment.summary.assessment_summary`).

``--export-fragility FILE.csv`` writes, after the run, every object's and base's fitted fragility (each
failure mode: overturn, failure) as a damage model of pelicun
(:mod:`isorock.assessment.pelicun_export`); a fit that is not estimable is left out with one line
saying why, and ``--json`` gets the key ``exported_fragility`` (``path``, ``n_rows``, ``left_out``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from isorock.cli.output import print_json
from isorock.cli.report import add_run_options, build
from isorock.errors import IsorockError

__all__ = ["register", "cmd_assess"]


def cmd_assess(a: argparse.Namespace) -> int:
    """``isorock assess``: the workflow of an assessment configuration, its report and summary."""
    from isorock.assessment.summary import assessment_summary
    from isorock.assessment.words import text_summary

    a.configfile = a.config
    export = None
    if a.export_fragility:  # a wrong path is refused before the run, not after it
        from isorock.assessment.pelicun_export import check_export_path

        export = check_export_path(Path(a.export_fragility).expanduser()).absolute()
    settings = build(a)
    if not settings.config.get("assessment"):
        raise IsorockError(
            f"{a.config}: no 'assessment' section: describe the objects, isolation cases and stripes "
            "(see config/assessment.yaml)"
        )
    if a.print_commands:
        print(" ".join(settings.report_cmd() if a.no_run else settings.run_cmd(a.dry_run, report=True)))
        return 0
    out = sys.stderr if a.json else None  # keep stdout for the JSON object
    res = settings.execute(dry_run=a.dry_run, run_jobs=not a.no_run, stdout=out)
    if res.dry_run:
        return 0
    store = res.store
    lines: list[str] = []
    exported = None
    if export is not None:  # read from the store alone: written whatever the summary says
        exported, lines = _export(store, export)
    summary = assessment_summary(store)
    summary["store"] = str(store)
    summary["report"] = str(res.report)
    if exported is not None:
        summary["exported_fragility"] = exported
    if a.json:
        for line in lines:  # stdout holds the JSON object
            print(line, file=sys.stderr)
        print_json(summary)
        return 0
    print(f"isorock assess: {settings.configfile.name}, {len(summary['records'])} record(s)")
    for line in text_summary(summary, str(res.report)):
        print(line)
    print()
    print(f"results: {store}; report: {res.report}")
    for line in lines:
        print(line)
    return 0


def _export(store: Path, path: Path) -> tuple[dict[str, Any], list[str]]:
    """Write the store's fragilities for pelicun to ``path``: the ``exported_fragility`` object of
    ``--json`` and the lines for the user (one per fit left out, one for the file)."""
    from isorock.assessment.pelicun_export import write_pelicun_csv

    rows, left = write_pelicun_csv(path, store)
    lines = [f"isorock assess: --export-fragility: {x.line()}" for x in left]
    lines.append(f"fragility for pelicun: {path} ({len(rows)} row(s), {len(left)} left out)")
    return {"path": str(path), "n_rows": len(rows), "left_out": [x.to_dict() for x in left]}, lines


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``assess``."""
    p = subparsers.add_parser(
        "assess",
        help="assess objects: fragility, isolator displacement, validity, isolation design",
        description="Run the workflow of an assessment configuration (records, isolation cases and "
        "an 'assessment' section: objects, cases, capacity, stripes, design levels, optional design grid; "
        "see config/assessment.yaml) in the current directory (or --directory DIR), write its report and "
        "print a summary.",
    )
    p.add_argument(
        "config",
        metavar="CONFIG",
        help="assessment configuration (YAML), merged over the workflow's config/config.yaml",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object (records, cases, design)")
    p.add_argument(
        "--export-fragility",
        default=None,
        metavar="FILE.csv",
        help="after the run, write every object's and base's fitted fragility (overturn, failure) as a "
        "pelicun damage model (CSV: ID <object>.<case>.<failure mode>, lognormal median and beta); fits "
        "that are not estimable are left out, one line each",
    )
    add_run_options(p, snakemake_args=False, config="CONFIG")
    p.set_defaults(func=cmd_assess)
