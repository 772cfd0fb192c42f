"""Who runs in a working directory (isorock.control.runlock) and which outputs are damaged
(isorock.control.integrity): real processes, real lock files, real HDF5 files; no workflow run (the
runs under faults are the second stage, tests/faults)."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

from isorock.control import integrity, runlock
from isorock.control.run import RunSettings, run_snakemake
from isorock.errors import IsorockError


def _locked(d: Path) -> None:
    (d / ".snakemake" / "locks").mkdir(parents=True)
    for name in ("0.input.lock", "0.output.lock"):
        (d / ".snakemake" / "locks" / name).write_text("results/isorock.h5\n")


def _run_file(d: Path, **kw) -> None:
    data = {
        "pid": 1,
        "host": socket.gethostname(),
        "started": "2026-11-26T10:00:00",
        "command": "isorock report",
    }
    data.update(kw)
    (d / ".snakemake").mkdir(exist_ok=True)
    (d / runlock.RUN_FILE).write_text(json.dumps(data))


@pytest.fixture
def sleeper():
    proc = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    yield proc
    proc.kill()
    proc.wait()


def test_a_live_run_is_named_and_its_lock_kept(tmp_path, sleeper):
    _locked(tmp_path)
    _run_file(tmp_path, pid=sleeper.pid, ticks=runlock._start_ticks(sleeper.pid))
    with pytest.raises(IsorockError) as e:
        runlock.claim(tmp_path, "isorock report", print)
    msg = str(e.value)
    assert msg.startswith(
        f"another run (pid {sleeper.pid}, since 2026-11-26 10:00:00) is working in this folder"
    )
    assert msg.endswith("wait for it or use another folder (--directory DIR)")
    assert len(list((tmp_path / ".snakemake" / "locks").iterdir())) == 2


def test_a_live_snakemake_of_the_run_counts_when_its_wrapper_is_gone(tmp_path, sleeper):
    _run_file(tmp_path, pid=2**22 + 7, snakemake=[[sleeper.pid, runlock._start_ticks(sleeper.pid)]])
    with pytest.raises(IsorockError, match=f"another run \\(pid {sleeper.pid}, "):
        runlock.claim(tmp_path, "isorock report", print)


def test_a_dead_run_lock_is_cleared_in_one_line(tmp_path):
    _locked(tmp_path)
    _run_file(tmp_path, pid=2**22 + 7)
    lines: list[str] = []
    run = runlock.claim(tmp_path, "isorock report", lines.append)
    assert lines == [
        f"isorock: a run that stopped before finishing (pid {2**22 + 7}, since 2026-11-26 10:00:00) left "
        f"{tmp_path.resolve()} locked: lock cleared, its unfinished jobs run again"
    ]
    assert not list((tmp_path / ".snakemake" / "locks").iterdir())
    assert json.loads((tmp_path / runlock.RUN_FILE).read_text())["pid"] == os.getpid()
    runlock.release(tmp_path, run)
    assert not (tmp_path / runlock.RUN_FILE).exists()


def test_a_reused_process_id_is_not_the_run(tmp_path, sleeper):
    """The run file's pid now belongs to a process started at another time: the run is dead."""
    _locked(tmp_path)
    _run_file(tmp_path, pid=sleeper.pid, ticks=runlock._start_ticks(sleeper.pid) - 1)
    lines: list[str] = []
    runlock.release(tmp_path, runlock.claim(tmp_path, "isorock report", lines.append))
    assert len(lines) == 1 and "lock cleared" in lines[0]


def test_a_killed_process_not_yet_reaped_is_dead(tmp_path):
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    ticks = runlock._start_ticks(proc.pid)
    os.waitid(os.P_PID, proc.pid, os.WEXITED | os.WNOWAIT)  # exited; still a zombie until waited for
    try:
        assert runlock._stat(proc.pid)[0] == "Z"
        _locked(tmp_path)
        _run_file(tmp_path, pid=proc.pid, ticks=ticks)
        lines: list[str] = []
        runlock.release(tmp_path, runlock.claim(tmp_path, "isorock report", lines.append))
        assert "lock cleared" in lines[0]
    finally:
        proc.wait()


