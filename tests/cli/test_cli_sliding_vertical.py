"""`isorock simulate --friction MU` and `--vertical auto|FILE` (issue 24): the JSON keys the issue names,
the sliding mode below tan(alpha), the vertical found beside a record (the BBP files of the shared
records are found through their manifest rows, not by name), and the errors (one line, exit 2)."""

from __future__ import annotations

import numpy as np
import pytest

from isorock.constants import G
from support.cli import run_cli, run_json
from support.records import manifest, need_records

SQUAT = ["--height", "1.2", "--width", "0.5"]  # tan(alpha) = 0.417: the worked example's showcase
PULSE = ["--pulse", "rect", "--td", "0.4", "--pga", "0.5"]


def test_friction_below_tan_alpha_gives_the_sliding_keys(capsys):
    out = run_json(
        capsys, ["simulate", *SQUAT, "--isolation", "none", *PULSE, "--friction", "0.35", "--json"]
    )
    assert out["mode"] == "sliding" and out["friction"] == 0.35
    assert out["tan_alpha"] == pytest.approx(0.5 / 1.2)
    # the closed form of docs/model.md §16: 0.5 (A - mu g) td^2 A / (mu g)
    A, mu, td = 0.5 * G, 0.35, 0.4
    exact = 0.5 * (A - mu * G) * td**2 * A / (mu * G)
    assert out["sliding_peak_m"] == pytest.approx(exact, rel=1e-9)
    assert out["sliding_residual_m"] == pytest.approx(-exact, rel=1e-9)
    assert out["n_slips"] == 1 and out["t_first_slip_s"] == 0.0
    assert out["outcome"] == "no_uplift" and out["max_theta_over_alpha"] == 0.0


def test_friction_above_tan_alpha_is_the_rocking_analysis(capsys):
    base = ["simulate", *SQUAT, "--isolation", "none", "--pulse", "halfsine", "--td", "0.5", "--pga", "0.8"]
    plain = run_json(capsys, [*base, "--json"])
    rock = run_json(capsys, [*base, "--friction", "0.9", "--json"])
    assert rock["mode"] == plain["mode"] == "rocking" and "sliding_peak_m" not in rock
    assert rock["max_theta_over_alpha"] == plain["max_theta_over_alpha"]


def test_squat_object_on_an_isolator_slides_where_rocking_would_bounce(capsys):
    """Width 0.5 m, height 0.3 m: below the no-bounce slenderness of an isolated base, it never rocks."""
    iso = ["--isolation", "linear", "--Tb", "2.5", "--xi", "0.1", "--rho", "0.8"]
    argv = ["simulate", "--height", "0.3", "--width", "0.5", *iso, "--pulse", "halfsine", "--td", "0.5"]
    out = run_json(capsys, [*argv, "--pga", "0.8", "--friction", "0.4", "--json"])
    assert out["mode"] == "sliding" and out["n_slips"] >= 1 and out["sliding_peak_m"] > 0.01
    res = run_cli([*argv, "--pga", "0.8"])
    assert res.returncode == 2 and "give its friction" in res.stderr and "Traceback" not in res.stderr


@pytest.mark.parametrize(
    "extra, what",
    [
        (["--friction", "0"], "--friction 0 must be > 0"),
        (["--friction", "35"], "--friction 35 is above 1"),
        (["--vertical", "auto"], "--vertical applies to --record or --id"),
    ],
)
def test_bad_friction_or_vertical_is_one_line(extra, what):
    res = run_cli(["simulate", *SQUAT, "--isolation", "none", *PULSE, *extra])
    assert res.returncode == 2 and what in res.stderr, res.stderr
    assert len(res.stderr.strip().splitlines()) == 1


def _bbp_rows() -> list[dict[str, str]]:
    need_records()
    return [r for r in manifest() if r["format"] == "bbp"]


