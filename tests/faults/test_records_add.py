"""``isorock records add`` is one transaction: additions to one folder at the same time lose no row,
an addition waits for another, and an addition killed at any moment is finished by the same command.

Second stage (``pytest -m e2e``): each test runs ``isorock records add`` as separate processes. The
reference is an addition never disturbed; every other addition must end with the same manifest (the
same rows, apart from their order) and the same files.

The moments of the kills are points of the addition's own progress (the number of files it has copied
into the folder, seeded), never times; where an addition ends before its moment (a fast machine), the
test still checks that the same command completes it.
"""

from __future__ import annotations

import csv
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from isorock.store.atomic import file_sha256, try_lock

pytestmark = pytest.mark.e2e

SEED = 20261129
TIMEOUT = 300
N_FILES = 40


def _at2(path: Path, seed: int, n: int = 3000, dt: float = 0.01) -> Path:
    """A PEER AT2 file of a synthetic record (a decaying sine of its own frequency and peak) [g]."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * dt
    a = (0.1 + 0.3 * rng.random()) * np.sin(2 * np.pi * (0.5 + rng.random()) * t) * np.exp(-0.2 * t)
    a *= np.minimum(t, 1.0)
    head = (
        "PEER NGA STRONG MOTION DATABASE RECORD\n"
        f"Synthetic {seed}, 1/1/2000, Station {seed}, 090\n"
        "ACCELERATION TIME SERIES IN UNITS OF G\n"
        f"NPTS= {n:6d}, DT= {dt:8.4f} SEC,\n"
    )
    body = "".join("".join(f"{x:15.7E}" for x in a[i : i + 5]) + "\n" for i in range(0, n, 5))
    path.write_text(head + body)
    return path


def _files(folder: Path, prefix: str, n: int = N_FILES, seed0: int = 0) -> list[Path]:
    folder.mkdir(parents=True, exist_ok=True)
    return [_at2(folder / f"{prefix}{i:03d}.AT2", seed0 + i) for i in range(n)]


def _command(files: list[Path], records: Path) -> list[str]:
    cli = [sys.executable, "-m", "isorock.cli"]
    return [*cli, "records", "add", *map(str, files), "--records", str(records)]


def _add(files: list[Path], records: Path) -> subprocess.CompletedProcess:
    return subprocess.run(_command(files, records), capture_output=True, text=True, timeout=TIMEOUT)


def _start(files: list[Path], records: Path) -> subprocess.Popen:
    return subprocess.Popen(
        _command(files, records),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )


def _rows(records: Path) -> dict[str, dict[str, str]]:
    """The manifest's rows by file name (its line numbers are not compared)."""
    with open(records / "manifest.csv", newline="", encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    by_file = {r["file"]: r for r in rows}
    assert len(by_file) == len(rows), "a file is listed twice"
    return by_file


def _same_folder(reference: Path, records: Path) -> None:
    """The same manifest rows and the same files (by sha256), no temporary file left."""
    assert _rows(records) == _rows(reference)
    left = sorted(p.name for p in records.iterdir() if p.name.endswith(".tmp"))
    assert left == []
    for name, row in _rows(records).items():
        assert file_sha256(records / name) == row["sha256"]


def _no_traceback(res: subprocess.CompletedProcess) -> None:
    assert "Traceback" not in res.stdout + res.stderr, res.stderr[-3000:]


@pytest.fixture(scope="module")
def sources(tmp_path_factory) -> dict:
    """The two sets of files to add and the folder of an addition of both never disturbed."""
    base = tmp_path_factory.mktemp("sources")
    a, b = _files(base / "a", "ra"), _files(base / "b", "rb", seed0=1000)
    reference = base / "reference"
    for files in (a, b):
        res = _add(files, reference)
        assert res.returncode == 0, res.stderr[-3000:]
    assert len(_rows(reference)) == 2 * N_FILES
    return {"a": a, "b": b, "reference": reference}


@pytest.mark.parametrize("attempt", range(3))
def test_two_additions_at_once_lose_no_row(sources, tmp_path, attempt):
    """40 + 40 files added to one folder by two commands started together: 80 rows (the review saw
    40 or 50 when nothing locked the manifest)."""
    records = tmp_path / "records"
    first, second = _start(sources["a"], records), _start(sources["b"], records)
    outs = [p.communicate(timeout=TIMEOUT) for p in (first, second)]
    for p, (out, err) in zip((first, second), outs, strict=True):
        assert p.returncode == 0, err[-3000:]
        assert "Traceback" not in out + err
    _same_folder(sources["reference"], records)


def test_an_addition_waits_for_the_one_that_holds_the_folder(sources, tmp_path):
    """While another addition holds the folder's lock, an addition says that it waits and changes
    nothing; once the lock goes, it completes."""
    from isorock.records.adding import MANIFEST_LOCK

    records = tmp_path / "records"
    records.mkdir()
    fd = try_lock(records / MANIFEST_LOCK)
    assert fd is not None
    try:
        proc = _start(sources["a"][:3], records)
        assert proc.stderr is not None
        line = proc.stderr.readline()  # blocks until the addition says something (or ends)
        assert "another 'records add' is writing" in line and "waiting for it" in line, line
        assert proc.poll() is None
        assert not (records / "manifest.csv").exists()
    finally:
        os.close(fd)
    out, err = proc.communicate(timeout=TIMEOUT)
    assert proc.returncode == 0, err[-3000:]
    assert len(_rows(records)) == 3


def test_an_addition_killed_before_its_manifest_is_finished_by_the_same_command(sources, tmp_path):
    """What an addition killed while copying leaves (the review's reproduction): 18 of its files in the
    folder but not in the manifest, and a temporary copy of the 19th. The same command registers the
    files that are there (identical files are no conflict), copies the rest, and removes the leftover."""
    records = tmp_path / "records"
    res = _add(sources["a"], records)
    assert res.returncode == 0, res.stderr[-3000:]
    b = sources["b"]
    for f in b[:18]:
        shutil.copy2(f, records / f.name)
    (records / f".{b[18].name}.k3x9_q2a.tmp").write_bytes(b[18].read_bytes()[:5000])
    again = _add(b, records)
    assert again.returncode == 0, again.stderr[-3000:]
    _no_traceback(again)
    assert "removed 1 unfinished copy left by an addition that was stopped" in again.stdout
    _same_folder(sources["reference"], records)


def _moments(n: int, k: int = 4) -> list[int]:
    """The seeded moments of the kills: numbers of files copied (1 .. n - 1)."""
    return sorted(int(x) + 1 for x in np.random.default_rng(SEED).choice(n - 1, k, replace=False))


def _copied(records: Path, names: set[str]) -> int:
    try:
        return sum(1 for p in records.iterdir() if p.name in names)
    except FileNotFoundError:
        return 0


@pytest.mark.parametrize("kill", range(4), ids=[f"kill{i}" for i in range(4)])
def test_kill_9_during_an_addition_then_the_same_command(sources, tmp_path, kill):
    """An addition killed (-9) once a seeded number of its files is in the folder; the same command
    then completes it, with the folder of the addition never disturbed."""
    records = tmp_path / "records"
    res = _add(sources["a"], records)
    assert res.returncode == 0, res.stderr[-3000:]
    b = sources["b"]
    k = _moments(len(b))[kill]
    names = {f.name for f in b}
    proc = _start(b, records)
    t0 = time.perf_counter()
    while proc.poll() is None and _copied(records, names) < k:
        if time.perf_counter() - t0 > TIMEOUT:  # a hung addition, not a slow machine
            break
        time.sleep(0.0005)
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    proc.communicate()
    again = _add(b, records)
    assert again.returncode == 0, again.stderr[-3000:]
    _no_traceback(again)
    _same_folder(sources["reference"], records)
