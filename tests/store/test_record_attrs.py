"""The one spec of the record attributes (RECORD_ATTRS), the processing steps of a record in the store
(layout 4, and layout 2 read back), and the restitution table computed once (isorock.store.layout)."""

from __future__ import annotations

import json
import math
import shutil

import h5py
import numpy as np
import pandas as pd
import pytest

from isorock.jobs import record as jobs
from isorock.jobs.merge import merge
from isorock.physics.model import housner_restitution, impact_coefficients
from isorock.pipeline import load_config, params_process, plan
from isorock.processing import AppliedStep
from isorock.records.adding import add_records
from isorock.store import (
    COLUMN_UNITS,
    LAYOUT_HISTORY,
    LAYOUT_VERSION,
    RECORD_ATTRS,
    RECORD_SUMMARY_COLUMNS,
    Store,
    describe_record_attrs,
    processing_steps,
    read_table,
    record_attr_names,
    record_attrs_in_order,
    restitution_table,
)

#: the columns of /summary/records of layout 2, in order: the table must not change
SUMMARY_COLUMNS_V2 = (
    "record", "label", "event", "year", "station", "component", "azimuth_deg", "component_method",
    "component_qa", "table1_component", "catalog_id", "source_file", "rotated_from", "source_format",
    "substitute", "npts", "dt_s", "duration_s", "pga_g", "pgv_m_s", "pgd_m", "arias_m_s", "d5_95_s", "Tp_s",
    "Tp_mp_s", "Tp_br_s", "tp_method", "Tp_method_s", "pulse_like", "pulse_indicator", "table1_pga_g",
    "table1_pgv_m_s", "table1_tp_s", "tp_source", "qa_passed", "record_sha256",
)  # fmt: skip

#: the processing lines of /records/IMV79-E04 in a store of layout 2 (isorock 0.1.0), as written
OLD_LINES = [
    "isorock: rotate_horizontal(140, 230 -> 53 deg)",
    "isorock 0.1.0: check_pga(min_g=0.001, max_g=5): PGA 0.3672 g passed",
    "isorock 0.1.0: detrend(type='linear'): mean before 1.9e-06 m/s^2",
    "isorock 0.1.0: detrend(type='demean'): mean before 5.908e-18 m/s^2",
    "isorock 0.1.0: taper(type='hann', max_percentage=0.05, max_length=2, side='both'): 1.95 s at each "
    "tapered end",
    "isorock 0.1.0: bandpass_filter(freqmin=0.05, freqmax=40, corners=4, zerophase=True, pad=True): acausal "
    "Butterworth band-pass (obspy), zero pads 60 s at each end removed after",
    "isorock 0.1.0: baseline_polynomial(order=6, end_constraints=True): removed the second derivative of the "
    "fitted displacement polynomial, max 0.0145 m/s^2",
    "isorock 0.1.0: check_tail(duration=5, max_vel_ratio=0.3, max_dis_ratio=0.9): tail ratios velocity "
    "0.0843, displacement 0.109 passed",
    "isorock 0.1.0: check_pga(min_g=0.001, max_g=5): PGA 0.3659 g passed",
    "isorock 0.1.0: resample(dt=None): not resampled (no target dt)",
]


def _quake(path, amp=0.3, n=1500, dt=0.01):
    t = np.arange(n) * dt
    np.savetxt(path, amp * np.sin(2 * np.pi * 1.5 * t) * np.exp(-0.3 * t) * np.minimum(t, 1.0))
    return path


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """The record jobs of one record of the user's own (no shared records needed), and their merge."""
    d = tmp_path_factory.mktemp("attrs")
    mine = d / "mine"
    add_records([_quake(d / "quake.txt")], mine, ids=["MY-QUAKE"], dt=0.01, units="g", event="My quake")
    cfg = load_config({"records": {"dir": str(mine)}})
    p = plan(cfg, d)
    pp = params_process(cfg, p.spec("MY-QUAKE"), p.processing)
    rec, pulse = d / "rec.h5", d / "pulse.h5"
    written = jobs.process_record(pp["spec"], rec, processing=pp["processing"], choose=pp["choose"])
    jobs.extract_pulse(rec, pulse, pulse={"tp_min_s": 0.25, "tp_max_s": 15.0, "fit_mp": False})
    store = d / "store.h5"
    merge([rec, pulse], store, config=cfg, source=f"records directory {mine}", config_name="attrs")
    return {"rec": rec, "pulse": pulse, "store": store, "written": written, "dir": d}


