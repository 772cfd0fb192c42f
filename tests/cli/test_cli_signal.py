"""``isorock info`` and ``isorock pulse`` (isorock.cli.signal)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from isorock.cli import main
from isorock.constants import G
from isorock.pulse import mp_acceleration, mp_velocity

TP = 1.6  # period of the synthetic MP pulse [s]


@pytest.fixture()
def pulse_file(tmp_path):
    """A one-column file (g, dt = 0.01 s) holding an MP velocity pulse of period TP and amplitude 0.8 m/s."""
    dt = 0.01
    t = np.arange(0.0, 30.0, dt)
    acc = mp_acceleration(t, 0.8, 1.0 / TP, math.pi / 2, 2.0, 8.0)
    p = tmp_path / "pulse_g.txt"
    np.savetxt(p, acc / G)
    return p


@pytest.fixture()
def bbp_file(tmp_path):
    """A small three-component BBP file (cm/s^2)."""
    dt = 0.01
    t = np.arange(0.0, 20.0, dt)
    ns = 100.0 * mp_acceleration(t, 0.5, 0.5, 0.0, 2.0, 8.0)
    ew = 0.5 * ns
    lines = ["#    time(sec)      N-S(cm/s/s)      E-W(cm/s/s)      U-D(cm/s/s)"]
    lines += [f"{ti:.6e} {a:.6e} {b:.6e} {a:.6e}" for ti, a, b in zip(t, ns, ew, strict=True)]
    p = tmp_path / "three.bbp"
    p.write_text("\n".join(lines) + "\n")
    return p


def _run(capsys, *argv):
    rc = main([str(a) for a in argv])
    out = capsys.readouterr()
    return rc, out.out, out.err


def test_pulse_json(capsys, pulse_file):
    rc, out, err = _run(
        capsys, "pulse", pulse_file, "--format", "one-column", "--dt", 0.01, "--units", "g", "--json"
    )
    assert rc == 0, err
    d = json.loads(out)
    for k in (
        "Tp_s",
        "Tp_mp_s",
        "pulse_like",
        "pulse_indicator",
        "mp_A_m_s",
        "mp_fp_hz",
        "mp_nu_rad",
        "mp_gamma",
        "mp_t0_s",
        "Tp_br_s",
    ):
        assert k in d, k
    assert d["Tp_mp_s"] == pytest.approx(TP, rel=0.03)
    assert d["Tp_br_s"] == pytest.approx(TP, abs=0.03)  # nu = pi/2: the PGV half-cycle lasts TP / 2
    assert d["mp_fp_hz"] == pytest.approx(1 / TP, rel=0.03)
    assert d["pulse_like"] is True
    assert d["qa_passed"] is True


def test_pulse_text(capsys, pulse_file):
    rc, out, _ = _run(capsys, "pulse", pulse_file, "--format", "one-column", "--dt", 0.01, "--units", "g")
    assert rc == 0
    assert "Tp (db4 wavelet" in out and "Mavroeidis-Papageorgiou" in out and "pulse-like" in out
    assert "Bray & Rodriguez-Marek" in out


def test_info_json_and_text(capsys, pulse_file):
    rc, out, err = _run(
        capsys, "info", pulse_file, "--format", "one-column", "--dt", 0.01, "--units", "g", "--json"
    )
    assert rc == 0, err
    d = json.loads(out)
    for k in ("npts", "dt_s", "pga_g", "pgv_m_s", "pgd_m", "arias_m_s", "d5_95_s"):
        assert k in d, k
    assert d["npts"] == 3000 and d["dt_s"] == 0.01
    t = np.arange(0.0, 30.0, 0.01)
    pgv = np.max(np.abs(mp_velocity(t, 0.8, 1.0 / TP, math.pi / 2, 2.0, 8.0)))  # 0.7 m/s
    assert d["pgv_m_s"] == pytest.approx(pgv, rel=0.03)
    assert d["pga_g"] == pytest.approx(
        np.max(np.abs(mp_acceleration(t, 0.8, 1.0 / TP, math.pi / 2, 2.0, 8.0))) / G, rel=0.03
    )
    rc, out, _ = _run(capsys, "info", pulse_file, "--format", "one-column", "--dt", 0.01, "--units", "g")
    assert rc == 0 and "PGA" in out and "Arias" in out and "D5-95" in out


def test_component_choice(capsys, bbp_file):
    rc, _out, err = _run(capsys, "info", bbp_file)
    assert rc == 2 and "--component" in err and len(err.strip().splitlines()) == 1
    rc, out, err = _run(capsys, "info", bbp_file, "--component", "E-W", "--json")
    assert rc == 0, err
    assert json.loads(out)["component"] == "E-W"


@pytest.mark.parametrize(
    "argv, words",
    [
        (["pulse", "/no/such/file.txt"], "no such file"),
        (["info", "{f}", "--format", "one-column", "--dt", "-0.01", "--units", "g"], "dt"),
        (["info", "{f}", "--format", "one-column", "--units", "g"], "dt"),
        (
            [
                "info",
                "{f}",
                "--format",
                "one-column",
                "--dt",
                "0.01",
                "--units",
                "g",
                "--config",
                "/no/conf.yaml",
            ],
            "conf",
        ),
    ],
)
def test_user_errors_exit_2_with_one_line(capsys, pulse_file, argv, words):
    rc, _out, err = _run(capsys, *[a.replace("{f}", str(pulse_file)) for a in argv])
    assert rc == 2
    assert len(err.strip().splitlines()) == 1 and err.startswith("isorock: error:")
    assert words in err


def test_pulse_of_a_file_reports_the_wavelet_period_as_Tp_s(capsys, pulse_file):
    rc, out, err = _run(
        capsys, "pulse", pulse_file, "--format", "one-column", "--dt", 0.01, "--units", "g", "--json"
    )
    assert rc == 0, err
    d = json.loads(out)
    assert d["method"] == "wavelet" and d["Tp_s"] == d["Tp_wavelet_s"]


@pytest.fixture()
def e04_records(tmp_path):
    """A records directory holding two synthetic components (140 and 230) of the Table 1 row IMV79-E04:
    an MP pulse of period TP polarised along azimuth 53 deg, its SN direction (strike 323 deg)."""
    dt = 0.01
    t = np.arange(0.0, 30.0, dt)
    acc = mp_acceleration(t, 0.8, 1.0 / TP, math.pi / 2, 2.0, 8.0)
    d = tmp_path / "recs"
    d.mkdir()
    rows = ["file,table1_id,event,station,component,format,units,dt_s,column,note"]
    for az in (140, 230):
        np.savetxt(d / f"E04-{az}.txt", acc * math.cos(math.radians(az - 53.0)) / G)
        rows.append(
            f"E04-{az}.txt,IMV79-E04,1979 Imperial Valley,El Centro Array #4,{az},one-column,g,0.01,,"
        )
    (d / "manifest.csv").write_text("\n".join(rows) + "\n")
    return d


def test_pulse_by_table1_id_rotates_to_the_rows_direction(capsys, e04_records):
    rc, out, err = _run(capsys, "pulse", "--id", "IMV79-E04", "--records", e04_records, "--json")
    assert rc == 0, err
    d = json.loads(out)
    assert (d["component"], d["azimuth_deg"], d["component_method"]) == ("SN", 53.0, "rotated")
    assert d["method"] == "mp" and d["Tp_s"] == d["Tp_mp_s"] and d["tp_source"].startswith("Mavroeidis")
    assert d["Tp_s"] == pytest.approx(TP, rel=0.03)
    assert {"Tp_wavelet_s", "Tp_br_s", "table1_tp_s", "Tp_error_pct"} <= set(d)
    assert [r["component"] for r in d["record"]["rotated_from"]] == ["140", "230"]
    rc, out, err = _run(capsys, "info", "--id", "IMV79-E04", "--records", e04_records, "--json")
    assert rc == 0, err
    i = json.loads(out)
    assert (i["component"], i["azimuth_deg"]) == ("SN", 53.0)
    t = np.arange(0.0, 30.0, 0.01)
    pgv = np.max(np.abs(mp_velocity(t, 0.8, 1.0 / TP, math.pi / 2, 2.0, 8.0)))
    assert i["pgv_m_s"] == pytest.approx(pgv, rel=0.03)  # the whole pulse: rotated onto its direction
    rc, out, _ = _run(capsys, "pulse", "--id", "IMV79-E04", "--records", e04_records)
    assert rc == 0 and "component: SN (rotated)" in out and "Tp by the method of the Table 1 source" in out


@pytest.mark.parametrize(
    "argv, words",
    [
        (["pulse", "{f}", "--id", "IMV79-E04"], "not both"),
        (["pulse"], "FILE or --id"),
        (["pulse", "{f}", "--records", "{d}"], "--records applies to --id"),
        (["pulse", "--id", "IMV79-E04", "--records", "{d}", "--units", "g"], "--units"),
        (["pulse", "--id", "NOPE-1", "--records", "{d}"], "not a catalog row"),
        (["info", "--id", "NOR94-RRS", "--records", "{d}"], "no file"),
    ],
)
def test_id_errors_exit_2_with_one_line(capsys, pulse_file, e04_records, argv, words):
    argv = [a.replace("{f}", str(pulse_file)).replace("{d}", str(e04_records)) for a in argv]
    rc, _out, err = _run(capsys, *argv)
    assert rc == 2 and len(err.strip().splitlines()) == 1 and words in err


def _table1_ids_present() -> list:
    from support.records import manifest

    ids = sorted({r["table1_id"] for r in manifest() if r["table1_id"]})
    if not ids:
        return [
            pytest.param(None, marks=pytest.mark.skip(reason="shared records not found"), id="no-records")
        ]
    return ids


@pytest.mark.parametrize("rid", _table1_ids_present())
def test_pulse_by_id_for_every_table1_row_present(capsys, rid):
    """``isorock pulse --id`` on the shared records: the Tp of the row's published method, its
    direction, and the other methods under their own keys."""
    from isorock.records.catalog import load_catalog
    from support.records import need_records

    d = need_records()
    rc, out, err = _run(capsys, "pulse", "--id", rid, "--records", d, "--json")
    assert rc == 0, err
    p = json.loads(out)
    row = load_catalog().set_index("id").loc[rid]
    method = "br" if "Bray" in row["tp_source"] else "mp"
    assert p["method"] == method and p["Tp_s"] == p[f"Tp_{method}_s"] and p["id"] == rid
    assert p["component"] and "azimuth_deg" in p and p["component_method"] in (
        "provided", "rotated", "aligned", "as recorded"
    )  # fmt: skip
    assert p["table1_tp_s"] == row["tp_s"] and len(p["record"]["sha256"]) == 64


DEFAULT_STEPS = (
    "check_pga, detrend x2, taper, bandpass_filter, baseline_polynomial, check_tail, check_pga, resample"
)


def _count(names: str) -> int:
    return sum(int(n.rsplit(" x", 1)[1]) if " x" in n else 1 for n in names.split(", "))


def test_processing_text_counts_and_names_the_same_steps(capsys, pulse_file):
    """What was seen: "processed (9 steps: ...)" listing 7 names (a step run twice named once)."""
    rc, out, _ = _run(capsys, "info", pulse_file, "--format", "one-column", "--dt", 0.01, "--units", "g")
    assert rc == 0
    assert f"processed (9 steps: {DEFAULT_STEPS})" in out.splitlines()[0]
    assert _count(DEFAULT_STEPS) == 9
    common = ["--format", "one-column", "--dt", 0.01, "--units", "g"]
    rc, out, _ = _run(capsys, "simulate", "--lambda", 4, "--R", 2, "--record", pulse_file, *common)
    assert rc == 0 and f"processed (9 steps: {DEFAULT_STEPS})" in out


def test_processing_text_counts_the_structured_steps_not_the_lines():
    """The provenance of a rotated record has a rotation line first: it is not a processing step."""
    from obspy import Trace

    from isorock.cli.options import processing_text
    from isorock.processing import applied_steps, process
    from isorock.records.motion import RecordSource

    tr = process(Trace(0.5 * np.sin(np.arange(2000) * 0.05), header={"delta": 0.01}))
    lines = ["isorock: rotate_horizontal(140, 230 -> 53 deg)", *tr.stats.processing]
    source = RecordSource("f", "0", "one-column", "g", "given", "", "", lines, steps=applied_steps(tr))
    assert len(lines) == 10
    assert processing_text(source) == f"processed (9 steps: {DEFAULT_STEPS})"
    raw = RecordSource("f", "0", "one-column", "g", "given", "", "", None)
    assert processing_text(raw) == "not processed (--raw)"