def test_a_lock_without_run_file_is_stale_when_no_snakemake_works_here(tmp_path):
    _locked(tmp_path)
    lines: list[str] = []
    runlock.release(tmp_path, runlock.claim(tmp_path, "isorock report", lines.append))
    assert lines == [
        f"isorock: a run that stopped before finishing left {tmp_path.resolve()} locked: lock cleared, "
        "its unfinished jobs run again"
    ]


def test_a_report_only_run_clears_the_lock_without_promising_jobs(tmp_path):
    _locked(tmp_path)
    lines: list[str] = []
    runlock.release(tmp_path, runlock.claim(tmp_path, "isorock report", lines.append, run_jobs=False))
    assert lines[0].endswith("locked: lock cleared")


def _seen(folder: Path) -> list[int]:
    """What live_snakemake finds in ``folder`` once a process just started there shows (5 s at most)."""
    for _ in range(250):
        if runlock.live_snakemake(folder):
            break
        time.sleep(0.02)
    return runlock.live_snakemake(folder)


def test_a_snakemake_started_by_hand_in_the_folder_is_a_live_run(tmp_path):
    proc = subprocess.Popen(["bash", "-c", "exec -a snakemake sleep 60"], cwd=tmp_path)
    try:
        assert _seen(tmp_path) == [proc.pid]  # once exec has replaced bash
        with pytest.raises(IsorockError, match=f"another run \\(pid {proc.pid}, since an unknown time\\)"):
            runlock.claim(tmp_path, "isorock report", print)
        assert runlock.live_snakemake(tmp_path / "..") == []
    finally:
        proc.kill()
        proc.wait()


def test_a_run_of_another_host_cannot_be_checked_and_says_what_to_remove(tmp_path):
    _run_file(tmp_path, host="login2.cluster", pid=4242)
    with pytest.raises(IsorockError) as e:
        runlock.claim(tmp_path, "isorock report", print)
    assert "pid 4242 on host login2.cluster" in str(e.value)
    assert f"rm {tmp_path.resolve() / runlock.RUN_FILE}" in str(e.value)


def test_a_damaged_run_file_is_not_trusted(tmp_path):
    (tmp_path / ".snakemake").mkdir()
    (tmp_path / runlock.RUN_FILE).write_text('{"pid": 12')  # killed while writing (never: it is atomic)
    runlock.release(tmp_path, runlock.claim(tmp_path, "isorock report", print))


# ============================================================================= damaged outputs
def _h5(path: Path) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    with h5py.File(path, "w") as f:
        f["x"] = np.arange(5000.0)
    return path


