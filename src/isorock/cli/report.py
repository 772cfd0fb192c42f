"""``isorock report``: run the Snakemake workflow, then write its self-contained HTML report.

It wraps ``snakemake --cores N`` and ``snakemake --report FILE`` with the workflow that comes with
isorock (``Snakefile``, ``workflow/``, ``config/``: :mod:`isorock.resources`) and a workflow profile
(``--profile``: ``default``, this machine; ``slurm``, a SLURM cluster through
snakemake-executor-plugin-slurm; or a folder of one's own), run in the current directory (``results/``
there). The configuration
is checked first, as the workflow will see it (``config/config.yaml``, the ``--configfile`` merged
over it, ``--records`` over both), and the records are found, so that a bad key, a missing records
directory or a run without records is reported in one line before any job.

The report is named after the configuration (``report.html`` for the default one, ``report-ci.html``
for ``--configfile config/ci.yaml``), so that a run of another configuration does not overwrite it;
``results/`` holds the results of the last run, and a run of another configuration says so before it
replaces them.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import shutil
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import IsorockError

__all__ = ["ReportCommand", "find_snakefile", "find_profile", "build", "register", "cmd_report"]


@dataclass
class ReportCommand:
    """The two Snakemake invocations of ``isorock report`` (``isorock assess`` uses the same).

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
    config : dict
        The configuration the workflow will see (validated, defaults filled in).
    cores : int or None
        Cores Snakemake may use on this machine; with a cluster profile, the most CPUs one cluster job
        asks for. None: the profile's value.
    profile : Path or None
        Workflow profile directory (``workflow/profiles/default``: local; ``slurm``: a cluster).
    overrides : dict
        Configuration values given on the command line (``--config KEY=VALUE``).
    extra : list of str
        Further Snakemake options.
    """

    snakefile: Path
    directory: Path
    configfile: Path
    report: Path
    config: dict = field(default_factory=dict)
    cores: int | None = 2
    profile: Path | None = None
    overrides: dict = field(default_factory=dict)
    extra: list[str] = field(default_factory=list)

    def base(self, profile: bool = True) -> list[str]:
        """The options both commands share; ``profile``: with the workflow profile."""
        cmd = [sys.executable, "-m", "snakemake", "--snakefile", str(self.snakefile)]
        cmd += ["--directory", str(self.directory), "--configfile", str(self.configfile)]
        if self.overrides:
            cmd += ["--config", *(f"{k}={json.dumps(v)}" for k, v in self.overrides.items())]
        if profile and self.profile is not None:
            cmd += ["--workflow-profile", str(self.profile)]
        return cmd

    def run_cmd(self, dry_run: bool = False) -> list[str]:
        """``snakemake --cores N`` (``-n`` for a dry run)."""
        cores = ["--cores", str(self.cores)] if self.cores is not None else []
        return self.base() + cores + (["-n"] if dry_run else []) + self.extra

    def report_cmd(self) -> list[str]:
        """``snakemake --report FILE`` (here, whatever profile ran the jobs: it runs none)."""
        return self.base(profile=False) + ["--cores", "1", "--report", str(self.report)]


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


def find_profile(name: str, workflow_dir: Path) -> Path:
    """The workflow profile folder for ``--profile NAME``: one that comes with isorock
    (``workflow/profiles/<NAME>``: ``default``, ``slurm``), else a folder holding a ``config.yaml``.

    Raises
    ------
    IsorockError
        No such profile; or a cluster profile whose executor plugin is not installed, or on a machine
        without the cluster's commands.
    """
    import yaml

    shipped = workflow_dir / "workflow" / "profiles"
    folder = shipped / name
    if not (folder / "config.yaml").is_file():
        folder = Path(name).expanduser()
        if not (folder / "config.yaml").is_file():
            names = sorted(d.name for d in shipped.iterdir() if (d / "config.yaml").is_file())
            raise IsorockError(
                f"--profile {name}: no such profile; valid: {', '.join(names)}, "
                "or a folder with a config.yaml"
            )
    folder = folder.resolve()
    try:
        settings = yaml.safe_load((folder / "config.yaml").read_text()) or {}
    except yaml.YAMLError as exc:
        raise IsorockError(f"{folder / 'config.yaml'}: not valid YAML: {exc}") from None
    executor = str(settings.get("executor", "local")) if isinstance(settings, dict) else "local"
    if executor == "slurm":
        if importlib.util.find_spec("snakemake_executor_plugin_slurm") is None:
            raise IsorockError(
                f"--profile {name} submits jobs to SLURM and needs its Snakemake plugin: "
                "pip install 'isorock[cluster]'"
            )
        if shutil.which("sbatch") is None:
            raise IsorockError(
                f"--profile {name} submits jobs to SLURM, but there is no sbatch here: run it on a "
                "login node of the cluster"
            )
    return folder


def default_report_name(configfile: str | None) -> str:
    """``report.html`` for the default configuration, ``report-<name>.html`` for ``<name>.yaml``."""
    if not configfile:
        return "report.html"
    stem = Path(configfile).stem
    return "report.html" if stem == "config" else f"report-{stem}.html"


def build(a: argparse.Namespace) -> ReportCommand:
    """The invocations for the parsed options (checks the configuration and the records)."""
    from ..pipeline import plan, workflow_config

    if a.cores is not None and a.cores < 1:
        raise IsorockError(f"--cores {a.cores}: valid an integer >= 1")
    snakefile = find_snakefile(a.snakefile)
    wf = snakefile.parent
    configfile = Path(a.configfile).expanduser() if a.configfile else wf / "config" / "config.yaml"
    if not configfile.is_file():
        raise IsorockError(f"{configfile}: no such configuration file")
    directory = (Path(a.directory).expanduser() if a.directory else Path.cwd()).resolve()
    overrides: dict = {}
    if a.records is not None:
        rec = Path(a.records).expanduser()
        if not rec.is_dir():
            raise IsorockError(f"--records {rec}: no such directory")
        overrides["records"] = {"dir": str(rec.resolve())}
    config = workflow_config(configfile, overrides)  # what the workflow will see; one line when bad
    if importlib.util.find_spec("snakemake") is None:
        raise IsorockError("isorock report needs Snakemake: pip install 'isorock[workflow]'")
    p = plan(config, basedir=directory)  # a missing records directory, or no records, in one line
    for w in p.warnings:
        print(f"isorock: warning: {w}", file=sys.stderr)
    profile = find_profile(a.profile, wf)
    extra = list(a.snakemake_args or [])
    if extra and extra[0] == "--":
        extra = extra[1:]
    report = a.report_path or default_report_name(a.configfile)
    return ReportCommand(
        snakefile=snakefile,
        directory=directory,
        configfile=configfile.resolve(),
        report=(directory / report if not Path(report).is_absolute() else Path(report)).resolve(),
        config=config,
        cores=a.cores,
        profile=profile,
        overrides=overrides,
        extra=extra,
    )


def previous_results(rc: ReportCommand) -> str | None:
    """A line saying that ``results/`` holds the results of another configuration, or None."""
    import h5py

    from ..store import config_hash

    store = rc.directory / "results" / "isorock.h5"
    if not store.is_file():
        return None
    try:
        with h5py.File(store, "r") as f:
            old_hash = str(f.attrs.get("config_hash", ""))
            old_name = str(f.attrs.get("config_name", "?"))
    except OSError:
        return None
    new_hash = config_hash(json.loads(json.dumps(rc.config, default=str)))
    if old_hash == new_hash:
        return None
    return (
        f"isorock: {store} holds the results of configuration {old_name!r}; this run of "
        f"{rc.configfile.name!r} replaces them (its report: {rc.report.name})"
    )


def run_snakemake(cmd: list[str], what: str, stdout=None) -> None:
    """Run one Snakemake command; its failure is one line (the messages are above it). ``stdout``: where
    its standard output goes (default: ours)."""
    try:
        rc = subprocess.call(cmd, stdout=stdout)
    except OSError as exc:
        raise IsorockError(f"cannot start snakemake: {exc.strerror or exc}") from None
    if rc != 0:
        raise IsorockError(
            f"snakemake {what} failed with exit code {rc}: see its messages above and the job logs in logs/"
            + (" (a killed run leaves a lock: snakemake --unlock)" if rc == 1 else "")
        )


def cmd_report(a: argparse.Namespace) -> int:
    """``isorock report``: the workflow run, then its report."""
    rc = build(a)
    if a.print_commands:
        print(" ".join(rc.run_cmd(a.dry_run)))
        if not a.dry_run:
            print(" ".join(rc.report_cmd()))
        return 0
    if not a.no_run:
        note = previous_results(rc)
        if note and not a.dry_run:
            print(note, file=sys.stderr)
        run_snakemake(rc.run_cmd(a.dry_run), "run")
    if a.dry_run:
        return 0
    run_snakemake(rc.report_cmd(), "--report")
    print(
        f"isorock: report written to {rc.report} (configuration {rc.configfile.name}; results in "
        f"{rc.directory / 'results' / 'isorock.h5'})"
    )
    return 0


def add_run_options(p: argparse.ArgumentParser, *, snakemake_args: bool = True) -> None:
    """Options of the commands that run the workflow (``report``, ``assess``); ``snakemake_args``:
    the further Snakemake options after ``--`` (not with a positional argument before them)."""
    p.add_argument(
        "--cores",
        type=int,
        default=None,
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
    p.add_argument("--directory", "-d", default=None, help="working directory for results/ (default: here)")
    p.add_argument("--snakefile", default=None, help="the workflow (default: the one isorock ships)")
    p.add_argument(
        "--report",
        dest="report_path",
        default=None,
        help="report file (default: report.html, or report-<name>.html for --configfile <name>.yaml)",
    )
    p.add_argument("--no-run", action="store_true", help="only write the report of an earlier run")
    p.add_argument("--dry-run", "-n", action="store_true", help="list the jobs, run nothing")
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
        help="workflow configuration, merged over config/config.yaml (default: that file alone)",
    )
    add_run_options(p)
    p.set_defaults(func=cmd_report)
