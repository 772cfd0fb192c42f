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
