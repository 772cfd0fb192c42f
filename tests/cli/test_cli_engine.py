"""`isorock simulate` / `isorock min-overturn`: keys, exit codes and the record path (a public contract)."""

import json
import math

import numpy as np
import pytest

from isorock.cli import main
from support.cli import run_cli, run_json
from support.records import RECORDS_SKIP, records_dir

SIM_KEYS = {"outcome", "max_theta_over_alpha", "n_impacts", "max_base_disp_m", "t_uplift_s", "t_overturn_s"}
MIN_KEYS = {"min_overturn_g", "uplift_g", "min_overturn_over_tan_alpha", "n_analyses", "resolution"}
BLOCK = ["--lambda", "4", "--R", "1"]


@pytest.mark.parametrize(
    "iso",
    [
        [],
        ["--isolation", "linear", "--Tb", "3", "--xi", "0.35", "--rho", "0.5"],
        ["--isolation", "fp", "--mu", "0.11", "--Rb", "2.24", "--rho", "0.5"],
    ],
)
def test_simulate_json_keys(capsys, iso):
    argv = ["simulate", "--lambda", "4", "--R", "3", *iso, "--pulse", "fullsine", "--td", "0.5"]
    out = run_json(capsys, [*argv, "--pga", "0.6", "--json"])
    assert SIM_KEYS <= set(out) and out["pga_g"] == 0.6 and out["stalls"] == 0
    assert out["jumps"] is False and isinstance(out["mu_required"], float)
    assert out["outcome"] in ("no_uplift", "rocking", "overturn")
    if out["outcome"] == "no_uplift":
        assert out["t_uplift_s"] is None
    else:
        assert out["t_uplift_s"] > 0
    assert "record" not in out  # a pulse has no record provenance


def test_simulate_json_reactions_and_jumps(capsys):
    """``jumps`` tells a block that would jump (``mu_required`` null: not defined once the normal force
    vanishes) from one that does not (``mu_required`` always a number), docs/model.md §15."""
    argv = ["simulate", "--lambda", "3", "--R", "1", "--pulse", "fullsine", "--json"]
    jumps = run_json(capsys, [*argv, "--td", "0.05", "--pga", "6"])
    assert jumps["jumps"] is True and jumps["mu_required"] is None and jumps["min_normal_over_weight"] <= 0
    rocks = run_json(capsys, [*argv, "--td", "0.4", "--pga", "0.6"])
    assert rocks["jumps"] is False and rocks["outcome"] != "no_uplift"
    assert isinstance(rocks["mu_required"], float) and 0 < rocks["min_normal_over_weight"] <= 1
    # a block that lifts off at once under a rectangular pulse: no full-contact demand of 0.35 g
    rect = run_json(capsys, ["simulate", *BLOCK, "--pulse", "rect", "--td", "0.3", "--pga", "0.35", "--json"])
    assert rect["jumps"] is False and rect["mu_required"] == pytest.approx(4.75 / 17.3, rel=1e-9)


def test_amp_is_a_deprecated_alias_of_pga(capsys):
    argv = ["simulate", *BLOCK, "--pulse", "halfsine", "--td", "0.5", "--json"]
    new = run_json(capsys, [*argv, "--pga", "0.4"])
    assert main([*argv, "--amp", "0.4"]) == 0
    cap = capsys.readouterr()
    assert json.loads(cap.out)["outcome"] == new["outcome"] and json.loads(cap.out)["pga_g"] == 0.4
    assert "--amp is deprecated" in cap.err and "--pga" in cap.err


def test_min_overturn_json_resolution_and_null(capsys):
    argv = ["min-overturn", "--lambda", "4", "--R", "3", "--pulse", "rect", "--td", "0.5", "--json"]
    out = run_json(capsys, argv)
    assert MIN_KEYS <= set(out)
    assert out["uplift_g"] == pytest.approx(0.25)
    assert out["min_overturn_over_tan_alpha"] == pytest.approx(out["min_overturn_g"] / 0.25)
    assert out["n_analyses"] > 1
    # the relative uncertainty is the scan step, not the (far narrower) bisection bracket
    assert out["resolution"] == pytest.approx(0.005) and out["bisection_width"] <= 1e-6
    coarse = run_json(capsys, [*argv, "--growth", "1.05"])
    assert coarse["resolution"] == pytest.approx(0.05)
    assert abs(coarse["min_overturn_g"] / out["min_overturn_g"] - 1) <= 0.05 + 1e-9
    none = run_json(capsys, [*argv, "--pga-max", "0.3"])
    assert none["min_overturn_g"] is None and none["min_overturn_over_tan_alpha"] is None
    assert none["resolution"] is None


