"""The vertical through the workflow's jobs (issue 24), on a recording of the user's own (no shared
records needed): ``records add`` registers its vertical file as the vertical of the records of its
event and station, ``process_record`` finds it, processes it alike and stores its peak, PGV and samples,
the analyses read it only when asked (``records.vertical``), and the minimum overturning PGA is kept
both ways for the paper page's sensitivity."""

from __future__ import annotations

import math

import h5py
import numpy as np
import pytest

from isorock import pipeline
from isorock.constants import G
from isorock.jobs.record import read_job_record
from isorock.records.adding import add_records
from isorock.records.lookup import find_records
from isorock.records.manifest import VERTICAL_NOTE, read_manifest
from isorock.report.build import vertical_table

SEARCH = {"amp_max_g": 5.0, "growth": 1.01, "rtol": 1e-3}


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    """A three-file recording of the user's own (two horizontals and an UP file), added together."""
    d = tmp_path_factory.mktemp("own")
    t = np.arange(2000) * 0.01
    env = np.exp(-(((t - 6.0) / 2.5) ** 2))
    h1 = 0.4 * np.sin(2 * np.pi * 1.1 * t) * env
    h2 = 0.3 * np.sin(2 * np.pi * 0.8 * t + 1.0) * env
    up = 0.5 * np.sin(2 * np.pi * 4.0 * t + 0.3) * env  # a strong vertical at a higher frequency
    files = []
    for name, a in (("SETA-hor1.txt", h1), ("SETA-hor2.txt", h2), ("SETA-UP.txt", up)):
        np.savetxt(d / name, a)
        files.append(d / name)
    mine = d / "mine"
    rows = add_records(files, mine, ids=["SETA1", "SETA2", "SETA-UP"], dt=0.01, units="g",
                       event="Test 2026", station="Lab")  # fmt: skip
    return mine, rows, up


def test_records_add_registers_the_vertical_without_an_id(recording):
    mine, rows, _ = recording
    ups = [r for r in rows if r.component == "U-D"]
    assert len(ups) == 1 and ups[0].id == "" and VERTICAL_NOTE in ups[0].note
    assert [r.id for r in read_manifest(mine / "manifest.csv") if r.id] == ["SETA1", "SETA2"]
    rs = find_records({"dir": str(mine), "select": ["SETA1"]})
    (spec,) = rs.records
    assert [f.component_name for f in spec.files] == ["HOR1", "U-D"]


def test_process_record_stores_the_vertical_and_the_analyses_read_it_when_asked(recording, tmp_path):
    mine, _, up = recording
    (spec,) = find_records({"dir": str(mine), "select": ["SETA1"]}).records
    out = tmp_path / "rec.h5"
    attrs = pipeline.process_record(spec, out)
    assert attrs["vertical_component"] == "SETA-UP.txt:U-D"
    # processed by the same steps as the horizontal (filtering barely touches a 4 Hz sine)
    assert attrs["vertical_pga_g"] == pytest.approx(0.5, rel=0.05)
    assert attrs["vertical_pgv_m_s"] == pytest.approx(0.5 * G / (2 * np.pi * 4.0), rel=0.05)
    assert "0 samples cut, 0 padded" in attrs["vertical_note"]
    with h5py.File(out) as h:
        g = h["records/SETA1"]
        assert g["vertical"].shape == g["acc"].shape and g["vertical"].attrs["units"] == "m/s^2"
    _, plain, _ = read_job_record(out)
    _, both, _ = read_job_record(out, vertical=True)
    assert plain.vertical is None and both.vertical is not None
    assert np.max(np.abs(both.vertical)) / G == pytest.approx(attrs["vertical_pga_g"], rel=1e-12)


def test_min_overturn_is_kept_both_ways(recording, tmp_path):
    mine, _, _ = recording
    (spec,) = find_records({"dir": str(mine), "select": ["SETA1"]}).records
    rec = tmp_path / "rec.h5"
    pipeline.process_record(spec, rec)
    case = {"name": "none", "kind": "none"}
    kw = {"lambdas": [4.0], "Rs": [0.5, 2.0], "cases": [case], "search": SEARCH}
    h = pipeline.min_overturn(rec, tmp_path / "h.h5", **kw, vertical=False)
    hv = pipeline.min_overturn(rec, tmp_path / "hv.h5", **kw, vertical=True)
    assert not h["with_vertical"].any() and hv["with_vertical"].all()
    np.testing.assert_array_equal(h["min_overturn_g"], h["min_overturn_h_g"])
    np.testing.assert_array_equal(hv["min_overturn_g"], hv["min_overturn_hv_g"])
    # the two runs searched the same two problems
    np.testing.assert_allclose(h["min_overturn_hv_g"], hv["min_overturn_hv_g"], rtol=0, atol=0)
    np.testing.assert_allclose(h["min_overturn_h_g"], hv["min_overturn_h_g"], rtol=0, atol=0)
    # a vertical half the size of the horizontal changes the answer
    assert (np.abs(h["min_overturn_hv_g"] / h["min_overturn_h_g"] - 1) > 1e-3).any()
    import pandas as pd

    table = vertical_table(
        h.assign(record="SETA1"),
        pd.DataFrame(
            {"record": ["SETA1"], "vertical_pga_g": [0.5], "vertical_component": ["SETA-UP.txt:U-D"]}
        ),
        {"SETA1": 0.5},
    )
    assert len(table) == 2 and set(table["vertical"]) == {"SETA-UP.txt:U-D"}
    down = 0.5 / h["record_pga_g"].to_numpy() * h["min_overturn_hv_g"].to_numpy()
    np.testing.assert_allclose(table["downward peak there [g]"], down, rtol=1e-12)
    assert ((table["jumps"] != "") == (down > 1.0)).all()
    r = table["ratio [-]"].to_numpy()
    assert np.all(np.isfinite(r)) and math.isclose(
        r[0], h["min_overturn_hv_g"].iloc[0] / h["min_overturn_h_g"].iloc[0]
    )


