"""``isorock assess CONFIG``: assess real objects (the configuration's ``assessment`` section).

It runs the workflow for that configuration in the current directory (``results/`` there, as
``snakemake`` does; :mod:`isorock.pipeline.run`, as ``isorock report``), writes the report
(``report-<name>.html``) and prints per object and design level the verdict (isolate, keep the fixed
base, or no decision, with the numbers that carry it), where the design search stopped, and a short
table of the bases compared (:func:`isorock.assessment.words.text_summary`); with ``--json`` one JSON
object (:func:`isorock.assessment.summary.assessment_summary`).
"""

from __future__ import annotations

import argparse
import sys

from ..errors import IsorockError
from .output import print_json
from .report import add_run_options, build

__all__ = ["register", "cmd_assess"]


def cmd_assess(a: argparse.Namespace) -> int:
    """``isorock assess``: the workflow of an assessment configuration, its report and summary."""
    from ..assessment.summary import assessment_summary
    from ..assessment.words import text_summary

    a.configfile = a.config
    settings = build(a)
    if not settings.config.get("assessment"):
        raise IsorockError(
            f"{a.config}: no 'assessment' section: describe the objects, isolation cases and stripes "
            "(see config/assessment.yaml)"
        )
    if a.print_commands:
        print(" ".join(settings.run_cmd(a.dry_run)))
        return 0
    out = sys.stderr if a.json else None  # keep stdout for the JSON object
    res = settings.execute(dry_run=a.dry_run, run_jobs=not a.no_run, stdout=out)
    if res.dry_run:
        return 0
    store = res.store
    summary = assessment_summary(store)
    summary["store"] = str(store)
    summary["report"] = str(res.report)
    if a.json:
        print_json(summary)
        return 0
    print(f"isorock assess: {settings.configfile.name}, {len(summary['records'])} record(s)")
    for line in text_summary(summary, str(res.report)):
        print(line)
    print()
    print(f"results: {store}; report: {res.report}")
    return 0


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
    add_run_options(p, snakemake_args=False, config="CONFIG")
    p.set_defaults(func=cmd_assess)
