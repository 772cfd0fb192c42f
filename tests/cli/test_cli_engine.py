"""The `isorock simulate` / `isorock min-overturn` interface (keys and exit codes are a public contract)."""

import json
import subprocess
import sys

import numpy as np
import pytest

from isorock.cli import main

SIM_KEYS = {"outcome", "max_theta_over_alpha", "n_impacts", "max_base_disp_m", "t_uplift_s", "t_overturn_s"}
MIN_KEYS = {"min_overturn_g", "uplift_g", "min_overturn_over_tan_alpha", "n_analyses"}


def run_json(capsys, argv):
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize(
    "iso",
    [
        [],
        ["--isolation", "linear", "--Tb", "3", "--xi", "0.35", "--rho", "0.5"],
        ["--isolation", "fp", "--mu", "0.11", "--Rb", "2.24", "--rho", "0.5"],
    ],
)
def test_simulate_json_keys(capsys, iso):
    out = run_json(
        capsys,
        [
            "simulate",
            "--lambda",
            "4",
            "--R",
            "3",
            *iso,
            "--pulse",
            "fullsine",
            "--td",
            "0.5",
            "--amp",
            "0.6",
            "--json",
        ],
    )
    assert SIM_KEYS <= set(out)
    assert out["outcome"] in ("no_uplift", "rocking", "overturn")
    if out["outcome"] == "no_uplift":
        assert out["t_uplift_s"] is None
    else:
        assert out["t_uplift_s"] > 0


def test_min_overturn_json_and_null(capsys):
    out = run_json(
        capsys, ["min-overturn", "--lambda", "4", "--R", "3", "--pulse", "rect", "--td", "0.5", "--json"]
    )
    assert MIN_KEYS <= set(out)
    assert out["uplift_g"] == pytest.approx(0.25)
    assert out["min_overturn_over_tan_alpha"] == pytest.approx(out["min_overturn_g"] / 0.25)
    assert out["n_analyses"] > 1
    out = run_json(
        capsys,
        [
            "min-overturn",
            "--lambda",
            "4",
            "--R",
            "3",
            "--pulse",
            "rect",
            "--td",
            "0.5",
            "--amp-max",
            "0.3",
            "--json",
        ],
    )
    assert out["min_overturn_g"] is None and out["min_overturn_over_tan_alpha"] is None


def test_record_from_plain_file(tmp_path, capsys):
    dt = 0.01
    t = np.arange(0, 6, dt)
    acc = 0.5 * np.sin(2 * np.pi * t / 1.0) * (t < 1.0)  # one full-sine cycle, in g
    f = tmp_path / "rec.txt"
    np.savetxt(f, acc)
    out = run_json(
        capsys,
        [
            "simulate",
            "--lambda",
            "4",
            "--R",
            "1",
            "--record",
            str(f),
            "--dt",
            str(dt),
            "--units",
            "g",
            "--scale",
            "2",
            "--json",
        ],
    )
    assert out["pga_g"] == pytest.approx(1.0, rel=1e-3)
    assert out["outcome"] == "overturn"
    mo = run_json(
        capsys,
        [
            "min-overturn",
            "--lambda",
            "4",
            "--R",
            "1",
            "--record",
            str(f),
            "--dt",
            str(dt),
            "--units",
            "g",
            "--json",
        ],
    )
    assert 0.25 < mo["min_overturn_g"] < 1.0


@pytest.mark.parametrize(
    "argv, words",
    [
        (["simulate", "--lambda", "-4", "--R", "3", "--pulse", "rect", "--td", "1", "--amp", "1"], "lambda"),
        (
            [
                "simulate",
                "--lambda",
                "4",
                "--R",
                "3",
                "--isolation",
                "linear",
                "--pulse",
                "rect",
                "--td",
                "1",
                "--amp",
                "1",
            ],
            "--Tb",
        ),
        (["simulate", "--lambda", "4", "--R", "3", "--pulse", "rect", "--amp", "1"], "--td"),
        (
            ["simulate", "--lambda", "4", "--R", "3", "--record", "/nonexistent/file.txt", "--dt", "0.01"],
            "/nonexistent/file.txt",
        ),
        (
            [
                "simulate",
                "--lambda",
                "4",
                "--R",
                "3",
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
                "--amp",
                "1",
            ],
            "xi_b",
        ),
    ],
)
def test_errors_one_line_exit_2_no_traceback(argv, words):
    p = subprocess.run([sys.executable, "-m", "isorock.cli", *argv], capture_output=True, text=True)
    assert p.returncode == 2
    assert "Traceback" not in p.stderr
    lines = [ln for ln in p.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and words in lines[0], p.stderr


def test_bad_record_names_file_and_line(tmp_path):
    f = tmp_path / "bad.txt"
    f.write_text("0.1\n0.2\nabc\n0.3\n")
    p = subprocess.run(
        [
            sys.executable,
            "-m",
            "isorock.cli",
            "simulate",
            "--lambda",
            "4",
            "--R",
            "3",
            "--record",
            str(f),
            "--dt",
            "0.01",
            "--units",
            "g",
            "--format",
            "one-column",
        ],
        capture_output=True,
        text=True,
    )
    assert p.returncode == 2 and "Traceback" not in p.stderr
    assert str(f) in p.stderr and "3" in p.stderr