# ------------------------------------------------------------------------------------------ the spec
def test_the_spec_is_well_formed():
    names = [a.name for a in RECORD_ATTRS]
    assert len(names) == len(set(names))
    assert {a.kind for a in RECORD_ATTRS} <= {"text", "json", "number", "integer", "flag"}
    assert {a.job for a in RECORD_ATTRS} == {"process_record", "extract_pulse"}
    for a in RECORD_ATTRS:
        assert a.description, a.name
        assert (a.unit != "") == (a.kind == "number"), a.name  # numbers have a unit ("-": dimensionless)
    # a column of /summary/records with a unit has the spec's unit
    for a in RECORD_ATTRS:
        if a.summary and a.name in COLUMN_UNITS:
            assert COLUMN_UNITS[a.name] == a.unit, a.name
    assert "processing_json" in names and len(describe_record_attrs().splitlines()) == len(names)


def test_summary_columns_are_those_of_layout_2_then_the_vertical():
    """Layout 4 adds the vertical's columns after those of layout 2, which keep their order."""
    n = len(SUMMARY_COLUMNS_V2)
    assert RECORD_SUMMARY_COLUMNS[:n] == SUMMARY_COLUMNS_V2
    assert RECORD_SUMMARY_COLUMNS[n : n + 4] == (
        "vertical_component", "vertical_pga_g", "vertical_pgv_m_s", "vertical_note"
    )  # fmt: skip
    # layout 7 adds, after them, among others the recording's metadata (records add --peer-search)
    assert RECORD_SUMMARY_COLUMNS[-4:] == ("mw", "rjb_km", "vs30_m_s", "luf_hz")


def test_layout_version_and_its_history():
    assert LAYOUT_VERSION == 7 and max(LAYOUT_HISTORY) == LAYOUT_VERSION
    assert "processing_json" in LAYOUT_HISTORY[3] and "vertical_pga_g" in LAYOUT_HISTORY[4]
    assert "dimension scales" in LAYOUT_HISTORY[5] and "time_s" in LAYOUT_HISTORY[5]


def test_record_attrs_in_order_refuses_other_names():
    values = {k: 1.0 for k in record_attr_names("extract_pulse")}
    assert list(record_attrs_in_order(values, "extract_pulse")) == list(record_attr_names("extract_pulse"))
    with pytest.raises(ValueError, match=r"missing \['Tp_s'\]"):
        record_attrs_in_order({k: v for k, v in values.items() if k != "Tp_s"}, "extract_pulse")
    with pytest.raises(ValueError, match=r"extra \['Tp_other_s'\]"):
        record_attrs_in_order({**values, "Tp_other_s": 1.0}, "extract_pulse")


# ------------------------------------------------------------------------------------------ writer and merge
def test_the_jobs_write_exactly_the_spec(run):
    assert list(run["written"]) == list(record_attr_names("process_record"))
    with h5py.File(run["rec"], "r") as f:
        assert set(f["records/MY-QUAKE"].attrs) == set(record_attr_names("process_record"))
    with h5py.File(run["pulse"], "r") as f:
        assert set(f["records/MY-QUAKE"].attrs) == set(record_attr_names("extract_pulse"))


def test_the_merge_keeps_exactly_the_spec(run):
    with h5py.File(run["store"], "r") as f:
        assert f.attrs["layout_version"] == LAYOUT_VERSION
        g = f["records/MY-QUAKE"]
        assert set(g.attrs) == {a.name for a in RECORD_ATTRS}
        for a in RECORD_ATTRS:  # the extract_pulse ones are those of the pulse group
            if a.job == "extract_pulse" and a.kind != "text":
                assert np.array_equal(g.attrs[a.name], g["pulse"].attrs[a.name], equal_nan=True), a.name
    rec = read_table(run["store"], "summary/records")
    assert tuple(rec.columns) == RECORD_SUMMARY_COLUMNS and rec["record"].tolist() == ["MY-QUAKE"]
    for a in RECORD_ATTRS:
        if a.summary and a.kind in ("text", "json"):
            assert isinstance(rec[a.name].iloc[0], str), a.name
        if a.summary and a.kind == "flag":
            assert rec[a.name].dtype == bool, a.name


