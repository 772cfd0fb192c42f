"""Fault injection: a workflow run killed, its outputs damaged, its folder shared, its disk read-only
or full, and the same ``isorock report`` command run again, with no manual step in between.

Second stage (``pytest -m e2e``, run by ``.ci/run``): each test runs the workflow several times. The
configuration is tiny (two pyslammer sample records, the grids of ``tests/pipeline/test_workflow.py``):
an uninterrupted run is the reference, and every faulted run must end with a store holding the same
numbers (``tests/cluster/compare_stores.py``: 0 differences).

- ``kill -9`` of the whole run (wrapper, Snakemake and its jobs) at 5 seeded points of its progress,
  the same command run again after each; ``kill -9`` of Snakemake alone, its jobs going on;
- a truncated store, a truncated and an empty job file;
- a second run started in the folder while the first works;
- a read-only ``results/`` and a full disk (a bind mount and a small tmpfs: root only, skipped with
  the reason elsewhere).

The moments of the kills are points of the run's own progress, never times: Snakemake writes
``k of n steps (p%) done`` as each job ends, and a killed run is killed as soon as its live log shows
the seeded ``k`` (or, for ``k = 0``, its first job). A kill thus means the same on any machine and
under any load, and no test depends on how fast the machine is (``TIMEOUT`` only ends a run that
hangs).
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
import pytest
import yaml

from support.records import ROOT

pytestmark = pytest.mark.e2e

sys.path.insert(0, str(ROOT / "tests" / "cluster"))
from compare_stores import compare  # noqa: E402

sys.path.insert(0, str(ROOT / "tests" / "pipeline"))
from test_workflow import tiny_config  # noqa: E402

SEED = 20261126
N_KILLS = 5
TIMEOUT = 600


def _config() -> dict:
    cfg = tiny_config(Path("."), [])
    # the samples whatever $ISOROCK_RECORDS says: the same two records on every machine
    cfg["records"] = {"dir": None, "include": ["samples"], "max_records": 2, "choose": "table1_pgv"}
    return cfg


def _command(folder: Path) -> list[str]:
    return [sys.executable, "-m", "isorock.cli", "report", "--configfile", "tiny.yaml", "--cores", "2",
            "--directory", str(folder)]  # fmt: skip


def _folder(path: Path) -> Path:
    path.mkdir(parents=True, exist_ok=True)
    (path / "tiny.yaml").write_text(yaml.safe_dump(_config()))
    return path


def _run(folder: Path, timeout: float = TIMEOUT) -> subprocess.CompletedProcess:
    return subprocess.run(_command(folder), cwd=folder, capture_output=True, text=True, timeout=timeout)


def _start(folder: Path, log: Path) -> subprocess.Popen:
    with open(log, "w") as fh:
        return subprocess.Popen(
            _command(folder), cwd=folder, stdout=fh, stderr=subprocess.STDOUT, start_new_session=True
        )


def _children() -> dict[int, list[int]]:
    """Each process's children, from ``/proc/<pid>/stat`` (field 4, the parent)."""
    out: dict[int, list[int]] = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        out.setdefault(int(fields[1]), []).append(int(stat.parent.name))
    return out


def _kill(proc: subprocess.Popen) -> None:
    """kill -9 of the whole run: the wrapper, Snakemake (in a process group of its own) and the jobs.

    Every process of the tree is stopped first (SIGSTOP: none starts another or notices the others
    go), until no new one appears, then all are killed at once."""
    stopped: set[int] = set()
    while True:
        tree, todo, found = _children(), [proc.pid], []
        while todo:
            pid = todo.pop()
            found.append(pid)
            todo += tree.get(pid, [])
        new = [p for p in found if p not in stopped]
        if not new:
            break
        for pid in new:
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGSTOP)
        stopped.update(new)
    for pid in stopped:
        with contextlib.suppress(ProcessLookupError):
            os.kill(pid, signal.SIGKILL)
    proc.wait()


def _same_numbers(a: Path, b: Path) -> None:
    count, diffs = compare(str(a / "results" / "isorock.h5"), str(b / "results" / "isorock.h5"))
    assert count > 50 and diffs == [], diffs[:10]


def _no_manual_step(text: str) -> None:
    for advice in ("snakemake --unlock", "cannot be locked", "Traceback", "IncompleteFilesException"):
        assert advice not in text, f"{advice!r} in:\n{text[-3000:]}"


#: Snakemake's progress line, written to the run's output as each of its steps (jobs) ends
STEPS = re.compile(r"^(\d+) of (\d+) steps \(\d+%\) done$", re.MULTILINE)
#: Snakemake's header of a job it starts (``localrule merge:``, ``rule regime_maps:``)
JOB = re.compile(r"^(?:local)?rule \w+:$", re.MULTILINE)


