"""Who is running in a working directory: a live run is waited for, a dead one's lock is cleared.

Snakemake locks a working directory while it runs (``.snakemake/locks``) and leaves the lock behind
when it is killed (``kill -9``, a lost node, a full machine); the next run is then refused with
"Directory cannot be locked". Snakemake alone cannot tell that lock from the one of a run still
working, so :func:`run_workflow <isorock.control.run.run_workflow>` writes a run file,
``.snakemake/isorock-run.json``, before it starts Snakemake: its own process id, Snakemake's, the
host, the start time and each process's start time in the kernel's clock (so that a process id
reused by another program is not taken for the run), and holds an exclusive ``flock`` on
``.snakemake/isorock-run.lock`` for as long as it and its Snakemake live (the kernel lets it go when
they end, ``kill -9`` included), so that two runs started at the same moment cannot both start. Before
a run :func:`claim` takes that lock and reads the run file:

- the lock is held, a process of that run is alive on this host, or a Snakemake process or job of
  this directory that no run file names (``snakemake`` started by hand, a job left working by a killed
  Snakemake): :class:`~isorock.errors.IsorockError`, "another run
  (pid N, since T) is working in this folder: wait for it or use another folder";
- a run file of another host (a cluster's shared disk): the same error, since it cannot be checked
  from here, with the file to remove if that run is gone;
- otherwise a lock left behind is stale: it is removed (the lock files only, as
  ``snakemake --unlock`` does) and one line says so; the run then starts with
  ``--rerun-incomplete`` so that the jobs the dead run left unfinished run again.

- SLURM jobs of this user working in the folder (``squeue``, asked where a cluster is in use): the
  same error, naming them (a run through ``--profile slurm`` whose login-node Snakemake died leaves
  them running).

Processes are found through ``/proc`` (Linux); elsewhere only the run file's process ids are checked.
"""

from __future__ import annotations

import json
import os
import socket
import time
from collections.abc import Callable, Iterator
from dataclasses import asdict, dataclass, field
from pathlib import Path

from isorock.errors import IsorockError
from isorock.store.atomic import try_lock

__all__ = ["RunFile", "RUN_FILE", "claim", "release", "record_snakemake", "live_snakemake"]

RUN_FILE = ".snakemake/isorock-run.json"
LOCK_FILE = ".snakemake/isorock-run.lock"
LOCKS = ".snakemake/locks"


