"""``isorock report``: run the Snakemake workflow, then write its self-contained HTML report.

It wraps ``snakemake --cores N`` and ``snakemake --report report.html`` with the workflow that comes
with isorock (``Snakefile``, ``workflow/``, ``config/``: :mod:`isorock.resources`) and its profile
``workflow/profiles/default``, run in the current directory (``results/`` there). The configuration
is validated first, as the workflow will see it, so that a bad key is reported in one line.
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import IsorockError

__all__ = ["ReportCommand", "find_snakefile", "register", "cmd_report"]


@dataclass
class ReportCommand:
    """The two Snakemake invocations of ``isorock report``.

    Parameters
    ----------
    snakefile : Path
        The workflow's ``Snakefile``.
    directory : Path
        Working directory (``results/``, ``logs/`` and ``.snakemake/`` go there).
    configfile : Path
        Workflow configuration.
    report : Path
        HTML report written.
    cores : int
        Cores Snakemake may use.
    profile : Path or None
        Workflow profile directory.
    extra : list of str
        Further Snakemake options.
    env : dict
        Environment variables set for Snakemake (``ISOROCK_RECORDS``).
    """

    snakefile: Path
    directory: Path
    configfile: Path
    report: Path
    cores: int = 2
    profile: Path | None = None
    extra: list[str] = field(default_factory=list)
    env: dict[str, str] = field(default_factory=dict)

    def base(self) -> list[str]:
        cmd = [sys.executable, "-m", "snakemake", "--snakefile", str(self.snakefile)]
        cmd += ["--directory", str(self.directory), "--configfile", str(self.configfile)]
        if self.profile is not None:
            cmd += ["--workflow-profile", str(self.profile)]
        return cmd

    def run_cmd(self, dry_run: bool = False) -> list[str]:
        """``snakemake --cores N`` (``-n`` for a dry run)."""
        return self.base() + ["--cores", str(self.cores)] + (["-n"] if dry_run else []) + self.extra

    def report_cmd(self) -> list[str]:
        """``snakemake --report FILE``."""
        return self.base() + ["--cores", str(self.cores), "--report", str(self.report)]


def find_snakefile(given: str | None = None) -> Path:
    """The workflow's Snakefile: ``given``, else the one that comes with isorock.

    Raises
    ------
    IsorockError
        ``given`` does not exist, or the installation lacks its workflow.
    """
    from .. import resources

    if given:
        p = Path(given).expanduser()
        if not p.is_file():
            raise IsorockError(f"{p}: no such Snakefile")
        return p.resolve()
    return resources.snakefile().resolve()


def build(a: argparse.Namespace) -> ReportCommand:
    """The invocations for the parsed options (checks the configuration and the records directory)."""
    from ..pipeline import workflow_config

    if a.cores < 1:
        raise IsorockError(f"--cores {a.cores}: valid an integer >= 1")
    snakefile = find_snakefile(a.snakefile)
    wf = snakefile.parent
    configfile = Path(a.configfile).expanduser() if a.configfile else wf / "config" / "config.yaml"
    if not configfile.is_file():
        raise IsorockError(f"{configfile}: no such configuration file")
    directory = Path(a.directory).expanduser() if a.directory else Path.cwd()
    config = workflow_config(configfile)  # what the workflow will see; one-line error when bad
    if importlib.util.find_spec("snakemake") is None:
        raise IsorockError("isorock report needs Snakemake: pip install 'isorock[workflow]'")
    env = {}
    if a.records is not None:
        rec = Path(a.records).expanduser()
        if not rec.is_dir():
            raise IsorockError(f"--records {rec}: no such directory")
        env["ISOROCK_RECORDS"] = str(rec.resolve())
    _check_plan(config, directory, env)
    profile = wf / "workflow" / "profiles" / "default"
    extra = list(a.snakemake_args or [])
    if extra and extra[0] == "--":
        extra = extra[1:]
    return ReportCommand(
        snakefile=snakefile,
        directory=directory.resolve(),
        configfile=configfile.resolve(),
        report=Path(a.report_path).expanduser().resolve(),
        cores=a.cores,
        profile=profile if profile.is_dir() else None,
        extra=extra,
        env=env,
    )


def _check_plan(config: dict, directory: Path, env: dict[str, str]) -> None:
    """Find the records as the workflow will, so that a bad records directory is one line here."""
    from ..pipeline import plan

    saved = {k: os.environ.get(k) for k in env}
    os.environ.update(env)
    try:
        plan(config, basedir=directory)
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def _run(cmd: list[str], env: dict[str, str], what: str) -> None:
    try:
        rc = subprocess.call(cmd, env={**os.environ, **env})
    except OSError as exc:
        raise IsorockError(f"cannot start snakemake: {exc.strerror or exc}") from None
    if rc != 0:
        raise IsorockError(
            f"snakemake {what} failed with exit code {rc}: see its messages above and the job logs in logs/"
            + (" (a killed run leaves a lock: snakemake --unlock)" if rc == 1 else "")
        )


def cmd_report(a: argparse.Namespace) -> int:
    rc = build(a)
    if a.print_commands:
        print(" ".join(rc.run_cmd(a.dry_run)))
        if not a.dry_run:
            print(" ".join(rc.report_cmd()))
        return 0
    if not a.no_run:
        _run(rc.run_cmd(a.dry_run), rc.env, "run")
    if a.dry_run:
        return 0
    _run(rc.report_cmd(), rc.env, "--report")
    print(f"isorock: report written to {rc.report} (results in {rc.directory / 'results' / 'isorock.h5'})")
    return 0


def register(subparsers: argparse._SubParsersAction) -> None:
    p = subparsers.add_parser(
        "report",
        help="run the workflow (snakemake) and write its HTML report",
        description="Run the isorock Snakemake workflow (records -> pulses -> minimum overturning PGA "
        "-> regime maps -> results/isorock.h5 -> figures) and write the self-contained report. "
        "Options after -- go to snakemake.",
    )
    p.add_argument("--cores", type=int, default=2, help="cores for snakemake (default 2)")
    p.add_argument("--configfile", default=None, help="workflow configuration (default config/config.yaml)")
    p.add_argument("--records", default=None, metavar="DIR", help="records directory (sets ISOROCK_RECORDS)")
    p.add_argument("--directory", "-d", default=None, help="working directory for results/ (default: here)")
    p.add_argument("--snakefile", default=None, help="the workflow (default: the one isorock ships)")
    p.add_argument("--report", dest="report_path", default="report.html", help="report file (report.html)")
    p.add_argument("--no-run", action="store_true", help="only write the report of an earlier run")
    p.add_argument("--dry-run", "-n", action="store_true", help="list the jobs, run nothing")
    p.add_argument("--print-commands", action="store_true", help="print the snakemake commands, run nothing")
    p.add_argument("snakemake_args", nargs=argparse.REMAINDER, help="further snakemake options (after --)")
    p.set_defaults(func=cmd_report)