def _steps(text: str) -> tuple[int, int] | None:
    """The last progress line of a run's output, as (steps done, steps in all); None before any."""
    done = STEPS.findall(text)
    return (int(done[-1][0]), int(done[-1][1])) if done else None


@pytest.fixture(scope="module")
def reference(tmp_path_factory) -> dict:
    """The run that is never disturbed, and its number of Snakemake steps."""
    wd = _folder(tmp_path_factory.mktemp("reference"))
    res = _run(wd)
    assert res.returncode == 0, res.stderr[-4000:]
    last = _steps(res.stdout + res.stderr)
    assert last is not None and last[0] == last[1], f"no complete progress in:\n{res.stderr[-3000:]}"
    return {"dir": wd, "steps": last[1]}


def _copy(reference: dict, dst: Path) -> Path:
    shutil.copytree(reference["dir"], dst, symlinks=True)
    return dst


def _moments(n: int) -> list[int]:
    """The 5 moments of the kills of a run of ``n`` steps, as numbers of steps done (seeded, distinct):
    ``k`` in 0 .. n - 2, so that at least one job besides the final ``all`` is still to run; 0 is the
    moment the first job starts."""
    assert n - 1 >= N_KILLS, f"{n} steps: too few for {N_KILLS} distinct moments"
    return [int(k) for k in np.random.default_rng(SEED).choice(n - 1, N_KILLS, replace=False)]


def _reached(text: str, k: int) -> bool:
    """Whether a run's output shows the moment ``k``: k steps done (k = 0: a job started)."""
    if k == 0:
        return JOB.search(text) is not None
    last = _steps(text)
    return last is not None and last[0] >= k


@pytest.mark.parametrize("kill", range(N_KILLS), ids=[f"kill{i}" for i in range(N_KILLS)])
def test_kill_9_at_a_seeded_moment_then_the_same_command(reference, tmp_path, kill):
    """A run from an empty folder killed (-9, every process of it) at a seeded point of its progress;
    the same command then ends it, with the numbers of the run that was never disturbed."""
    wd = _folder(tmp_path / "killed")
    n = reference["steps"]
    k = _moments(n)[kill]
    moment = "its first job started" if k == 0 else f"{k} of {n} steps were done"
    log = tmp_path / "killed.log"
    proc = _start(wd, log)
    t0 = time.perf_counter()
    # the live log, read as it grows (a character half written at its end is no error)
    while proc.poll() is None and not _reached(log.read_text(errors="replace"), k):
        if time.perf_counter() - t0 > TIMEOUT:  # a hung run, not a slow machine
            _kill(proc)
            pytest.fail(f"no sign in {TIMEOUT} s that {moment}:\n{log.read_text()[-3000:]}")
        time.sleep(0.02)
    rc, last = proc.poll(), _steps(log.read_text(errors="replace"))
    ended = "before any step was done" if last is None else f"at {last[0]} of {last[1]} steps done"
    assert rc is None, (
        f"the run ended (exit code {rc}) {ended}, before the kill once {moment}:\n{log.read_text()[-3000:]}"
    )
    _kill(proc)
    _no_manual_step(log.read_text())
    again = _run(wd)
    text = again.stdout + again.stderr
    assert again.returncode == 0, text[-4000:]
    _no_manual_step(text)
    assert "another run" not in text
    if (
        tmp_path / "killed" / ".snakemake" / "metadata"
    ).exists() and "Select jobs to execute" in log.read_text():
        # Snakemake had locked the folder: the rerun says it cleared a dead run's lock
        assert "locked: lock cleared" in text, text[-3000:]
    _same_numbers(reference["dir"], wd)
    assert not (wd / ".snakemake" / "isorock-run.json").exists()


def _without_ignored_interrupts(text: str) -> str:
    """The output without the blocks Python prints when the SIGINT passed on to Snakemake lands inside a
    callback it cannot raise from (``Exception ignored in: <function WeakSet...._remove>`` ...
    ``KeyboardInterrupt``): the interpreter reports it, ignores it, and Snakemake goes on with its
    clean-up. Where the signal lands depends on the machine's load (CI once saw one); any other
    traceback, and a KeyboardInterrupt anywhere else, still fails the test."""
    return re.sub(
        r"Exception ignored in: [^\n]*\nTraceback \(most recent call last\):\n(?:[ \t][^\n]*\n|\n)*?"
        r"KeyboardInterrupt:?[^\n]*(?:\n|$)",
        "",
        text,
    )