def test_min_overturn_text_has_the_precision_of_the_scan(capsys):
    assert main(["min-overturn", "--lambda", "4", "--R", "3", "--pulse", "rect", "--td", "0.5"]) == 0
    line = next(ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("minimum overturning"))
    value = line.split(":")[1].split("g")[0].strip()
    assert len(value.replace("0.", "", 1).lstrip("0")) == 3  # 3 significant digits at a 0.5 % resolution
    assert "resolution 0.5 %" in line


def test_record_is_processed_by_default_and_raw_on_request(plain_file, capsys):
    common = ["simulate", *BLOCK, "--record", str(plain_file), "--dt", "0.01", "--units", "g", "--json"]
    raw = run_json(capsys, [*common, "--raw", "--scale", "2"])
    assert raw["pga_g"] == pytest.approx(1.0, rel=1e-3) and raw["outcome"] == "overturn"
    assert raw["record"]["processing"] == "none (raw record)" and raw["scale"] == 2
    processed = run_json(capsys, common)
    steps = processed["record"]["processing"]
    assert isinstance(steps, list) and any("bandpass_filter" in s for s in steps)
    info = run_json(capsys, ["info", str(plain_file), "--dt", "0.01", "--units", "g", "--json"])
    assert info["pga_g"] == processed["pga_g"]  # the same signal through both commands
    info_raw = run_json(capsys, ["info", str(plain_file), "--dt", "0.01", "--units", "g", "--raw", "--json"])
    raw1 = run_json(capsys, [*common, "--raw"])
    assert info_raw["pga_g"] == raw1["pga_g"] == pytest.approx(0.5, rel=1e-3)
    # --pga G: the processed record scaled to G, and reported as G
    scaled = run_json(capsys, [*common, "--pga", "0.8"])
    assert scaled["pga_g"] == 0.8 and scaled["scale"] == pytest.approx(0.8 / processed["pga_g"])


def test_min_overturn_reports_the_record(plain_file, capsys):
    out = run_json(
        capsys,
        ["min-overturn", *BLOCK, "--record", str(plain_file), "--dt", "0.01", "--units", "g", "--json"],
    )
    rec = out["record"]
    assert {"file", "sha256", "units", "processing", "format", "component"} <= set(rec)
    assert rec["file"] == str(plain_file.resolve()) and len(rec["sha256"]) == 64
    assert rec["units"] == "g" and rec["units_source"] == "given" and rec["format"] == "one-column"
    assert 0.25 < out["min_overturn_g"] < 1.0