def test_vertical_auto_on_the_bbp_record_with_a_real_vertical(capsys):
    d = need_records()
    real = [r for r in _bbp_rows() if "duplicates N-S" not in r["note"] and "repeats N-S" not in r["note"]]
    assert len(real) == 1, "the manifest names one BBP file with a vertical of its own"
    rec = ["--record", str(d / real[0]["file"]), "--component", "N-S"]
    out = run_json(
        capsys,
        ["simulate", *SQUAT, "--isolation", "none", *rec, "--scale", "1", "--vertical", "auto", "--json"],
    )
    assert out["vertical"]["component"] == "U-D" and out["vertical"]["cut"] == out["vertical"]["padded"] == 0
    # the processed U-D column's peak (the raw column peaks at 0.35 g), scaled with the horizontal (x 1)
    assert 0.3 < out["vertical_pga_g"] < 0.4 and out["jumps"] is False
    # the same with a scale: the vertical follows the horizontal
    twice = run_json(
        capsys,
        ["simulate", *SQUAT, "--isolation", "none", *rec, "--scale", "2", "--vertical", "auto", "--json"],
    )
    assert twice["vertical_pga_g"] == pytest.approx(2 * out["vertical_pga_g"], rel=1e-12)
    # and the sliding mode with it
    sl = run_json(
        capsys,
        ["simulate", *SQUAT, "--isolation", "none", *rec, "--scale", "1", "--vertical", "auto",
         "--friction", "0.3", "--json"],
    )  # fmt: skip
    assert sl["mode"] == "sliding" and sl["n_slips"] >= 1 and "vertical_pga_g" in sl


def test_vertical_auto_refuses_a_copied_u_d_column():
    d = need_records()
    copies = [r for r in _bbp_rows() if "duplicates N-S" in r["note"] or "repeats N-S" in r["note"]]
    assert copies
    r = copies[0]
    res = run_cli(["simulate", *SQUAT, "--isolation", "none", "--record", str(d / r["file"]),
                   "--component", "N-S", "--vertical", "auto"])  # fmt: skip
    assert res.returncode == 2 and "repeats the horizontal N-S: no vertical" in res.stderr, res.stderr


def _two_column(path, t, a):
    np.savetxt(path, np.column_stack([t, a / G]), fmt="%.8f")


def test_vertical_file_of_your_own(tmp_path, capsys):
    """--vertical FILE: a vertical of constant -0.3 g is gravity 0.7 g: the uplift time of a ramp moves
    to (g - 0.3 g) tan(alpha) / rate (no processing: --raw)."""
    t = np.arange(0, 5, 0.01)
    _two_column(tmp_path / "h.txt", t, 2.0 * t)
    _two_column(tmp_path / "v.txt", t, np.full(t.size, -0.3 * G))
    base = ["simulate", "--lambda", "4", "--R", "1", "--isolation", "none", "--record",
            str(tmp_path / "h.txt"),
            "--format", "two-column", "--units", "g", "--raw", "--scale", "1", "--json"]  # fmt: skip
    plain = run_json(capsys, base)
    vert = run_json(capsys, [*base, "--vertical", str(tmp_path / "v.txt")])
    tan_a = 0.25
    assert plain["t_uplift_s"] == pytest.approx(G * tan_a / 2.0, abs=0.011)
    assert vert["t_uplift_s"] == pytest.approx(0.7 * G * tan_a / 2.0, abs=0.011)
    assert vert["vertical_pga_g"] == pytest.approx(0.3, rel=1e-9)


def test_vertical_file_that_copies_the_horizontal_is_refused(tmp_path):
    t = np.arange(0, 5, 0.01)
    a = np.sin(3 * t) * np.exp(-0.3 * t)
    _two_column(tmp_path / "h.txt", t, a)
    _two_column(tmp_path / "v.txt", t, a)
    res = run_cli(["simulate", "--lambda", "4", "--R", "1", "--isolation", "none", "--record",
                   str(tmp_path / "h.txt"), "--format", "two-column", "--units", "g",
                   "--vertical", str(tmp_path / "v.txt")])  # fmt: skip
    assert res.returncode == 2 and "repeats the horizontal" in res.stderr, res.stderr
    assert len(res.stderr.strip().splitlines()) == 1


def test_vertical_auto_finds_peer_s_up_file_beside_a_name_with_a_dot(capsys):
    """``RSN6_IMPVALL.I_I-ELC-UP.AT2`` (El Centro 1940's vertical, PEER's name) was not found beside
    ``RSN6_IMPVALL.I_I-ELC180-hor1.AT2``: the name was cut at its first dot, so it named no component."""
    d = need_records()
    rows = [r for r in manifest() if r["file"].startswith("RSN6_IMPVALL.I_I-ELC")]
    h1 = next((r["file"] for r in rows if "180" in r["file"]), None)
    if h1 is None or not any("-UP" in r["file"] for r in rows):
        pytest.skip("the manifest names no El Centro 1940 (RSN6) horizontal and vertical")
    out = run_json(
        capsys,
        ["simulate", *SQUAT, "--isolation", "none", "--record", str(d / h1), "--vertical", "auto", "--json"],
    )
    assert out["vertical"]["file"].endswith("RSN6_IMPVALL.I_I-ELC-UP.AT2")
    assert out["vertical_pga_g"] > 0
