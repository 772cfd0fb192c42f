"""Ordinary and extreme inputs end as they should (issue 32): the report is written for whatever the
runs produced, a record too long or a name too large is one line before any job, a configuration that
gives no advice is refused, and a store whose job file was deleted or whose record file changed is
made again, with the numbers of a run never disturbed.

Second stage (``pytest -m e2e``): each test runs ``isorock report`` (or ``assess``) as a user does, on
the tiny grids of ``tests/pipeline/test_workflow.py`` and records of its own (synthetic, added with
``isorock records add``).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
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

TIMEOUT = 600
CLI = [sys.executable, "-m", "isorock.cli"]


def _record(path: Path, pga_g: float, seconds: float = 30.0, dt: float = 0.01) -> Path:
    """A one-column record [g]: a 1 Hz wave packet of peak ``pga_g`` lasting ``seconds``."""
    t = np.arange(int(round(seconds / dt)) + 1) * dt
    a = np.sin(2 * np.pi * t) * np.exp(-(((t - 0.3 * seconds) / (0.15 * seconds)) ** 2))
    np.savetxt(path, a / np.abs(a).max() * pga_g, fmt="%.7e")
    return path


def _cli(args: list[str], cwd: Path, timeout: float = TIMEOUT) -> subprocess.CompletedProcess:
    return subprocess.run([*CLI, *args], cwd=cwd, capture_output=True, text=True, timeout=timeout)


def _one_line(res: subprocess.CompletedProcess) -> str:
    assert res.returncode == 2, res.stderr[-3000:]
    assert "Traceback" not in res.stderr
    errors = [line for line in res.stderr.splitlines() if line.startswith("isorock: error:")]
    assert len(errors) == 1, res.stderr[-3000:]
    return errors[0]


def _folder(tmp_path: Path, pga_g: float, R_m: list[float] | None = None, **records) -> Path:
    """A run folder whose records are one added record of peak ``pga_g`` (``R_m``: the blocks of the
    minimum-overturning study; ``records``: more keys of the configuration's records section); the
    configuration is ``tiny.yaml``."""
    wd = tmp_path / "run"
    wd.mkdir()
    src = _record(tmp_path / "mine.txt", pga_g)
    res = _cli(["records", "add", str(src), "--dt", "0.01", "--units", "g", "--records", "records"], wd)
    assert res.returncode == 0, res.stderr[-3000:]
    cfg = tiny_config(wd / "records", [])
    cfg["records"] = {"dir": "records", "include": ["added"], "choose": "table1_pgv", **records}
    cfg["maps"]["amplitude"] = "record"
    cfg["pulses"]["enabled"] = False  # the pulse studies do not depend on the records: not needed here
    if R_m is not None:
        cfg["overturn"]["R_m"] = R_m
    (wd / "tiny.yaml").write_text(yaml.safe_dump(cfg))
    return wd


def _report(wd: Path) -> subprocess.CompletedProcess:
    return _cli(["report", "--configfile", "tiny.yaml", "--cores", "2"], wd)


# --------------------------------------------------------------------------- item 3: the report
@pytest.mark.parametrize(
    "pga_g, R_m, what",
    [
        (0.35, [1.0, 5.0], "the R = 5 m block never overturns"),
        (0.008, [1.0, 5.0], "nothing uplifts"),
        (3.0, [1.0, 5.0], "every block overturns"),
        (0.35, [1.0, 40.0], "a block larger than every map's grid"),
    ],
    ids=["review", "no-uplift", "all-overturn", "beyond-the-grid"],
)
def test_the_report_is_written_for_whatever_one_record_produced(tmp_path, pga_g, R_m, what):
    """One added 30 s record and overturn.R_m [1, 5] (the review's reproduction: ``KeyError: 5.0`` in
    the landing page on every run), and the same with a record too weak to uplift anything, one that
    overturns every block, and a block larger than the maps' grids (R 40 m; they end at 9 m)."""
    wd = _folder(tmp_path, pga_g, R_m=R_m)
    res = _report(wd)
    text = res.stdout + res.stderr
    assert res.returncode == 0, f"{what}:\n{text[-4000:]}"
    assert "Traceback" not in text
    report = wd / "report-tiny.html"
    assert report.is_file() and report.stat().st_size > 10_000
    html = report.read_text(errors="replace")
    assert "Minimum overturning" in html or "minimum overturning" in html


# --------------------------------------------------------------------------- item 6: record length
def test_a_record_too_long_is_one_line_before_any_job_and_runs_when_allowed(tmp_path):
    """A 700 s record: ``records add`` refuses it in one line; added with --max-duration, a run refuses
    it before any job (naming the configuration's keys), and with records.max_duration_s raised it
    runs, its duration counted in the estimate."""
    wd = tmp_path / "run"
    wd.mkdir()
    src = _record(tmp_path / "long.txt", 0.3, seconds=700.0)
    add = ["records", "add", str(src), "--dt", "0.01", "--units", "g", "--records", "records"]
    line = _one_line(_cli(add, wd))
    assert "70,001 samples over 700.0 s, longer than isorock analyses unless asked" in line
    assert _cli([*add, "--max-duration", "800"], wd).returncode == 0
    cfg = tiny_config(wd / "records", [])
    cfg["records"] = {"dir": "records", "include": ["added"], "choose": "table1_pgv"}
    (wd / "tiny.yaml").write_text(yaml.safe_dump(cfg))
    dry = ["report", "--configfile", "tiny.yaml", "--cores", "2", "--dry-run"]
    line = _one_line(_cli(dry, wd))
    assert "raise records.max_samples / records.max_duration_s of the configuration" in line
    assert not (wd / "results").exists()
    cfg["records"]["max_duration_s"] = 800
    (wd / "tiny.yaml").write_text(yaml.safe_dump(cfg))
    res = _cli(dry, wd)
    assert res.returncode == 0, res.stderr[-3000:]
    assert "on 1 record(s) of 700 s (700 s of record in all)" in res.stderr, res.stderr[-3000:]


def test_a_file_far_too_large_is_refused_unread(tmp_path):
    """A 10-million-sample file (the review's 50,000 s record took 2.1 GB to add): refused in one line
    before it is read."""
    big = tmp_path / "huge.txt"
    with open(big, "wb") as fh:
        for _ in range(100):
            fh.write(b"1.0000000e-01\n" * 100_000)
    res = subprocess.run(
        [*CLI, "records", "add", str(big), "--dt", "0.005", "--units", "g", "--records", str(tmp_path / "r")],
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
    )
    assert "more than a record of at most 200,000 samples takes (not read;" in _one_line(res)
    assert not (tmp_path / "r" / "huge.txt").exists()


def test_a_long_record_allowed_declares_the_memory_it_needs(tmp_path):
    """A record of 600,001 samples allowed by the configuration: its processing job declares more than
    the 1 GB floor (about 1.1 kB a sample was measured), and the estimate says so."""
    wd = tmp_path / "run"
    wd.mkdir()
    src = _record(tmp_path / "dense.txt", 0.3, seconds=300.0, dt=0.0005)  # 600,001 samples, 8.6 MB
    res = _cli(["records", "add", str(src), "--dt", "0.0005", "--units", "g", "--records", "records",
                "--max-samples", "2000000"], wd)  # fmt: skip
    assert res.returncode == 0, res.stderr[-3000:]
    cfg = tiny_config(wd / "records", [])
    cfg["records"] = {"dir": "records", "include": ["added"], "choose": "table1_pgv"}
    cfg["records"]["max_samples"] = 2_000_000
    (wd / "tiny.yaml").write_text(yaml.safe_dump(cfg))
    res = _cli(["report", "--configfile", "tiny.yaml", "--cores", "2", "--dry-run"], wd)
    assert res.returncode == 0, res.stderr[-3000:]
    from isorock.control.memory import job_memory_mb

    need = job_memory_mb("process_record", src.stat().st_size / 2**20)
    assert need > 600_001 * 1.07e3 / 2**20 and need > 1000
    assert f"its record jobs declare up to {need:,} MB of memory each" in res.stderr, res.stderr[-2000:]
    # Snakemake's plan of the processing job (one batch of records: rule process_record_p0) declares it
    job = res.stdout[res.stdout.index("rule process_record_p0:") :]
    assert f"mem_mb={need}," in job.split("\n\n")[0], job[:2000]


# --------------------------------------------------------------------------- item 7: a huge name
def _assessment(**a) -> dict:
    """The README's object file (one object on the fixed base), with ``a`` changed."""
    return {
        "isolation": {"rho": 0.5, "cases": [{"name": "none", "kind": "none"}]},
        "assessment": {"objects": [{"name": "statue", "height_m": 1.8, "width_m": 0.5, "friction": 0.5}],
                       "cases": ["none"], "stripes_g": [0.1, 0.2, 0.3, 0.4, 0.5, 0.6], "design_g": [0.3],
                       "mce_g": [0.45], **a},
    }  # fmt: skip


def test_a_huge_object_name_is_one_line_at_once(tmp_path):
    """A 10 MB object name once passed the checks and hung ``assess --dry-run`` in "Building DAG of
    jobs" for over 10 minutes."""
    obj = tmp_path / "obj.yaml"
    huge = {"name": "x" * 10_000_000, "height_m": 1.8, "width_m": 0.6, "friction": 0.5}
    obj.write_text(yaml.safe_dump(_assessment(objects=[huge])))
    line = _one_line(_cli(["assess", str(obj), "--dry-run"], tmp_path, timeout=300))
    assert "assessment.objects.0.name" in line and len(line) < 400, line[:400]


# --------------------------------------------------------------------------- item 9
@pytest.mark.parametrize(
    "change, words",
    [
        ({"bootstrap": 0}, "assessment.bootstrap: 0 is out of range: must be >= 100"),
        ({"design_g": []}, "assessment names no design level"),
    ],
    ids=["bootstrap-0", "no-design-level"],
)
def test_an_assessment_that_cannot_advise_is_refused(tmp_path, change, words):
    obj = tmp_path / "obj.yaml"
    obj.write_text(yaml.safe_dump(_assessment(**change)))
    line = _one_line(_cli(["assess", str(obj), "--dry-run"], tmp_path, timeout=300))
    assert words in line, line


def _same_numbers(a: Path, b: Path) -> None:
    count, diffs = compare(str(a), str(b))
    assert count > 20 and diffs == [], diffs[:10]


def test_a_deleted_job_file_is_made_again(tmp_path):
    """A job file deleted after a complete run (the review: not rebuilt): the same command says so in
    one line, makes it again and merges the store again, with the numbers of the first run."""
    wd = _folder(tmp_path, 0.35)
    assert _report(wd).returncode == 0
    first = tmp_path / "first.h5"
    shutil.copy2(wd / "results" / "isorock.h5", first)
    gone = sorted((wd / "results" / "jobs" / "maps").glob("*.h5"))[0]
    gone.unlink()
    res = _report(wd)
    assert res.returncode == 0, res.stderr[-4000:]
    assert f"was merged from {gone}, deleted since: removed" in res.stderr, res.stderr[-3000:]
    assert gone.is_file()
    _same_numbers(first, wd / "results" / "isorock.h5")


def test_a_record_file_changed_in_place_is_analysed_again(tmp_path):
    """The record file replaced by another of an older time stamp (Snakemake sees no change): the store
    records the file's sha256, so the same command analyses the new record; changed back, the numbers
    are the first run's again."""
    wd = _folder(tmp_path, 0.35)
    assert _report(wd).returncode == 0
    first = tmp_path / "first.h5"
    shutil.copy2(wd / "results" / "isorock.h5", first)
    rec = wd / "records" / "mine.txt"
    original, stamp = rec.read_bytes(), rec.stat()
    _record(rec, 0.5)
    os.utime(rec, ns=(stamp.st_atime_ns, stamp.st_mtime_ns - 10**9))
    res = _report(wd)
    assert res.returncode == 0, res.stderr[-4000:]
    assert "was made from the record file" in res.stderr and "changed since: removed" in res.stderr
    with h5py.File(wd / "results" / "isorock.h5", "r") as f:
        assert f["records/mine"].attrs["pga_g"] == pytest.approx(0.5, rel=0.05)
    rec.write_bytes(original)
    os.utime(rec, ns=(stamp.st_atime_ns, stamp.st_mtime_ns - 2 * 10**9))
    res = _report(wd)
    assert res.returncode == 0, res.stderr[-4000:]
    _same_numbers(first, wd / "results" / "isorock.h5")