def test_a_record_without_a_vertical_says_why(tmp_path):
    from support.records import own_records

    mine = own_records(tmp_path)
    (spec,) = find_records({"dir": str(mine), "select": ["Q1"]}).records
    attrs = pipeline.process_record(spec, tmp_path / "q.h5")
    assert attrs["vertical_component"] == "" and math.isnan(attrs["vertical_pga_g"])
    assert attrs["vertical_note"] == "no vertical component"
    none = [{"name": "none", "kind": "none"}]
    df = pipeline.min_overturn(
        tmp_path / "q.h5",
        tmp_path / "o.h5",
        lambdas=[4.0],
        Rs=[1.0],
        cases=none,
        search=SEARCH,
        vertical=True,
    )
    assert not df["with_vertical"].any() and df["min_overturn_hv_g"].isna().all()


def test_a_vertical_without_event_or_station_attaches_by_its_file_name(tmp_path):
    """Plain files name no event or station: the vertical goes with the records whose file name is its
    own up to the last - or _ (SETB-UP.txt beside SETB-hor1.txt, not beside OTHER-hor1.txt)."""
    t = np.arange(1000) * 0.01
    for name in ("SETB-hor1.txt", "SETB-UP.txt", "OTHER-hor1.txt"):
        np.savetxt(tmp_path / name, 0.2 * np.sin(2 * np.pi * (1.0 + len(name) / 10) * t) * np.exp(-0.3 * t))
    mine = tmp_path / "mine"
    add_records([tmp_path / n for n in ("SETB-hor1.txt", "SETB-UP.txt", "OTHER-hor1.txt")], mine,
                ids=["B1", "B-UP", "O1"], dt=0.01, units="g")  # fmt: skip
    specs = {s.id: s for s in find_records({"dir": str(mine), "select": ["B1", "O1"]}).records}
    assert [f.component_name for f in specs["B1"].files] == ["HOR1", "U-D"]
    assert [f.component_name for f in specs["O1"].files] == ["HOR1"]


def test_a_dwn_vertical_is_stored_positive_up_with_its_sense_said(tmp_path):
    """Issue 34: a vertical file named DWN holds its samples positive down; the workflow stores it turned
    positive up, its note and the dataset's attributes say the sense of the file and the sign applied
    (an UP or U-D file is stored as read: sign +1)."""
    t = np.arange(2000) * 0.01
    env = np.exp(-(((t - 6.0) / 2.5) ** 2))
    up = 0.5 * np.sin(2 * np.pi * 4.0 * t + 0.3) * env  # the ground's vertical, positive up
    np.savetxt(tmp_path / "SETD-hor1.txt", 0.4 * np.sin(2 * np.pi * 1.1 * t) * env)
    np.savetxt(tmp_path / "SETD-DWN.txt", -up)  # as a positive-down instrument records it
    mine = tmp_path / "mine"
    add_records([tmp_path / "SETD-hor1.txt", tmp_path / "SETD-DWN.txt"], mine, ids=["D1", "D-DWN"],
                dt=0.01, units="g", event="Test 2026", station="Lab")  # fmt: skip
    (spec,) = find_records({"dir": str(mine), "select": ["D1"]}).records
    assert [f.component_name for f in spec.files] == ["HOR1", "DWN"]
    out = tmp_path / "d.h5"
    attrs = pipeline.process_record(spec, out)
    assert attrs["vertical_component"] == "SETD-DWN.txt:DWN"
    assert "positive down in the file" in attrs["vertical_note"] and "sign reversed" in attrs["vertical_note"]
    with h5py.File(out) as h:
        v = h["records/D1/vertical"]
        assert (v.attrs["positive_in_file"], int(v.attrs["sign"])) == ("down", -1)
        assert "DWN" in v.attrs["polarity"]
        stored = v[()]
    k = int(np.argmax(np.abs(up)))
    assert np.sign(stored[k]) == np.sign(up[k]) and abs(stored[k]) / G == pytest.approx(abs(up[k]), rel=0.05)
    assert np.corrcoef(stored, up)[0, 1] > 0.99