def _stat(pid: int) -> tuple[str, int] | None:
    """The state and start time (clock ticks since boot) of process ``pid`` (``/proc/<pid>/stat``
    fields 3 and 22); None when it is not there or ``/proc`` is not there."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    # the command name (field 2) is in parentheses and may hold spaces: split after its closing one
    fields = stat.rsplit(")", 1)[1].split()
    return fields[0], int(fields[19])


def _start_ticks(pid: int) -> int | None:
    """The start time of process ``pid`` in clock ticks since boot; None when unknown."""
    st = _stat(pid)
    return st[1] if st else None


def _alive(pid: int, ticks: int | None) -> bool:
    """True when process ``pid`` runs and is the one started at ``ticks`` (when given)."""
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process of that id: alive
        pass
    st = _stat(pid)
    if st is None:
        return True  # no /proc: os.kill's answer
    if st[0] in ("Z", "X"):  # killed, not yet reaped by its parent: it does nothing any more
        return False
    return ticks is None or st[1] == ticks


@dataclass
class RunFile:
    """The run file of a working directory (``.snakemake/isorock-run.json``).

    Attributes
    ----------
    pid : int
        The process that started the run (``isorock report``, ``isorock assess``, a Python caller).
    host : str
        The host it runs on.
    started : str
        When it started (local time, ISO 8601, to the second).
    command : str
        What it runs (for the message).
    ticks : int or None
        ``pid``'s start time in clock ticks since boot (None where ``/proc`` is not there).
    snakemake : list of [pid, ticks]
        The Snakemake processes it started.
    """

    pid: int
    host: str
    started: str
    command: str
    ticks: int | None = None
    snakemake: list[list[int | None]] = field(default_factory=list)
    #: whether its jobs run on a cluster (a profile with an executor such as slurm)
    cluster: bool = False
    #: the descriptor holding the run lock (not written in the file)
    fd: int | None = field(default=None, repr=False, compare=False)

    def pids(self) -> Iterator[tuple[int, int | None]]:
        yield self.pid, self.ticks
        for p, t in self.snakemake:
            if p is not None:
                yield int(p), t

    def alive(self) -> int | None:
        """The process id of one of its processes that still runs here (None: none does)."""
        return next((p for p, t in self.pids() if _alive(p, t)), None)


def _read(directory: Path) -> RunFile | None:
    path = directory / RUN_FILE
    try:
        return RunFile(**json.loads(path.read_text()))
    except (OSError, ValueError, TypeError):
        return None  # no run file, or a damaged one (a run killed while writing it): nothing to trust


def _write(directory: Path, run: RunFile) -> None:
    path = directory / RUN_FILE
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    data = asdict(run)
    data.pop("fd")
    tmp.write_text(json.dumps(data))
    os.replace(tmp, path)


def live_snakemake(directory: Path) -> list[int]:
    """Process ids of the Snakemake processes working in ``directory`` (their working directory or
    their ``--directory``) and of the jobs they started there (``.snakemake/scripts/``: a job goes on
    when only its Snakemake is killed), this process's own excepted; empty where ``/proc`` is not
    there."""
    directory = directory.resolve()
    found = []
    for proc in Path("/proc").glob("[0-9]*"):
        pid = int(proc.name)
        if pid == os.getpid():
            continue
        try:
            args = (proc / "cmdline").read_bytes().split(b"\0")
            cwd = Path(os.readlink(proc / "cwd"))
        except OSError:
            continue
        words = [a.decode(errors="replace") for a in args if a]
        if any(".snakemake/scripts/" in w for w in words) and cwd.resolve() == directory:
            found.append(pid)  # a job of a run (a script rule), left working by a killed Snakemake
            continue
        if not any(Path(w).name == "snakemake" or w == "snakemake" for w in words[:3]):
            continue
        where = cwd
        for flag in ("--directory", "-d"):
            if flag in words[:-1]:
                given = Path(words[words.index(flag) + 1])
                where = given if given.is_absolute() else cwd / given
        try:
            if where.resolve() == directory:
                found.append(pid)
        except OSError:
            continue
    return found


def cluster_jobs(directory: Path, *, asked: bool = False) -> list[str]:
    """The SLURM jobs of this user whose working directory is ``directory`` (``squeue --me``, field
    ``%Z``): the jobs of a run through a cluster profile go on when the Snakemake that submitted them
    on the login node dies. Asked only where a cluster is in use (``asked``: this run goes to a cluster,
    or the run file of the last run says that one did; or ``.snakemake/slurm_logs`` exists, which
    snakemake-executor-plugin-slurm writes while its jobs run), so that a machine with a SLURM client and
    no controller does not wait for it; empty where ``squeue`` is not installed or does not answer."""
    import shutil
    import subprocess

    if shutil.which("squeue") is None:
        return []
    if not (asked or (directory / ".snakemake" / "slurm_logs").is_dir()):
        return []
    try:
        res = subprocess.run(
            ["squeue", "--me", "--noheader", "--states=PD,R,CF,CG,S", "--format=%i %Z"],
            capture_output=True,
            text=True,
            timeout=30,
        )
    except (OSError, subprocess.TimeoutExpired):
        return []
    if res.returncode != 0:
        return []
    directory = directory.resolve()
    jobs = []
    for line in res.stdout.splitlines():
        job, _, where = line.strip().partition(" ")
        try:
            if where and Path(where).resolve() == directory:
                jobs.append(job)
        except OSError:
            continue
    return jobs


def _since(run: RunFile) -> str:
    return run.started.replace("T", " ")


def _hold(directory: Path) -> int | None:
    """Take the run lock, an exclusive ``flock`` on ``.snakemake/isorock-run.lock``
    (:func:`isorock.store.atomic.try_lock`); its descriptor, or None when another process holds it. The
    kernel lets it go when its holders end, ``kill -9`` included: two runs started at the same moment
    cannot both pass :func:`claim`."""
    return try_lock(directory / LOCK_FILE)


def claim(
    directory: Path,
    command: str,
    notify: Callable[[str], None],
    *,
    run_jobs: bool = True,
    cluster: bool = False,
) -> RunFile:
    """Make sure no other run works in ``directory``, clear a dead run's lock, and write this run's
    run file, holding the run lock (:func:`_hold`) until :func:`release`.

    Parameters
    ----------
    directory : Path
        The working directory.
    command : str
        What this run is (``isorock report``), kept in the run file for another run's message.
    notify : callable
        Called with the line saying that a stale lock was cleared.
    run_jobs : bool
        Whether this run runs jobs (False: it only writes the report), for that line.
    cluster : bool
        Whether its jobs run on a cluster: ``squeue`` is asked for jobs working in the folder, and the
        run file keeps it (a later run asks too).

    Returns
    -------
    RunFile
        This run's run file; its ``fd`` holds the run lock.

    Raises
    ------
    IsorockError
        Another run works in the folder.
    """
    directory = directory.resolve()
    here = socket.gethostname()
    fd = _hold(directory)
    other = _read(directory)
    try:
        if other is not None and other.host != here:
            raise IsorockError(
                f"another run (pid {other.pid} on host {other.host}, since {_since(other)}) is working in "
                f"{directory}: wait for it or use another folder (--directory DIR); if that run is gone, "
                f"rm {directory / RUN_FILE} and run the same command again"
            )
        pid = other.alive() if other is not None else None
        known = {q for q, _ in other.pids()} if other is not None else set()
        hand = [p for p in live_snakemake(directory) if p not in known]
        if fd is None or pid is not None or hand:
            since = _since(other) if other is not None else "an unknown time"
            who = pid or (hand[0] if hand else (other.pid if other is not None else "unknown"))
            raise IsorockError(
                f"another run (pid {who}, since {since}) is working in this folder "
                f"({directory}): wait for it or use another folder (--directory DIR)"
            )
        queued = cluster_jobs(directory, asked=cluster or (other is not None and other.cluster))
        if queued:
            raise IsorockError(
                f"{len(queued)} cluster job(s) of another run (SLURM job {', '.join(queued[:3])}"
                f"{' ...' if len(queued) > 3 else ''}) are working in this folder ({directory}): wait for "
                f"them (squeue --me) or cancel them (scancel {' '.join(queued[:3])}), or use another folder "
                "(--directory DIR)"
            )
    except IsorockError:
        if fd is not None:
            os.close(fd)
        raise
    locks = directory / LOCKS
    stale = sorted(locks.glob("*.lock")) if locks.is_dir() else []
    if stale:
        for lock in stale:  # what `snakemake --unlock` removes
            lock.unlink(missing_ok=True)
        who = f" (pid {other.pid}, since {_since(other)})" if other is not None else ""
        notify(
            f"isorock: a run that stopped before finishing{who} left {directory} locked: lock cleared"
            + (", its unfinished jobs run again" if run_jobs else "")
        )
    run = RunFile(
        pid=os.getpid(),
        host=here,
        started=time.strftime("%Y-%m-%dT%H:%M:%S"),
        command=command,
        ticks=_start_ticks(os.getpid()),
        cluster=cluster,
    )
    run.fd = fd
    _write(directory, run)
    return run


def record_snakemake(directory: Path, run: RunFile, pid: int) -> None:
    """Add the Snakemake process ``pid`` to the run file (a killed wrapper leaves it running)."""
    run.snakemake.append([pid, _start_ticks(pid)])
    _write(directory.resolve(), run)


def release(directory: Path, run: RunFile | None) -> None:
    """Remove the run file of ``run`` (left in place when another run has written its own since) and
    let the run lock go."""
    if run is None:
        return
    current = _read(directory.resolve())
    if current is not None and current.pid == run.pid and current.ticks == run.ticks:
        (directory.resolve() / RUN_FILE).unlink(missing_ok=True)
    if run.fd is not None:
        os.close(run.fd)
        run.fd = None
