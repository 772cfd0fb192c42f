"""Issue 17's acceptance flow, on a fresh clone's default record set (the pyslammer samples, no
``$ISOROCK_RECORDS``): two files of the user's own added with ``isorock records add`` run with the
samples, and each is found by its id in every command without ``--format/--units/--dt``.

A full ``isorock report`` of the 20 records is not run here (minutes); the record lookup the
workflow's plan uses is checked instead.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from isorock.cli import main
from isorock.pipeline import load_config, plan
from isorock.records.lookup import find_records

pytest.importorskip("pyslammer", reason="the default record set (the samples) needs pyslammer")
pytest.importorskip("snakemake", reason="the workflow's plan needs snakemake")

N_SAMPLES = 18


def _accel(n: int, dt: float, amp: float) -> np.ndarray:
    t = np.arange(n) * dt
    return amp * np.sin(2 * np.pi * 1.2 * t) * np.exp(-0.3 * t) * np.minimum(t, 1.0)


def _at2_body(path, dt=0.01):
    """A PEER AT2 body with no header: data lines only, 5 values per line [g]."""
    a = _accel(1500, dt, 0.25)
    path.write_text("".join("".join(f"{x:15.7E}" for x in a[i : i + 5]) + "\n" for i in range(0, a.size, 5)))
    return path


def _percent(path, dt=0.004):
    """A %-header file whose second line holds the sample count and the time step [cm/s^2]."""
    a = _accel(2000, dt, 150.0)
    lines = ["%luc fn Lucerne, Landers 28 Jun 1992 (a synthetic stand-in)", f"%{a.size} {dt:.6f} 0 0 0."]
    lines += ["".join(f"{x:14.5E}" for x in a[i : i + 6]) for i in range(0, a.size, 6)]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_added_records_run_with_the_samples_and_are_found_by_id(tmp_path, monkeypatch, capsys):
    monkeypatch.delenv("ISOROCK_RECORDS", raising=False)
    monkeypatch.chdir(tmp_path)
    body = _at2_body(tmp_path / "quake-E.AT2")
    pct = _percent(tmp_path / "luc_fn.dat")
    mine = tmp_path / "my-records"

    argv = ["records", "add", str(body), "--format", "peer-at2-body", "--dt", "0.01", "--units", "g"]
    assert main([*argv, "--records", str(mine)]) == 0
    out = capsys.readouterr().out
    assert "added quake-E" in out and "component E (from the file name)" in out
    # the %-header file: format and time step detected, component from its name
    assert main(["records", "add", str(pct), "--units", "cm/s2", "--records", str(mine)]) == 0
    out = capsys.readouterr().out
    assert "added luc_fn" in out and "percent-header" in out and "component FN (from the file name)" in out
    # added again: one record, said so, no error
    assert main(["records", "add", str(pct), "--units", "cm/s2", "--records", str(mine)]) == 0
    assert "same sha256: not added again" in capsys.readouterr().out

    # every command finds an added record by its id, read as its manifest row says
    for rid, dt, comp in (("quake-E", 0.01, "E"), ("luc_fn", 0.004, "FN")):
        assert main(["info", "--id", rid, "--records", str(mine), "--json"]) == 0
        info = json.loads(capsys.readouterr().out)
        assert info["id"] == rid and info["dt_s"] == pytest.approx(dt) and info["component"] == comp
        assert info["table1_pga_g"] is None and info["qa_passed"] in (True, False)
    assert main(["simulate", "--id", "quake-E", "--records", str(mine), "--lambda", "3", "--R", "1"]) == 0
    capsys.readouterr()

    # the default configuration with that directory: the 18 samples and the 2 added records
    rc = load_config({"records": {"dir": str(mine)}})
    found = find_records(rc["records"], tmp_path)
    ids = [r.id for r in found.records]
    assert len(ids) == N_SAMPLES + 2 and ids[-2:] == ["quake-E", "luc_fn"]
    assert sum(r.source == "pyslammer samples" for r in found.records) == N_SAMPLES
    assert plan(rc, basedir=tmp_path).ids == ids  # what the workflow runs


def test_records_added_to_the_default_place_run_with_isorock_report(tmp_path, monkeypatch, capsys):
    """``isorock records add FILE`` (no --records) then ``isorock report``: the default place is
    found, and the store would hold the samples and the new record."""
    monkeypatch.delenv("ISOROCK_RECORDS", raising=False)
    monkeypatch.chdir(tmp_path)
    pct = _percent(tmp_path / "luc_fn.dat")
    assert main(["records", "add", str(pct), "--units", "cm/s2"]) == 0
    assert "(the default)" in capsys.readouterr().out
    p = plan(load_config({}), basedir=tmp_path)
    assert len(p.ids) == N_SAMPLES + 1 and p.ids[-1] == "luc_fn"
    assert main(["info", "--id", "luc_fn", "--json"]) == 0  # --records not needed either
    assert json.loads(capsys.readouterr().out)["dt_s"] == pytest.approx(0.004)
