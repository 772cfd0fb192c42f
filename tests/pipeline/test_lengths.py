"""The bounds on a record's length, the memory its jobs declare and the durations the cost estimate
counts (issue 32 item 6: a 50,000 s record was accepted, its job peaked at 9.9 GB while declaring
1 GB, and the estimate said "< 1 min")."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

import isorock.records.directory as recs
from isorock.control import cost
from isorock.control.lengths import LENGTHS_FILE, keep_lengths, read_lengths, record_lengths
from isorock.control.memory import BASE_MB, FLOOR_MB, PER_INPUT_MB, job_memory_mb
from isorock.errors import IsorockError
from isorock.pipeline import load_config, plan
from isorock.records.adding import add_records
from isorock.resources import config_schema


def _text(path: Path, n: int) -> Path:
    t = np.arange(n) * 0.01
    np.savetxt(path, 0.2 * np.sin(2 * np.pi * t) * np.exp(-t / (0.3 * t[-1])) + 1e-3, fmt="%.6e")
    return path


def _records(tmp_path: Path, lengths: dict[str, int]) -> Path:
    folder = tmp_path / "records"
    for name, n in lengths.items():
        src = _text(tmp_path / f"{name}.txt", n)
        add_records([src], folder, dt=0.01, units="g", max_samples=10**7, max_duration_s=1e6)
    return folder


def _config(folder: Path, **limits) -> dict:
    return load_config({"records": {"dir": str(folder), "include": ["added"], **limits}})


def test_the_schema_defaults_are_the_bounds_of_the_readers():
    props = yaml.safe_load(config_schema().read_text())["properties"]["records"]["properties"]
    assert props["max_samples"]["default"] == recs.MAX_SAMPLES
    assert props["max_duration_s"]["default"] == recs.MAX_DURATION_S


def test_a_record_longer_than_the_bounds_is_one_line_before_any_job(tmp_path):
    folder = _records(tmp_path, {"short": 3000, "long": 70_001})  # 30 s and 700 s
    cfg = _config(folder)
    with pytest.raises(IsorockError) as exc:
        record_lengths(plan(cfg).records, cfg)
    msg = str(exc.value)
    assert (
        "\n" not in msg and msg.startswith("record long: ") and "long.txt: 70,001 samples over 700.0 s" in msg
    )
    assert "at most 200,000 samples and 600 s; raise records.max_samples / records.max_duration_s" in msg
    # raised bounds let it run, and its length is what was written
    cfg = _config(folder, max_duration_s=800)
    got = {x.id: x for x in record_lengths(plan(cfg).records, cfg)}
    assert got["long"].npts == 70_001 and got["long"].duration_s == pytest.approx(700.0)
    assert got["short"].duration_s == pytest.approx(29.99)


def test_the_lengths_are_read_once_and_kept_in_the_run_folder(tmp_path, monkeypatch):
    folder = _records(tmp_path, {"a": 3000, "b": 4000})
    cfg = _config(folder)
    known = read_lengths(tmp_path)
    first = record_lengths(plan(cfg).records, cfg, known)
    assert not (tmp_path / LENGTHS_FILE).exists()  # kept once the run goes ahead
    keep_lengths(tmp_path, known)
    assert len(read_lengths(tmp_path)) == 2

    def refuse(*a, **k):
        raise AssertionError("read again")

    monkeypatch.setattr("isorock.io.read_trace", refuse)
    monkeypatch.setattr("isorock.control.lengths._SEEN", {})  # a new process: the kept file alone
    assert record_lengths(plan(cfg).records, cfg, read_lengths(tmp_path)) == first
    # a changed file is read again
    _text(folder / "a.txt", 5000)
    with pytest.raises(AssertionError, match="read again"):
        record_lengths(plan(cfg).records, cfg, read_lengths(tmp_path))


def test_a_file_too_large_for_the_bounds_is_refused_unread(tmp_path, monkeypatch):
    big = tmp_path / "huge.txt"
    big.write_bytes(b"1.0e-01\n" * (recs.MAX_SAMPLES * recs.MAX_BYTES_PER_SAMPLE // 8 + 1))

    def refuse(*a, **k):
        raise AssertionError("read")

    monkeypatch.setattr("isorock.records.directory.read_record", refuse)
    fc = recs.check_file(big, dt=0.01, units="g")
    assert not fc.ok and "more than a record of at most 200,000 samples takes (not read;" in fc.problem
    monkeypatch.setattr("isorock.records.adding.read_trace", refuse)
    with pytest.raises(IsorockError, match="not read"):
        add_records([big], tmp_path / "r", dt=0.01, units="g")


def test_the_memory_a_job_declares_grows_with_its_input_above_its_floor():
    assert job_memory_mb("process_record", 0.5) == FLOOR_MB["process_record"]
    # a record of 2 million samples in one-column text (13 bytes each): about 2.3 GB measured
    mb = 2_000_000 * 13 / 2**20
    assert job_memory_mb("process_record", mb) == int(np.ceil(BASE_MB + PER_INPUT_MB["process_record"] * mb))
    assert job_memory_mb("process_record", mb) > 2_000_000 * 1.07e3 / 2**20
    assert job_memory_mb("merge", 10) == FLOOR_MB["merge"]
    assert job_memory_mb("min_overturn", "TBD") == FLOOR_MB["min_overturn"]  # not known yet


def test_the_estimate_counts_the_records_durations(tmp_path):
    cfg = load_config({})
    plain = cost.estimate(cfg, 4)
    same = cost.estimate(cfg, 4, durations_s=[cost.BENCH_RECORD_S] * 4)
    long = cost.estimate(cfg, 4, durations_s=[3 * cost.BENCH_RECORD_S] * 4, memory_mb=2345)
    assert same.seconds == pytest.approx(plain.seconds)
    record_studies = sum(s.cpu_s for s in plain.studies if s.study != "pulses")
    assert long.cpu_s == pytest.approx(plain.cpu_s + 2 * record_studies)
    assert long.analyses == plain.analyses
    text = long.text()
    assert "on 4 record(s) of 120 s (480 s of record in all)" in text
    assert "its record jobs declare up to 2,345 MB of memory each (the longest record)" in text