#: how a run is stopped by a signal: to the wrapper alone (``kill PID``, ``timeout``), or to the
#: terminal's foreground process group (Ctrl-C; a closed terminal's SIGHUP)
SIGNALS = [("SIGTERM", "wrapper"), ("SIGINT", "group"), ("SIGHUP", "group")]


@pytest.mark.parametrize("name,to", SIGNALS, ids=[f"{n}-to-{t}" for n, t in SIGNALS])
def test_a_signal_ends_snakemake_and_its_jobs_then_the_same_command(reference, tmp_path, name, to):
    """SIGTERM to the wrapper (what ``kill PID`` and ``timeout`` send), SIGINT or SIGHUP to its process
    group (Ctrl-C, a closed terminal), at a seeded point of the run's progress: the wrapper ends with
    that signal's exit code and one line, no traceback; no Snakemake process nor job of the folder is
    left working (the review saw Snakemake go on in the background, and the next command told "another
    run"); the same command then ends the run with the numbers of the undisturbed one."""
    sig = getattr(signal, name)
    wd = _folder(tmp_path / "signalled")
    k = _moments(reference["steps"])[SIGNALS.index((name, to))] or 1
    log = tmp_path / "signalled.log"
    proc = _start(wd, log)
    t0 = time.perf_counter()
    while proc.poll() is None and not _reached(log.read_text(errors="replace"), k):
        if time.perf_counter() - t0 > TIMEOUT:
            break
        time.sleep(0.02)
    assert proc.poll() is None, f"the run ended before {k} steps were done:\n{log.read_text()[-3000:]}"
    if to == "group":
        os.killpg(proc.pid, sig)
    else:
        os.kill(proc.pid, sig)
    rc = proc.wait(timeout=TIMEOUT)
    text = log.read_text()
    assert rc == 128 + sig, f"exit code {rc}:\n{text[-3000:]}"
    assert f"isorock: stopped by {name}: snakemake run ended its jobs" in text, text[-3000:]
    for word in ("Traceback", "KeyboardInterrupt"):
        assert word not in _without_ignored_interrupts(text), text[-3000:]
    t0 = time.perf_counter()
    while _jobs_of(wd) and time.perf_counter() - t0 < TIMEOUT:  # only a hang fails here
        time.sleep(0.1)
    assert _jobs_of(wd) == [], "a Snakemake process or job of the folder goes on"
    for job_log in (wd / "logs").rglob("*.log"):
        assert "Traceback" not in job_log.read_text(), job_log
    again = _run(wd)
    out = again.stdout + again.stderr
    assert again.returncode == 0, out[-4000:]
    _no_manual_step(out)
    assert "another run" not in out
    _same_numbers(reference["dir"], wd)


def _jobs_of(folder: Path) -> list[int]:
    from isorock.control.runlock import live_snakemake

    return live_snakemake(folder)


def test_kill_9_of_snakemake_alone_leaves_jobs_that_are_waited_for(reference, tmp_path):
    """Snakemake killed alone (the out-of-memory killer's choice): its jobs go on; a run started while
    they work is told so, and once they have ended the same command finishes the run."""
    wd = _folder(tmp_path / "orphans")
    proc = _start(wd, tmp_path / "first.log")
    run_file = wd / ".snakemake" / "isorock-run.json"
    t0 = time.perf_counter()
    snakemake_pid = None
    while time.perf_counter() - t0 < 120 and proc.poll() is None:
        try:
            pids = json.loads(run_file.read_text())["snakemake"]
        except (OSError, ValueError, KeyError):
            pids = []
        if pids and any(p != pids[0][0] for p in _jobs_of(wd)):  # a job of it works
            snakemake_pid = pids[0][0]
            break
        time.sleep(0.02)
    assert snakemake_pid is not None, "no job started"
    os.kill(snakemake_pid, signal.SIGKILL)
    proc.wait(timeout=60)
    left = [p for p in _jobs_of(wd) if p != snakemake_pid]
    again = _run(wd)
    if left and all(Path(f"/proc/{p}").exists() for p in left):
        assert again.returncode == 2 and "another run (pid" in again.stderr, again.stderr[-2000:]
    t0 = time.perf_counter()
    while _jobs_of(wd) and time.perf_counter() - t0 < 120:
        time.sleep(0.1)
    final = _run(wd)
    assert final.returncode == 0, final.stderr[-4000:]
    _no_manual_step(final.stdout + final.stderr)
    _same_numbers(reference["dir"], wd)


