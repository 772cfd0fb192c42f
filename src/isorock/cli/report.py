"""``isorock report``: run the Snakemake workflow, then write its self-contained HTML report.

A thin caller of the workflow runner :mod:`isorock.control.run` (:func:`~isorock.pipeline.run_workflow`):
``snakemake --cores N`` and ``snakemake --report FILE`` with the workflow that comes with isorock
(``Snakefile``, ``workflow/``, ``config/``: :mod:`isorock.resources`) and a workflow profile
(``--profile``: ``default``, this machine; ``slurm``, a SLURM cluster through
snakemake-executor-plugin-slurm; or a folder of one's own), run in the current directory (``results/``
there). The configuration is checked first, as the workflow will see it (``config/config.yaml``, the
``--configfile`` merged over it, ``--records`` over both), and the records are found, so that a bad
key, a missing records directory or a run without records is reported in one line before any job.

The report is named after the configuration (``report.html`` for the default one, ``report-ci.html``
for ``--configfile config/ci.yaml``), so that a run of another configuration does not overwrite it;
``results/`` holds the results of the configuration run last, and a run of another configuration keeps
them apart in ``results-<name>/`` first (:func:`isorock.control.run.keep_apart`); a store of another
version (or no isorock store at all) is removed, saying why, and merged again.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from isorock.control.run import RunSettings

__all__ = ["build", "register", "cmd_report", "add_run_options"]


def build(a: argparse.Namespace) -> RunSettings:
    """The settings of the run the parsed options ask for, checked
    (:func:`isorock.control.run.prepare_run`: the configuration, the records, the profile, the cost
    estimate, refused above its limit without ``--force``)."""
    from isorock.control.run import prepare_run

    return prepare_run(
        a.configfile,
        records=a.records,
        cores=a.cores,
        profile=a.profile,
        directory=a.directory,
        report=a.report_path,
        snakefile=a.snakefile,
        snakemake_args=a.snakemake_args,
        force=bool(getattr(a, "force", False)),
    )


def cmd_report(a: argparse.Namespace) -> int:
    """``isorock report``: the workflow run, then its report."""
    settings = build(a)
    if a.print_commands:
        if a.no_run:
            print(" ".join(settings.report_cmd()))
        else:  # the jobs, then the report (--report-after-run), in one command
            print(" ".join(settings.run_cmd(a.dry_run, report=True)))
        return 0
    res = settings.execute(dry_run=a.dry_run, run_jobs=not a.no_run)
    if res.dry_run:
        return 0
    print(
        f"isorock: report written to {res.report} (configuration {settings.configfile.name}; results in "
        f"{res.store})"
    )
    return 0


def add_run_options(
    p: argparse.ArgumentParser, *, snakemake_args: bool = True, config: str = "--configfile"
) -> None:
    """Options of the commands that run the workflow (``report``, ``assess``); ``snakemake_args``:
    the further Snakemake options after ``--`` (not with a positional argument before them);
    ``config``: how the command names its configuration file (``--configfile``, ``CONFIG``), for the
    help of ``--report``."""
    p.add_argument(
        "--cores",
        type=int,
        default=None,
        metavar="N",
        help="cores for snakemake on this machine (default: the profile's, 2); with a cluster profile, "
        "the most CPUs one cluster job asks for (default: the profile's, 8)",
    )
    p.add_argument(
        "--profile",
        default="default",
        metavar="NAME",
        help="workflow profile: default (this machine), slurm (a SLURM cluster, needs isorock[cluster]; "
        "run it on the login node) or the folder of a profile of your own (default: default)",
    )
    p.add_argument(
        "--records",
        default=None,
        metavar="DIR",
        help="records directory (replaces records.dir of the configuration)",
    )
    p.add_argument(
        "--directory",
        "-d",
        default=None,
        metavar="DIR",
        help="working directory for results/ and the report (default: here)",
    )
    p.add_argument(
        "--snakefile", default=None, metavar="FILE", help="the workflow (default: the one isorock ships)"
    )
    p.add_argument(
        "--report",
        dest="report_path",
        default=None,
        metavar="FILE",
        help=f"report file (default: report.html, or report-<name>.html for {config} <name>.yaml)",
    )
    p.add_argument("--no-run", action="store_true", help="only write the report of an earlier run")
    p.add_argument(
        "--dry-run", "-n", action="store_true", help="list the jobs and the run's cost estimate, run nothing"
    )
    p.add_argument(
        "--force",
        action="store_true",
        help="run a configuration whose cost estimate (printed before every run: analyses per study, "
        "expected time) is above the limit of 50 million analyses",
    )
    p.add_argument("--print-commands", action="store_true", help="print the snakemake commands, run nothing")
    if snakemake_args:
        p.add_argument(
            "snakemake_args", nargs=argparse.REMAINDER, help="further snakemake options (after --)"
        )
    else:
        p.set_defaults(snakemake_args=[])


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``report``."""
    p = subparsers.add_parser(
        "report",
        help="run the workflow (snakemake) and write its HTML report",
        description="Run the isorock Snakemake workflow (records -> pulses -> minimum overturning PGA "
        "-> regime maps -> results/isorock.h5 -> figures) and write the self-contained report. "
        "Options after -- go to snakemake.",
    )
    p.add_argument(
        "--configfile",
        default=None,
        metavar="YAML",
        help="workflow configuration, merged over config/config.yaml (default: that file alone)",
    )
    add_run_options(p)
    p.set_defaults(func=cmd_report)