@pytest.mark.parametrize("command", ["simulate", "min-overturn", "map"])
def test_headerless_file_without_units_is_refused(plain_file, command):
    argv = {
        "simulate": ["simulate", *BLOCK],
        "min-overturn": ["min-overturn", *BLOCK],
        "map": ["map", "lambda-R", "--pga", "0.3", "--n-lambda", "2", "--n-R", "2"],
    }[command]
    p = run_cli([*argv, "--record", str(plain_file), "--dt", "0.01"])
    assert p.returncode == 2 and "Traceback" not in p.stderr
    lines = [ln for ln in p.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and "units" in lines[0] and str(plain_file) in lines[0]


def test_two_column_file_in_m_s2_needs_its_units(tmp_path, capsys):
    """What was seen: a two-column file in m/s2 read as g gave 8.27 g and 'overturn' without a word."""
    t = np.arange(0, 10, 0.02)
    f = tmp_path / "sylmar_like.dat"
    acc = 8.1 * np.sin(2 * np.pi * t) * np.exp(-0.3 * t)  # m/s2
    np.savetxt(f, np.column_stack([t, acc]))
    assert main(["simulate", *BLOCK, "--record", str(f)]) == 2
    assert "units not given" in capsys.readouterr().err
    out = run_json(capsys, ["simulate", *BLOCK, "--record", str(f), "--units", "m/s2", "--raw", "--json"])
    assert out["pga_g"] == pytest.approx(np.max(np.abs(acc)) / 9.81, rel=1e-6)


@pytest.mark.skipif(records_dir() is None, reason=RECORDS_SKIP)
def test_shared_two_column_m_s2_file():
    f = records_dir() / "Northridge_Sylmar_County.dat"
    p = run_cli(["simulate", *BLOCK, "--record", str(f)])
    assert p.returncode == 2 and "units" in p.stderr and "Traceback" not in p.stderr
    p = run_cli(["simulate", *BLOCK, "--record", str(f), "--units", "m/s2", "--json"])
    assert p.returncode == 0 and json.loads(p.stdout)["pga_g"] < 1.0  # about 0.84 g, not 8.27 g


def test_conflicting_units_are_named(tmp_path):
    at2 = tmp_path / "x.AT2"
    at2.write_text(
        "PEER NGA STRONG MOTION DATABASE RECORD\nX, 1/1/2000, Y, 090\n"
        "ACCELERATION TIME SERIES IN UNITS OF G\n"
        "NPTS=   200, DT=   .0100 SEC,\n"
        + "\n".join(f"{0.2 * math.sin(0.1 * k):.6E}" for k in range(200))
        + "\n"
    )
    p = run_cli(["simulate", *BLOCK, "--record", str(at2), "--units", "cm/s2"])
    assert p.returncode == 2 and "units='cm/s2' given but the file states g" in p.stderr
    assert "PEER" not in p.stderr


@pytest.mark.parametrize(
    "argv, words",
    [
        (["simulate", "--lambda", "-4", "--R", "3", "--pulse", "rect", "--td", "1", "--pga", "1"], "lambda"),
        (["simulate", *BLOCK, "--isolation", "linear", "--pulse", "rect", "--td", "1", "--pga", "1"], "--Tb"),
        (["simulate", *BLOCK, "--pulse", "rect", "--pga", "1"], "--td"),
        (["simulate", *BLOCK, "--pulse", "rect", "--td", "1"], "--pga"),
        (["simulate", *BLOCK, "--record", "/nonexistent/file.txt", "--dt", "0.01"], "/nonexistent/file.txt"),
        (
            [
                "simulate",
                *BLOCK,
                "--isolation",
                "linear",
                "--Tb",
                "3",
                "--xi",
                "-1",
                "--rho",
                "0.5",
                "--pulse",
                "rect",
                "--td",
                "1",
                "--pga",
                "1",
            ],
            "--xi",
        ),  # fmt: skip
        # options the command would ignore are refused
        (
            ["simulate", *BLOCK, "--Tb", "3", "--pulse", "rect", "--td", "1", "--pga", "1"],
            "--isolation is none",
        ),
        (
            [
                "simulate",
                *BLOCK,
                "--isolation",
                "linear",
                "--Tb",
                "3",
                "--xi",
                "0.2",
                "--rho",
                "0.5",
                "--mu",
                "0.1",
                "--pulse",
                "rect",
                "--td",
                "1",
                "--pga",
                "1",
            ],
            "--mu given but --isolation is linear",
        ),  # fmt: skip
        (
            ["simulate", *BLOCK, "--pulse", "rect", "--td", "1", "--pga", "1", "--dt", "0.01"],
            "apply to --record",
        ),
        (["simulate", *BLOCK, "--record", "x.txt", "--td", "1"], "--td applies to --pulse"),
        (["simulate", *BLOCK, "--record", "x.txt", "--pga", "1", "--scale", "2"], "not both"),
    ],
)
def test_errors_one_line_exit_2_no_traceback(argv, words):
    p = run_cli(argv)
    assert p.returncode == 2
    assert "Traceback" not in p.stderr
    lines = [ln for ln in p.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and words in lines[0], p.stderr


@pytest.mark.parametrize(
    "argv, words",
    [
        (["map", "lambda-R", "--lambda", "4", "--pulse", "rect", "--td", "1", "--pga", "1"], "--lambda"),
        (["map", "lambda-R", "--pulse", "rect", "--td", "1"], "--pga"),
        (
            ["map", "Tb-xi", "--lambda", "4", "--R", "3", "--pulse", "rect", "--td", "1", "--pga", "1"],
            "--rho",
        ),
    ],
)
def test_map_usage_errors(argv, words):
    """Options a map ignores are unknown to it; required ones are required (usage line, exit 2)."""
    p = run_cli(argv)
    assert p.returncode == 2 and "Traceback" not in p.stderr and words in p.stderr


def test_bad_record_names_file_and_line(tmp_path):
    f = tmp_path / "bad.txt"
    f.write_text("0.1\n0.2\nabc\n0.3\n")
    p = run_cli(
        ["simulate", *BLOCK, "--record", str(f), "--dt", "0.01", "--units", "g", "--format", "one-column"]
    )
    assert p.returncode == 2 and "Traceback" not in p.stderr
    assert f"{f}:3" in p.stderr