# ------------------------------------------------------------------------------------------ processing steps
def test_the_store_keeps_the_steps_and_their_lines(run):
    with h5py.File(run["store"], "r") as f:
        g = f["records/MY-QUAKE"]
        raw = json.loads(g.attrs["processing_json"])
        lines = [x.decode() for x in g["processing"][()]]
    assert [set(d) for d in raw] == [{"step", "parameters", "note"}] * len(raw)
    steps = Store(run["store"]).record_processing("MY-QUAKE")
    assert [s.step for s in steps] == [
        "check_pga", "detrend", "detrend", "taper", "bandpass_filter", "baseline_polynomial", "check_tail",
        "check_pga", "resample",
    ]  # fmt: skip
    assert steps[1].parameters == {"type": "linear"} and steps[-1].parameters == {"dt": None}
    assert steps[4].parameters["freqmax"] == 40.0 and steps[4].note.startswith("acausal Butterworth")
    assert lines == [s.line(run["written"]["isorock_version"]) for s in steps]  # the lines are the same steps
    assert Store(run["store"]).record_processing("NOPE") == []


def _as_layout_2(src, dst):
    """A copy of a store as layout 2 wrote it: no processing_json, layout_version 2."""
    shutil.copyfile(src, dst)
    with h5py.File(dst, "a") as f:
        f.attrs["layout_version"] = 2
        for g in f["records"].values():
            del g.attrs["processing_json"]
    return dst


def test_an_old_store_is_read_from_its_lines(run, tmp_path):
    old = Store(_as_layout_2(run["store"], tmp_path / "old.h5"))
    new = Store(run["store"])
    assert (old.layout_version, new.layout_version) == (2, LAYOUT_VERSION)
    a, b = old.record_processing("MY-QUAKE"), new.record_processing("MY-QUAKE")
    assert [(s.step, s.note) for s in a] == [(s.step, s.note) for s in b]
    for x, y in zip(a, b, strict=True):  # parameters as printed: 6 significant digits
        assert x.parameters.keys() == y.parameters.keys()
        for k, v in y.parameters.items():
            assert x.parameters[k] == (pytest.approx(v, rel=1e-5) if isinstance(v, float) else v), k


def test_a_layout_2_store_written_by_isorock_0_1(tmp_path):
    """The lines of a rotated record as isorock 0.1.0 wrote them; the rotation is not a step."""
    path = tmp_path / "v2.h5"
    with h5py.File(path, "w") as f:
        f.attrs["layout_version"] = 2
        g = f.create_group("records/IMV79-E04")
        g.attrs["component_method"] = "rotated"
        g.create_dataset("processing", data=np.array(OLD_LINES, dtype=h5py.string_dtype()))
    steps = Store(path).record_processing("IMV79-E04")
    assert len(steps) == 9 and all(isinstance(s, AppliedStep) for s in steps)
    assert [s.step for s in steps][:3] == ["check_pga", "detrend", "detrend"]
    assert steps[3].parameters == {"type": "hann", "max_percentage": 0.05, "max_length": 2, "side": "both"}
    assert steps[4].parameters["zerophase"] is True and steps[4].note.endswith("removed after")
    assert steps[6].note == "tail ratios velocity 0.0843, displacement 0.109 passed"
    assert steps[8].parameters == {"dt": None}
    with h5py.File(path, "r") as f:
        assert processing_steps(f["records/IMV79-E04"]) == steps


# ------------------------------------------------------------------------------------------ restitution
def test_restitution_table_is_the_closed_forms():
    df = restitution_table()
    assert list(df.columns) == ["lambda_", "rho", "eps", "beta1_over_h", "eps_housner"]
    assert len(df) == 5 * 91 and sorted(df["rho"].unique()) == [0.1, 0.25, 0.5, 1.0, 2.0]
    r = df.iloc[100]
    eps, beta1, _ = impact_coefficients(r["lambda_"], 1.0, r["rho"])
    assert (r["eps"], r["beta1_over_h"]) == (eps, beta1)
    assert r["eps_housner"] == housner_restitution(math.atan(1.0 / r["lambda_"]))
    small = restitution_table([0.5], [2.0, 4.0])
    assert small["lambda_"].tolist() == [2.0, 4.0] and small["rho"].tolist() == [0.5, 0.5]


def test_the_merge_stores_the_restitution_table(run):
    pd.testing.assert_frame_equal(read_table(run["store"], "pulses/restitution"), restitution_table())
