"""Run the workflow from Python: ``snakemake``, which writes its report once its jobs are done
(``--report-after-run``; what ``isorock report`` and ``isorock assess`` do).

:func:`run_workflow` runs the workflow that comes with isorock (``Snakefile``, ``workflow/``,
``config/``: :mod:`isorock.resources`) with a workflow profile (``profile``: ``default``, this machine;
``slurm``, a SLURM cluster through snakemake-executor-plugin-slurm; or a folder of one's own) in a
working directory (``results/`` there), then writes the self-contained HTML report, and returns where
the store and the report are (:class:`RunResult`). The configuration is checked first, as the workflow
will see it (``config/config.yaml``, the ``configfile`` merged over it, ``records`` over both), and the
records are found, so that a bad key, a missing records directory or a run without records raises
:class:`~isorock.errors.IsorockError` (one line) before any job.

The report is named after the configuration (``report.html`` for the default one, ``report-ci.html``
for ``config/ci.yaml``), so that a run of another configuration does not overwrite it; ``results/``
holds the results of the configuration run last (named in ``results/configuration.txt``), and those of
each other configuration run in the folder are kept beside it, in ``results-<name>/``, with the pages
its report was made from (:func:`keep_apart`): a run of ``cabinet.yaml`` after one of ``statue.yaml``
moves ``results/`` to ``results-statue/`` (``report-statue.html`` shows what its pages there show), and
the next run of ``statue.yaml`` moves it back, its finished jobs kept. A store that is not what this
run would make (another version's, one made from records changed since, or an HDF5 file that is no
isorock store) is never trusted: the run removes it, says why in one line, and merges it again
(:func:`stale_store`).

A run recovers by itself: before Snakemake starts, :mod:`~isorock.control.runlock` tells a run still
working in the folder (refused, naming it) from a dead one (its lock cleared, saying so), and
:mod:`~isorock.control.integrity` removes the outputs that do not open, so that they are made again;
Snakemake always runs with ``--rerun-incomplete``. A failure says when the disk is full and when the
report is left older than the store.

In two steps, :func:`prepare_run` checks everything and returns the run's settings
(:class:`RunSettings`: the Snakemake command lines, the configuration), and
:meth:`RunSettings.execute` runs them.

Example
-------
::

    from isorock.pipeline import prepare_run, run_workflow

    # the ci configuration on this machine's records, 4 cores, in ./study
    res = run_workflow("config/ci.yaml", records="/data/records", cores=4, directory="study")
    print(res.store, res.report)  # study/results/isorock.h5 study/report-ci.html

    # what would run, without running it
    settings = prepare_run("config/ci.yaml", cores=4)
    print(" ".join(settings.run_cmd()))
    settings.execute(dry_run=True)  # snakemake -n: lists the jobs
"""

from __future__ import annotations

import contextlib
import importlib.util
import json
import os
import shutil
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any

from isorock.errors import IsorockError, Stopped

__all__ = [
    "RunSettings",
    "RunResult",
    "run_workflow",
    "prepare_run",
    "find_snakefile",
    "find_profile",
    "default_report_name",
    "previous_results",
    "stale_store",
    "keep_apart",
    "results_owner",
    "configuration_name",
    "run_snakemake",
]

Notify = Callable[[str], None]


def _stderr(line: str) -> None:
    print(line, file=sys.stderr)