def test_damaged_finds_truncated_and_empty_files_only(tmp_path):
    good = _h5(tmp_path / "results" / "jobs" / "maps" / "A.h5")
    cut = _h5(tmp_path / "results" / "isorock.h5")
    os.truncate(cut, cut.stat().st_size // 2)
    empty = tmp_path / "results" / "report" / "maps.csv"
    empty.parent.mkdir(parents=True)
    empty.write_text("")
    (tmp_path / "results" / "jobs" / "maps" / ".B.h5.1234.tmp").write_text("")  # a job's temporary file
    (tmp_path / "results" / "benchmarks").mkdir()
    (tmp_path / "results" / "benchmarks" / "x.tsv").write_text("")
    found = dict(integrity.damaged(tmp_path))
    assert set(found) == {cut, empty}
    assert "truncated" in found[cut] and found[empty] == "empty"
    assert good not in found


def test_a_damaged_file_of_a_whole_folder_removes_the_folder(tmp_path):
    figs = tmp_path / "results" / "figures"
    figs.mkdir(parents=True)
    (figs / "fig04.png").write_bytes(b"")
    (figs / "fig05.png").write_bytes(b"\x89PNG")
    store = _h5(tmp_path / "results" / "isorock.h5")
    store.write_bytes(b"")
    lines: list[str] = []
    removed = integrity.remove_damaged(tmp_path, lines.append)
    assert removed == [figs, store] and not figs.exists() and not store.exists()
    assert lines == [
        "isorock: results/figures/fig04.png is damaged (empty): removed, it is made again",
        "isorock: results/isorock.h5 is damaged (empty): removed, it is made again",
    ]


def test_run_command_reruns_incomplete_jobs(tmp_path):
    s = RunSettings(snakefile=tmp_path / "Snakefile", directory=tmp_path, configfile=tmp_path / "c.yaml",
                    report=tmp_path / "report.html", cores=2)  # fmt: skip
    assert "--rerun-incomplete" in s.run_cmd() and "-n" not in s.run_cmd()
    assert "-n" in s.run_cmd(dry_run=True)


def test_a_damaged_job_file_has_the_store_merged_again(tmp_path):
    job = _h5(tmp_path / "results" / "jobs" / "maps" / "A.h5")
    store = _h5(tmp_path / "results" / "isorock.h5")
    os.truncate(job, 100)
    lines: list[str] = []
    assert integrity.remove_damaged(tmp_path, lines.append) == [job, store]
    assert lines[1] == "isorock: results/isorock.h5 is merged again, with the job file made again"


def test_a_file_held_open_by_another_program_is_no_damage(tmp_path):
    store = _h5(tmp_path / "results" / "isorock.h5")
    code = f"import h5py, time; f = h5py.File({str(store)!r}, 'a'); print(1, flush=True); time.sleep(30)"
    holder = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "1"
        assert integrity.damaged(tmp_path) == []
    finally:
        holder.kill()
        holder.wait()


def test_an_empty_file_of_the_users_own_is_left(tmp_path):
    (tmp_path / "results").mkdir()
    (tmp_path / "results" / "notes.txt").write_text("")
    assert integrity.damaged(tmp_path) == []


def test_two_runs_claiming_at_once_cannot_both_pass(tmp_path):
    first = runlock.claim(tmp_path, "isorock report", print)
    try:
        # the run file says nothing alive (its pid is ours, but a second claim from another process
        # would see the lock held): what matters is the lock
        code = (
            "import sys; from pathlib import Path; from isorock.control import runlock; "
            f"runlock.claim(Path({str(tmp_path)!r}), 'isorock report', print)"
        )
        res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
        assert res.returncode != 0 and "another run (pid" in res.stderr
    finally:
        runlock.release(tmp_path, first)
    second = runlock.claim(tmp_path, "isorock report", print)  # the lock was let go
    runlock.release(tmp_path, second)


def test_a_job_left_working_by_a_killed_snakemake_is_a_live_run(tmp_path):
    scripts = tmp_path / ".snakemake" / "scripts"
    scripts.mkdir(parents=True)
    (scripts / "tmpabc.regime_maps.py").write_text("import time; time.sleep(60)")
    proc = subprocess.Popen([sys.executable, ".snakemake/scripts/tmpabc.regime_maps.py"], cwd=tmp_path)
    try:
        assert _seen(tmp_path) == [proc.pid]
        with pytest.raises(IsorockError, match=f"another run \\(pid {proc.pid}, "):
            runlock.claim(tmp_path, "isorock report", print)
    finally:
        proc.kill()
        proc.wait()


def test_a_failed_snakemake_names_no_unlock_and_says_the_report_is_older(tmp_path):
    store = _h5(tmp_path / "results" / "isorock.h5")
    report = tmp_path / "report.html"
    report.write_text("<html>")
    os.utime(report, (store.stat().st_mtime - 60,) * 2)
    s = RunSettings(snakefile=tmp_path / "Snakefile", directory=tmp_path, configfile=tmp_path / "c.yaml",
                    report=report)  # fmt: skip
    with pytest.raises(IsorockError) as e:
        run_snakemake([sys.executable, "-c", "raise SystemExit(1)"], "run", after=s.stale_report)
    msg = str(e.value)
    assert "unlock" not in msg and "the same command resumes" in msg
    assert msg.endswith(f"report.html is older than {store}: it shows an earlier run")