def test_truncated_store_is_made_again(reference, tmp_path):
    wd = _copy(reference, tmp_path / "store")
    store = wd / "results" / "isorock.h5"
    os.truncate(store, 100_000)
    res = _run(wd)
    assert res.returncode == 0, res.stderr[-4000:]
    assert "results/isorock.h5 is damaged" in res.stderr and "made again" in res.stderr
    _same_numbers(reference["dir"], wd)
    report = wd / "report-tiny.html"
    assert report.stat().st_mtime >= store.stat().st_mtime


def test_truncated_and_empty_job_files_are_made_again(reference, tmp_path):
    wd = _copy(reference, tmp_path / "jobs")
    maps = sorted((wd / "results" / "jobs" / "maps").glob("*.h5"))
    overturn = sorted((wd / "results" / "jobs" / "overturn").glob("*.h5"))
    os.truncate(maps[0], maps[0].stat().st_size // 2)
    os.truncate(overturn[0], 0)
    res = _run(wd)
    assert res.returncode == 0, res.stderr[-4000:]
    assert res.stderr.count("is damaged") == 2, res.stderr
    for path in (maps[0], overturn[0]):
        with h5py.File(path, "r") as f:
            assert len(f.keys()) > 0
    _same_numbers(reference["dir"], wd)


def test_a_second_run_is_told_who_works_and_the_first_is_untouched(reference, tmp_path):
    wd = _copy(reference, tmp_path / "busy")
    # work for the first run: its maps, the store and everything after it
    shutil.rmtree(wd / "results")
    first = _start(wd, tmp_path / "first.log")
    try:
        run_file = wd / ".snakemake" / "isorock-run.json"
        t0 = time.perf_counter()
        while time.perf_counter() - t0 < 120 and first.poll() is None:
            try:
                if json.loads(run_file.read_text())["snakemake"]:
                    break
            except (OSError, ValueError, KeyError):
                pass
            time.sleep(0.05)
        assert first.poll() is None, "the first run ended before the second could start"
        second = _run(wd)
        assert second.returncode == 2
        errors = _errors(second.stderr)
        assert len(errors) == 1 and errors[0].startswith(
            f"isorock: error: another run (pid {first.pid}, since "
        )
        assert "wait for it or use another folder" in errors[0]
        assert first.wait(timeout=TIMEOUT) == 0, (tmp_path / "first.log").read_text()[-3000:]
    finally:
        if first.poll() is None:
            _kill(first)
    _same_numbers(reference["dir"], wd)


def _errors(stderr: str) -> list[str]:
    """The error lines of a command (the lines before them are its notes: the cost estimate ...)."""
    return [line for line in stderr.splitlines() if line.startswith("isorock: error:")]


def _mount(*args: str) -> None:
    res = subprocess.run(["mount", *args], capture_output=True, text=True)
    if res.returncode != 0:
        pytest.skip(f"cannot mount here ({res.stderr.strip()}): needs root with CAP_SYS_ADMIN")


def _umount(path: Path) -> None:
    subprocess.run(["umount", str(path)], check=False)


@pytest.mark.skipif(shutil.which("mount") is None or os.geteuid() != 0, reason="needs root and mount")
def test_read_only_results_is_one_line_then_the_run_resumes(reference, tmp_path):
    wd = _copy(reference, tmp_path / "ro")
    (wd / "results" / "isorock.h5").unlink()
    _mount("--bind", str(wd / "results"), str(wd / "results"))
    try:
        _mount("-o", "remount,bind,ro", str(wd / "results"))
        res = _run(wd)
    finally:
        _umount(wd / "results")
    assert res.returncode == 2
    errors = _errors(res.stderr)
    assert len(errors) == 1 and "results cannot be written" in errors[0] and "--directory DIR" in errors[0]
    assert "Traceback" not in res.stderr
    res = _run(wd)
    assert res.returncode == 0, res.stderr[-4000:]
    _same_numbers(reference["dir"], wd)


@pytest.mark.skipif(shutil.which("mount") is None or os.geteuid() != 0, reason="needs root and mount")
def test_full_disk_is_said_and_the_run_resumes_once_space_is_free(reference, tmp_path):
    wd = _folder(tmp_path / "full")
    results = wd / "results"
    results.mkdir()
    _mount("-t", "tmpfs", "-o", "size=1200k", "tmpfs", str(results))
    try:
        res = _run(wd)
        assert res.returncode == 2
        last = res.stderr.strip().splitlines()[-1]
        assert last.startswith("isorock: error: snakemake run failed") and "is full" in last, last
        _no_manual_step(last)
        subprocess.run(["mount", "-o", "remount,size=100m", str(results)], check=True)
        res = _run(wd)
        assert res.returncode == 0, res.stderr[-4000:]
        _same_numbers(reference["dir"], wd)
    finally:
        _umount(results)


def _first_float_dataset(h: h5py.File) -> str:
    """The path of a float dataset of a store (a number that trusting a stale store would show)."""
    found: list[str] = []

    def visit(name: str, obj) -> None:
        if not found and isinstance(obj, h5py.Dataset) and obj.dtype.kind == "f" and obj.size:
            found.append(name)

    h.visititems(visit)
    return found[0]


def test_a_foreign_hdf5_file_as_the_store_is_never_trusted(reference, tmp_path):
    """A valid HDF5 file of other content in place of results/isorock.h5: the same command removes it,
    says why in one line, and merges the store again (it once said the store would be replaced, and
    kept it)."""
    wd = _copy(reference, tmp_path / "foreign")
    store = wd / "results" / "isorock.h5"
    store.unlink()
    with h5py.File(store, "w") as h:
        h.create_dataset("x", data=np.arange(3.0))
    res = _run(wd)
    text = res.stdout + res.stderr
    assert res.returncode == 0, text[-4000:]
    assert "is no store of an isorock run (no configuration hash): removed" in text, text[-3000:]
    _no_manual_step(text)
    _same_numbers(reference["dir"], wd)


def test_the_store_of_another_configuration_is_made_again(reference, tmp_path):
    """A store whose configuration hash is another's (and one of its numbers changed): never trusted,
    the same command merges it again from this configuration's job files."""
    wd = _copy(reference, tmp_path / "other")
    store = wd / "results" / "isorock.h5"
    with h5py.File(store, "a") as h:
        h.attrs["config_hash"] = "0" * 16
        h.attrs["config_name"] = "other.yaml"
        d = h[_first_float_dataset(h)]
        d[(0,) * d.ndim] = d[(0,) * d.ndim] + 1.0
    res = _run(wd)
    text = res.stdout + res.stderr
    assert res.returncode == 0, text[-4000:]
    assert "holds the results of configuration 'other.yaml', not of this one: removed" in text, text[-3000:]
    _same_numbers(reference["dir"], wd)


def _no_home(tmp_path: Path) -> dict[str, str]:
    """An environment whose HOME cannot hold a cache folder: a file, not a folder (as a read-only or
    another user's HOME, for any user, root included), and no XDG_CACHE_HOME."""
    home = tmp_path / "home-is-a-file"
    home.write_text("")
    env = {k: v for k, v in os.environ.items() if k not in ("XDG_CACHE_HOME", "MPLCONFIGDIR")}
    return {**env, "HOME": str(home)}


def test_a_home_that_cannot_be_written_sends_the_caches_to_the_run_folder(reference, tmp_path):
    """HOME cannot be written: the run says in one line that its caches go to the run folder, and ends
    with the numbers of the reference (the review saw 40 lines of Snakemake's traceback, --dry-run
    included)."""
    wd = _folder(tmp_path / "nohome")
    env = _no_home(tmp_path)
    dry = subprocess.run([*_command(wd), "--dry-run"], cwd=wd, env=env, capture_output=True, text=True,
                         timeout=TIMEOUT)  # fmt: skip
    assert dry.returncode == 0, dry.stderr[-3000:]
    res = subprocess.run(_command(wd), cwd=wd, env=env, capture_output=True, text=True, timeout=TIMEOUT)
    text = res.stdout + res.stderr
    assert res.returncode == 0, text[-4000:]
    assert "Traceback" not in text
    line = f"(HOME={env['HOME']}) cannot be written (Not a directory): this run's caches go to"
    assert line in res.stderr and str(wd / ".snakemake" / "cache") in res.stderr, res.stderr[-3000:]
    _same_numbers(reference["dir"], wd)


def test_no_cache_folder_anywhere_is_one_line_naming_home(tmp_path):
    """Neither HOME nor the run folder can hold the caches: one line naming HOME, exit code 2."""
    wd = _folder(tmp_path / "nowhere")
    (wd / ".snakemake").mkdir()
    (wd / ".snakemake" / "cache").write_text("")  # a file where the run's cache folder would go
    res = subprocess.run([*_command(wd), "--dry-run"], cwd=wd, env=_no_home(tmp_path), capture_output=True,
                         text=True, timeout=TIMEOUT)  # fmt: skip
    assert res.returncode == 2, res.stderr[-3000:]
    assert "Traceback" not in res.stderr
    errors = _errors(res.stderr)
    assert len(errors) == 1 and errors[0].startswith("isorock: error: the cache folder"), res.stderr
    assert "set HOME or XDG_CACHE_HOME" in errors[0]