@dataclass
class RunSettings:
    """The settings of a workflow run, and its two Snakemake invocations.

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
        Configuration values given beside the file (``--config KEY=VALUE``: ``records``).
    extra : list of str
        Further Snakemake options.
    warnings : list of str
        What the check of the records found (skipped catalog rows ...), one line each.
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
    warnings: list[str] = field(default_factory=list)

    @property
    def store(self) -> Path:
        """The store the run writes: ``<directory>/results/isorock.h5``."""
        return self.directory / "results" / "isorock.h5"

    def base(self, profile: bool = True) -> list[str]:
        """The options both commands share; ``profile``: with the workflow profile."""
        cmd = [sys.executable, "-m", "snakemake", "--snakefile", str(self.snakefile)]
        cmd += ["--directory", str(self.directory), "--configfile", str(self.configfile)]
        if self.overrides:
            cmd += ["--config", *(f"{k}={json.dumps(v)}" for k, v in self.overrides.items())]
        if profile and self.profile is not None:
            cmd += ["--workflow-profile", str(self.profile)]
        return cmd

    def run_cmd(self, dry_run: bool = False, report: bool = False) -> list[str]:
        """``snakemake --cores N`` (``-n`` for a dry run); ``report``: and its report once the jobs
        are done, by the same Snakemake (``--report-after-run``: not a second Snakemake that reads the
        Snakefile and builds the DAG again)."""
        cores = ["--cores", str(self.cores)] if self.cores is not None else []
        after = ["--report", str(self.report), "--report-after-run"] if report and not dry_run else []
        # no other run works here (runlock.claim): what a killed run left unfinished is run again
        return self.base() + cores + ["--rerun-incomplete"] + (["-n"] if dry_run else []) + after + self.extra

    def report_cmd(self) -> list[str]:
        """``snakemake --report FILE`` (here, whatever profile ran the jobs: it runs none)."""
        return self.base(profile=False) + ["--cores", "1", "--report", str(self.report)]

    def execute(
        self,
        *,
        dry_run: bool = False,
        run_jobs: bool = True,
        stdout: IO[Any] | None = None,
        notify: Notify | None = None,
    ) -> RunResult:
        """Run the workflow, then write its report.

        Parameters
        ----------
        dry_run : bool
            Only list the jobs (``snakemake -n``); no report.
        run_jobs : bool
            False: only write the report of an earlier run.
        stdout : file, optional
            Where Snakemake's standard output goes (default: ours).
        notify : callable, optional
            Called with each line for the user (that ``results/`` holds another configuration's
            results); default: printed on stderr.

        Returns
        -------
        RunResult

        Raises
        ------
        IsorockError
            Snakemake cannot start or fails (its messages are above).
        """
        notify = notify or _stderr
        from isorock.control import caches, integrity, runlock

        env = caches.cache_environment(self.directory, notify)
        # the warnings of the records check were said by prepare_run, the run's status line is said by
        # the run's Snakefile: the report's parse of the Snakefile says neither again
        said = {"run": {SAID_ENV: "warnings"}, "--report": {SAID_ENV: "all"}}
        if dry_run:  # lists the jobs; takes no lock, removes nothing
            run_snakemake(self.run_cmd(dry_run=True), "run", stdout=stdout, env={**env, **said["run"]})
            return RunResult(store=self.store, report=None, settings=self, dry_run=True)

        integrity.check_writable(self.directory)
        run = runlock.claim(
            self.directory,
            "isorock report" if run_jobs else "isorock report --no-run",
            notify,
            run_jobs=run_jobs,
            cluster=not runs_here(self.profile),
        )
        try:

            def started(pid: int) -> None:
                runlock.record_snakemake(self.directory, run, pid)

            def snakemake(cmd: list[str], what: str) -> None:
                run_snakemake(cmd, what, stdout=stdout, started=started, after=self.stale_report,
                              logs=self.directory / "logs", keep_fd=run.fd,
                              env={**env, **said[what]})  # fmt: skip

            keep_apart(self, notify)  # another configuration's results/ is kept, not replaced
            if run_jobs:
                stale_store(self, notify)
                integrity.remove_damaged(self.directory, notify)
                if runs_here(self.profile):
                    # compile the engine once, here (saying so), instead of in several jobs at once
                    from isorock.physics.engine import warm_up

                    warm_up()
                snakemake(self.run_cmd(report=True), "run")
            else:
                bad = integrity.damaged(self.directory)
                if bad:
                    raise IsorockError(
                        f"{bad[0][0]} is damaged ({bad[0][1]}): run the workflow again, without --no-run"
                    )
                if not self.store.is_file():  # never a report of another configuration's results
                    raise IsorockError(
                        f"{self.store}: no results of {configuration_name(self.configfile)!r} here: "
                        "run the workflow first, without --no-run"
                    )
                snakemake(self.report_cmd(), "--report")
        finally:
            runlock.release(self.directory, run)
        return RunResult(store=self.store, report=self.report, settings=self)

    def stale_report(self) -> str:
        """What ends the message of a failed run: that the disk of ``results/`` is full, that the report
        is older than the store (it shows an earlier run); "" when neither."""
        note = ""
        results = self.directory / "results"
        try:
            free = shutil.disk_usage(results if results.is_dir() else self.directory).free
            if free < FULL_DISK_BYTES:
                note += f"; the disk of {results} is full ({free / 1e6:.1f} MB free): free some space"
        except OSError:
            pass
        if self.report.is_file() and (
            not self.store.is_file() or self.report.stat().st_mtime < self.store.stat().st_mtime
        ):
            note += f"; {self.report.name} is older than {self.store}: it shows an earlier run"
        return note


#: the environment variable that tells the workflow's Snakefile what isorock has said already, so that
#: each line is said once: ``warnings`` (the records check's, said by :func:`prepare_run`), ``all``
#: (those and the run's status line: the parse of ``snakemake --report --no-run``); unset, it says both
SAID_ENV = "ISOROCK_SAID"

#: below this much free space (bytes) on the disk of ``results/``, a failed run is said to have met a
#: full disk (a job file of the paper's configuration is up to a few MB; the store tens of MB)
FULL_DISK_BYTES = 50_000_000


def runs_here(profile: Path | None) -> bool:
    """True when a workflow profile runs the jobs on this machine (no executor, or ``local``).

    Parameters
    ----------
    profile : Path or None
        The profile directory (its ``config.yaml``); None: Snakemake's defaults, this machine.
    """
    if profile is None:
        return True
    import yaml

    try:
        data = yaml.safe_load((Path(profile) / "config.yaml").read_text()) or {}
    except (OSError, yaml.YAMLError):
        return True
    return str(data.get("executor") or "local") in ("local", "dryrun")


@dataclass(frozen=True)
class RunResult:
    """What a workflow run wrote.

    Attributes
    ----------
    store : Path
        The store of the results, ``results/isorock.h5`` in the working directory (not written by a
        dry run).
    report : Path or None
        The HTML report; None for a dry run.
    settings : RunSettings
        The settings it ran with.
    dry_run : bool
        True when the jobs were only listed.
    """

    store: Path
    report: Path | None
    settings: RunSettings
    dry_run: bool = False


def find_snakefile(given: str | Path | None = None) -> Path:
    """The workflow's Snakefile: ``given``, else the one that comes with isorock.

    Raises
    ------
    IsorockError
        ``given`` does not exist, or the installation lacks its workflow.
    """
    import isorock.resources as resources

    if given:
        p = Path(given).expanduser()
        if not p.is_file():
            raise IsorockError(f"{p}: no such Snakefile")
        return p.resolve()
    return resources.snakefile().resolve()


def find_profile(name: str | Path, workflow_dir: Path) -> Path:
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


def default_report_name(configfile: str | Path | None) -> str:
    """``report.html`` for the default configuration, ``report-<name>.html`` for ``<name>.yaml``."""
    if not configfile:
        return "report.html"
    stem = Path(configfile).stem
    return "report.html" if stem == "config" else f"report-{stem}.html"


def prepare_run(
    configfile: str | Path | None = None,
    *,
    records: str | Path | None = None,
    cores: int | None = None,
    profile: str | Path = "default",
    directory: str | Path | None = None,
    report: str | Path | None = None,
    snakefile: str | Path | None = None,
    snakemake_args: Sequence[str] = (),
    notify: Notify | None = None,
    force: bool = False,
) -> RunSettings:
    """The settings of a workflow run, checked: the configuration as the workflow will see it, the
    records, the profile, the cost; nothing runs. The arguments are those of :func:`run_workflow`.

    Parameters
    ----------
    notify : callable, optional
        Called with each warning line of the records check (also kept in
        :attr:`RunSettings.warnings`) and with the run's cost estimate
        (:func:`isorock.control.cost.estimate`: analyses per study, expected time on ``cores``);
        default: printed on stderr.
    force : bool
        Run a configuration whose estimate is above :data:`isorock.control.cost.MAX_ANALYSES`
        analyses (refused otherwise).

    Returns
    -------
    RunSettings

    Raises
    ------
    IsorockError
        A bad value (``cores`` < 1, no such configuration file, records directory or profile), a
        configuration that fails its checks (:class:`~isorock.errors.ConfigError`), no records to run,
        Snakemake not installed, or a run above the cost limit without ``force``.
    """
    from isorock.control.config import workflow_config
    from isorock.control.cost import check_cost, estimate, profile_cores
    from isorock.control.lengths import keep_lengths, read_lengths, record_lengths
    from isorock.control.memory import job_memory_mb
    from isorock.control.plan import plan

    notify = notify or _stderr
    if cores is not None and cores < 1:
        raise IsorockError(f"--cores {cores}: valid an integer >= 1")
    snakefile_path = find_snakefile(snakefile)
    wf = snakefile_path.parent
    config_path = Path(configfile).expanduser() if configfile else wf / "config" / "config.yaml"
    if not config_path.is_file():
        raise IsorockError(f"{config_path}: no such configuration file")
    workdir = (Path(directory).expanduser() if directory else Path.cwd()).resolve()
    overrides: dict = {}
    if records is not None:
        rec = Path(records).expanduser()
        if not rec.is_dir():
            raise IsorockError(f"--records {rec}: no such directory")
        overrides["records"] = {"dir": str(rec.resolve())}
    config = workflow_config(config_path, overrides)  # what the workflow will see; one line when bad
    if importlib.util.find_spec("snakemake") is None:
        raise IsorockError("isorock report needs Snakemake: pip install 'isorock[workflow]'")
    p = plan(config, basedir=workdir)  # a missing records directory, or no records, in one line
    for w in p.warnings:
        notify(f"isorock: warning: {w}")
    profile_path = find_profile(profile, wf)
    # every record's length, read once: too long a record stops here, in one line, before any job
    known = read_lengths(workdir)
    lengths = record_lengths(p.records, config, known, notify)
    longest_mb = max((Path(x.file).stat().st_size for x in lengths), default=0) / 2**20
    est = estimate(
        config,
        len(p.records),
        cores=cores or profile_cores(profile_path),
        basedir=workdir,
        durations_s=[x.duration_s for x in lengths],
        memory_mb=job_memory_mb("process_record", longest_mb) if lengths else None,
    )
    check_cost(est, force=force)  # above the limit: one line naming the estimate and --force
    notify(f"isorock: {est.text()}")
    keep_lengths(workdir, known)
    extra = list(snakemake_args or [])
    if extra and extra[0] == "--":
        extra = extra[1:]
    report_path = Path(report or default_report_name(configfile))
    return RunSettings(
        snakefile=snakefile_path,
        directory=workdir,
        configfile=config_path.resolve(),
        report=(workdir / report_path if not report_path.is_absolute() else report_path).resolve(),
        config=config,
        cores=cores,
        profile=profile_path,
        overrides=overrides,
        extra=extra,
        warnings=list(p.warnings),
    )


#: the file of ``results/`` that names the configuration whose results it holds
OWNER_FILE = "configuration.txt"


def configuration_name(configfile: str | Path | None) -> str:
    """The name of a configuration, as the store and the report have it: ``config`` for the default
    one (``config/config.yaml``), ``<name>`` for ``<name>.yaml``.

    Parameters
    ----------
    configfile : path-like or None
        The configuration file; None: the default one.
    """
    return Path(configfile).stem if configfile else "config"


def results_owner(directory: Path) -> str | None:
    """The name of the configuration whose results ``directory/results`` holds: the one its
    :data:`OWNER_FILE` names, else (results of an isorock that wrote no such file) the ``config_name``
    of its store; None when it names none (no such folder, or neither file).

    Parameters
    ----------
    directory : Path
        The working directory of a run.
    """
    import h5py

    results = Path(directory) / "results"
    owner = results / OWNER_FILE
    if owner.is_file():
        name = owner.read_text(encoding="utf-8", errors="replace").strip()
        return name or None
    store = results / "isorock.h5"
    if not store.is_file():
        return None
    try:
        with h5py.File(store, "r") as f:
            name = str(f.attrs.get("config_name", ""))
    except (OSError, ValueError):
        return None  # unreadable: integrity.remove_damaged removes it
    return Path(name).stem if name else None


def keep_apart(settings: RunSettings, notify: Notify) -> None:
    """Keep the results of each configuration run in one folder apart, so that none replaces another's.

    ``results/`` holds the results of the configuration run last. When it holds another
    configuration's (:func:`results_owner`), the whole folder, the store, the job files and the pages
    of its report, is moved to ``results-<that name>/`` (its report, ``report-<that name>.html``, shows
    what those pages show); then, when an earlier run of this configuration was kept so, its
    ``results-<name>/`` comes back to ``results/``, finished jobs and all. Each move is said in one
    line. Last, ``results/`` is marked as this configuration's (:data:`OWNER_FILE`).

    Parameters
    ----------
    settings : RunSettings
        The run (its working directory and configuration).
    notify : callable
        Called with each line for the user.
    """
    results = settings.directory / "results"
    mine = configuration_name(settings.configfile)
    owner = results_owner(settings.directory)
    if results.is_dir() and owner is not None and owner != mine:
        kept = settings.directory / f"results-{owner}"
        again = kept.exists()
        if again:  # an older run of that configuration, kept earlier: results/ holds its newer one
            shutil.rmtree(kept) if kept.is_dir() else kept.unlink()
        results.rename(kept)
        _move_records(settings.directory / ".snakemake", kept / _RECORDS_KEPT)
        notify(
            f"isorock: {results} held the results of configuration {owner!r} "
            f"({default_report_name(owner + '.yaml')}): kept in {kept}"
            + (" (replacing its older copy there)" if again else "")
            + f"; {mine!r} runs in {results}"
        )
    earlier = settings.directory / f"results-{mine}"
    if not results.exists() and earlier.is_dir():
        earlier.rename(results)
        _move_records(results / _RECORDS_KEPT, settings.directory / ".snakemake")
        with contextlib.suppress(OSError):
            (results / _RECORDS_KEPT).rmdir()  # emptied
        notify(
            f"isorock: {earlier} (an earlier run of {mine!r}) is back in {results}: its finished jobs "
            "are kept"
        )
    results.mkdir(parents=True, exist_ok=True)
    (results / OWNER_FILE).write_text(mine + "\n", encoding="utf-8")


#: Snakemake's records of the outputs of ``results/`` (their code, parameters, inputs; the jobs left
#: unfinished), folders of ``.snakemake/``: they go with the results kept apart, so that a
#: configuration's results brought back are as Snakemake left them (no job runs again for being
#: recorded as another configuration's)
_SNAKEMAKE_RECORDS = ("metadata", "incomplete")
#: where ``results-<name>/`` keeps them
_RECORDS_KEPT = ".snakemake"


def _move_records(src: Path, dst: Path) -> None:
    """Move Snakemake's records of the outputs (:data:`_SNAKEMAKE_RECORDS`) from the folder ``src`` to
    ``dst``, replacing those there (they are of outputs no longer there)."""
    for sub in _SNAKEMAKE_RECORDS:
        old, new = src / sub, dst / sub
        if new.exists():
            shutil.rmtree(new)
        if old.is_dir():
            dst.mkdir(parents=True, exist_ok=True)
            old.rename(new)


def previous_results(settings: RunSettings) -> str | None:
    """Why ``results/isorock.h5`` is not what this run would make, or None: the store of another
    configuration, of another version of isorock, a file that is no isorock store (an HDF5 file
    without the root attributes the merge writes), a store one of whose job files (its root's
    ``job_files_json``) was deleted, or one whose record file has changed since (the ``record_sha256``
    of ``/records/<id>``; the job files of that record are removed, so that its jobs run again). Such
    a store is never trusted: :func:`stale_store` removes it so that the run merges it again."""
    import h5py

    from isorock.store import config_hash, file_sha256
    from isorock.version import __version__

    store = settings.store
    if not store.is_file():
        return None
    try:
        with h5py.File(store, "r") as f:
            old_hash = str(f.attrs.get("config_hash", ""))
            old_name = str(f.attrs.get("config_name", "?"))
            old_version = str(f.attrs.get("isorock_version", ""))
            jobs = json.loads(str(f.attrs.get("job_files_json", "[]")))
            read = {
                rid: (str(g.attrs.get("source_file", "")), str(g.attrs.get("record_sha256", "")))
                for rid, g in (f["records"].items() if "records" in f else [])
            }
    except (OSError, ValueError):
        return None  # unreadable: integrity.remove_damaged removes it
    new_hash = config_hash(json.loads(json.dumps(settings.config, default=str)))
    if not old_hash:
        return f"isorock: {store} is no store of an isorock run (no configuration hash)"
    if old_hash != new_hash:
        return f"isorock: {store} holds the results of configuration {old_name!r}, not of this one"
    if old_version != __version__:
        return f"isorock: {store} was written by isorock {old_version or '?'}, this is {__version__}"
    gone = [j for j in jobs if not (settings.directory / j).exists()]
    if gone:
        more = f" (and {len(gone) - 1} more)" if len(gone) > 1 else ""
        return f"isorock: {store} was merged from {settings.directory / gone[0]}{more}, deleted since"
    changed = [(rid, path) for rid, (path, sha) in sorted(read.items())
               if sha and Path(path).is_file() and file_sha256(path) != sha]  # fmt: skip
    if changed:
        # the jobs of those records run again: their job files go with the store
        stems = {rid for rid, _ in changed}
        for j in jobs:
            if Path(j).stem in stems:
                (settings.directory / j).unlink(missing_ok=True)
        rid, path = changed[0]
        more = f" (and {len(changed) - 1} more)" if len(changed) > 1 else ""
        return f"isorock: {store} was made from the record file {path} of {rid}{more}, changed since"
    return None


def stale_store(settings: RunSettings, notify: Callable[[str], None]) -> bool:
    """Remove a store that is not what this run would make (:func:`previous_results`), saying why in
    one line, so that Snakemake merges it again from this configuration's job files (and the report
    is made again from it). Returns whether one was removed."""
    why = previous_results(settings)
    if why is None:
        return False
    settings.store.unlink(missing_ok=True)
    notify(
        f"{why}: removed; this run of {settings.configfile.name!r} merges it again (its report: "
        f"{settings.report.name})"
    )
    return True


def run_snakemake(
    cmd: list[str],
    what: str,
    stdout: IO[Any] | None = None,
    *,
    started: Callable[[int], None] | None = None,
    after: Callable[[], str] | None = None,
    logs: Path | None = None,
    keep_fd: int | None = None,
    env: Mapping[str, str] | None = None,
) -> None:
    """Run one Snakemake command; its failure is one line (the messages are above it).

    Parameters
    ----------
    cmd : list of str
        The command.
    what : str
        What it does, for the message (``run``, ``--report``).
    stdout : file, optional
        Where its standard output goes (default: ours).
    started : callable, optional
        Called with Snakemake's process id once it has started.
    after : callable, optional
        Called on a failure; what it returns ends the message (that the report is now older than the
        store).
    logs : Path, optional
        The folder of the job logs, named in the message (default: ``logs``, relative).
    keep_fd : int, optional
        A descriptor Snakemake inherits (the run lock, :mod:`isorock.control.runlock`: held while
        Snakemake lives, should this process be killed).
    env : mapping, optional
        Environment variables set for Snakemake and its jobs beside this process's
        (:func:`isorock.control.caches.cache_environment`).

    Raises
    ------
    IsorockError
        Snakemake cannot start, or exits with a non-zero code.
    Stopped
        This process was sent SIGINT, SIGTERM or SIGHUP while Snakemake ran (Ctrl-C, ``kill PID``,
        ``timeout``, a closed terminal): Snakemake, in a process group of its own, was sent SIGINT
        once, and has ended its jobs (it removes what they left unfinished, and unlocks the folder),
        so that the same command resumes. A second such signal sends it SIGTERM, a third kills it and
        its jobs (the next run clears the lock they leave and runs their jobs again).
    """
    got: list[int] = []
    proc: subprocess.Popen | None = None

    def stop(signum: int, frame: Any) -> None:
        name = signal.Signals(signum).name
        if proc is not None and len(got) < len(_ESCALATION):
            # SIGINT makes Snakemake end its jobs, remove what they left unfinished and unlock; asked
            # again, it is sent SIGTERM, then killed with its jobs (its process group)
            send, words = _ESCALATION[len(got)]
            with contextlib.suppress(ProcessLookupError):
                if send == signal.SIGKILL:
                    os.killpg(proc.pid, send)
                else:
                    proc.send_signal(send)
            print(f"isorock: {name}: {words}", file=sys.stderr, flush=True)
        got.append(signum)

    t_start = time.time() - 1.0  # the logs written from here on (mtime of a coarse file system)
    # the handlers are set before Snakemake starts: it then starts with SIGINT at its default (a
    # handled signal is reset at exec, an ignored one, as in a shell's background job, would stay so)
    with _signals_to(stop):
        try:
            # its own process group: a terminal's Ctrl-C reaches this process alone, which passes it on
            # once (a second SIGINT would cut Snakemake's own clean-up short)
            proc = subprocess.Popen(
                cmd,
                stdout=stdout,
                pass_fds=(keep_fd,) if keep_fd is not None else (),
                process_group=0,
                env={**os.environ, **env} if env else None,
            )
        except OSError as exc:
            raise IsorockError(f"cannot start snakemake: {exc.strerror or exc}") from None
        if got:  # a signal before Snakemake had started
            stop(got.pop(), None)
        try:
            if started is not None:
                started(proc.pid)
            rc = proc.wait()
        except BaseException:  # an error in ``started``: Snakemake stops too
            with contextlib.suppress(ProcessLookupError):
                proc.send_signal(signal.SIGINT)
            try:
                proc.wait(timeout=60)
            except (subprocess.TimeoutExpired, KeyboardInterrupt):
                proc.kill()
            raise
    if got:
        raise Stopped(
            got[0],
            f"snakemake {what} ended its jobs (exit code {rc}); the same command resumes (finished jobs "
            "are kept)",
        )
    if rc != 0:
        first = _job_error(logs, t_start)
        if first:
            raise IsorockError(
                f"{first} (a job of snakemake {what} stopped on it; once it is fixed, the same command "
                "resumes: finished jobs are kept)"
            )
        raise IsorockError(
            f"snakemake {what} failed with exit code {rc}: see its messages above and the job logs in "
            f"{logs or 'logs'}/; "
            "once the cause is fixed, the same command resumes (finished jobs are kept)"
            + (after() if after is not None else "")
        )


def _job_error(logs: Path | None, since: float) -> str:
    """The first line a job wrote in its log since ``since`` (epoch seconds) when its input was at fault
    (:data:`isorock.control.joblog.JOB_ERROR`), without that prefix; "" when none did."""
    from isorock.control.joblog import JOB_ERROR

    folder = Path(logs) if logs is not None else Path("logs")
    if not folder.is_dir():
        return ""
    found = []
    for p in folder.rglob("*.log"):
        try:
            if p.stat().st_mtime < since:
                continue
            for line in p.read_text(encoding="utf-8", errors="replace").splitlines():
                if line.startswith(JOB_ERROR):
                    found.append((p.stat().st_mtime, line[len(JOB_ERROR) :]))
        except OSError:
            continue
    return min(found)[1] if found else ""


#: the signals that stop a run: Ctrl-C, ``kill PID`` and ``timeout``, a closed terminal
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)

#: what Snakemake is sent at the first, second and third such signal, and the line that says so
_ESCALATION = (
    (signal.SIGINT, "stopping snakemake and its jobs (they remove what they left unfinished) ..."),
    (signal.SIGTERM, "asked again: snakemake is sent SIGTERM (it ends once its running jobs end) ..."),
    (signal.SIGKILL, "asked a third time: snakemake and its jobs are killed; the next run cleans up"),
)


@contextlib.contextmanager
def _signals_to(handler: Callable[[int, Any], None]) -> Iterator[None]:
    """Send :data:`STOP_SIGNALS` to ``handler`` for the block, then restore their handlers (in the main
    thread only: elsewhere Python cannot set handlers, and the block runs with the process's)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    before = {s: signal.signal(s, handler) for s in STOP_SIGNALS}
    try:
        yield
    finally:
        for s, h in before.items():
            signal.signal(s, h)


def run_workflow(
    configfile: str | Path | None = None,
    *,
    records: str | Path | None = None,
    cores: int | None = None,
    profile: str | Path = "default",
    directory: str | Path | None = None,
    report: str | Path | None = None,
    snakefile: str | Path | None = None,
    snakemake_args: Sequence[str] = (),
    dry_run: bool = False,
    run_jobs: bool = True,
    stdout: IO[Any] | None = None,
    notify: Notify | None = None,
    force: bool = False,
) -> RunResult:
    """Run the isorock workflow (``snakemake``) and write its HTML report (``--report-after-run``).

    Parameters
    ----------
    configfile : path-like, optional
        Workflow configuration, merged over the workflow's ``config/config.yaml`` (default: that file
        alone).
    records : path-like, optional
        Records directory; replaces ``records.dir`` of the configuration.
    cores : int, optional
        Cores for Snakemake on this machine; with a cluster profile, the most CPUs one cluster job asks
        for (default: the profile's).
    profile : str or path-like
        Workflow profile: ``default`` (this machine), ``slurm`` (a SLURM cluster; needs
        ``isorock[cluster]``, run on the login node) or the folder of a profile of one's own.
    directory : path-like, optional
        Working directory for ``results/`` (default: the current directory).
    report : path-like, optional
        Report file, relative to ``directory`` (default: ``report.html``, or ``report-<name>.html``
        for a ``configfile`` ``<name>.yaml``).
    snakefile : path-like, optional
        The workflow (default: the one isorock ships).
    snakemake_args : sequence of str
        Further Snakemake options.
    dry_run : bool
        Only list the jobs (``snakemake -n``); no report.
    run_jobs : bool
        False: only write the report of an earlier run.
    stdout : file, optional
        Where Snakemake's standard output goes (default: ours).
    notify : callable, optional
        Called with each line for the user (warnings of the records check, the cost estimate, a note
        that ``results/`` holds another configuration's results); default: printed on stderr.
    force : bool
        Run a configuration whose cost estimate is above the limit
        (:data:`isorock.control.cost.MAX_ANALYSES` analyses; refused otherwise).

    Returns
    -------
    RunResult
        The paths of the store (``results/isorock.h5``) and of the report.

    Raises
    ------
    IsorockError
        A bad setting or configuration, no records, a run above the cost limit without ``force``
        (before any job: :func:`prepare_run`), or a Snakemake failure.
    """
    settings = prepare_run(
        configfile,
        records=records,
        cores=cores,
        profile=profile,
        directory=directory,
        report=report,
        snakefile=snakefile,
        snakemake_args=snakemake_args,
        notify=notify,
        force=force,
    )
    return settings.execute(dry_run=dry_run, run_jobs=run_jobs, stdout=stdout, notify=notify)
