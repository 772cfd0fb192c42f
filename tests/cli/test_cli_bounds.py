"""The command line's bounds (issue 23, item 4): the ones of the configuration
(:mod:`isorock.plausibility`), every number finite, and a map above the cost limit refused unless
``--force``. Each refusal is exit code 2 and one line naming the option and what it must be."""

from __future__ import annotations

import pytest

from isorock.cli import main
from isorock.control.cost import MAX_ANALYSES
from isorock.plausibility import PERIOD_MAX_S, PERIOD_MIN_S
from support.cli import run_cli

BLOCK = ["--lambda", "4", "--R", "1"]
PULSE = ["--pulse", "rect", "--td", "1", "--pga", "1"]


def td(v: str, shape: str = "rect") -> list[str]:
    """A pulse of half-cycle duration ``v`` [s] at 1 g."""
    return ["--pulse", shape, "--td", v, "--pga", "1"]


FP = ["--isolation", "fp", "--Rb", "2", "--rho", "0.5"]
LINEAR = ["--isolation", "linear", "--Tb", "3", "--xi", "0.2", "--rho", "0.5"]


def _refused(capsys, argv: list[str]) -> str:
    """``isorock ARGV`` in this process: exit 2, nothing on stdout, one line on stderr (returned)."""
    assert main(argv) == 2
    out, err = capsys.readouterr()
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert out == "" and len(lines) == 1 and lines[0].startswith("isorock: error: "), err
    return lines[0]


@pytest.mark.parametrize(
    "argv, words",
    [
        (["simulate", *BLOCK, *FP, "--mu", "1.5", *PULSE], "--mu 1.5 is above 0.3: friction pendulum"),
        (["simulate", *BLOCK, *FP, "--mu", "0", *PULSE], "--mu 0 must be > 0 and <= 0.3"),
        (["simulate", *BLOCK, *td("1e9")],
         "--td 1e+09 is outside 0.05 to 20 s: a pulse's duration or period must be within them"),
        (["simulate", *BLOCK, *td("0.01", "halfsine")], "--td 0.01 is outside 0.05 to 20 s"),
        (["simulate", *BLOCK, *td("500")],
         "if it is milliseconds, 500 ms would be 0.5 s"),
        (["min-overturn", *BLOCK, "--pulse", "rect", "--td", "25"], "--td 25 is outside 0.05 to 20 s"),
        (["simulate", *BLOCK, *td("nan")], "--td nan is not a finite number"),
        (["simulate", *BLOCK, *td("1")[:-1], "inf"], "--pga inf is not a finite number"),
        (["simulate", "--lambda", "inf", "--R", "1", *PULSE], "--lambda inf is not a finite number"),
        (["simulate", *BLOCK, "--isolation", "linear", "--Tb", "30", "--xi", "0.2", "--rho", "0.5", *PULSE],
         "--Tb 30 is outside 0.05 to 20 s: an isolator's period"),
        (["simulate", *BLOCK, "--isolation", "linear", "--Tb", "inf", "--xi", "0.2", "--rho", "0.5", *PULSE],
         "--Tb inf is not a finite number"),
        (["simulate", *BLOCK, "--isolation", "linear", "--Tb", "3", "--xi", "0.2", "--rho", "50", *PULSE],
         "--rho 50 is out of range: the block-to-base mass ratio m/m_b is > 0 and <= 10"),
        (["simulate", *BLOCK, "--isolation", "fp", "--mu", "0.1", "--Rb", "224", "--rho", "0.5", *PULSE],
         "--Rb 224 gives a pendulum period 2 pi sqrt(R_b/g) of 30 s, outside 0.05 to 20 s"),
        (["map", "Tb-xi", *BLOCK, "--rho", "0.5", "--Tb-range", "0.5", "50", *PULSE[:4], "--pga", "0.5"],
         "--Tb-range 50 is outside 0.05 to 20 s"),
        (["map", "lambda-R", *PULSE[:4], "--pga", "0.5", "--lambda-range", "0", "8"],
         "--lambda-range 0.0 8.0: a block's lambda must be > 0"),
    ],
)  # fmt: skip
def test_out_of_bounds_is_refused_in_one_line(capsys, argv, words):
    line = _refused(capsys, argv)
    assert words in line, line


def test_refusal_in_a_separate_process_has_no_traceback():
    for argv in (["simulate", *BLOCK, *FP, "--mu", "1.5", *PULSE],
                 ["simulate", *BLOCK, *td("1e9")]):  # fmt: skip
        p = run_cli(argv)
        assert p.returncode == 2 and "Traceback" not in p.stderr and p.stdout == ""
        assert len(p.stderr.strip().splitlines()) == 1, p.stderr


@pytest.mark.parametrize("value", [PERIOD_MIN_S, PERIOD_MAX_S])
def test_the_bounds_themselves_run(capsys, value):
    argv = ["simulate", *BLOCK, *LINEAR, "--pulse", "rect", "--td", str(value), "--pga", "0.1", "--json"]
    assert main(argv) == 0, capsys.readouterr().err


def test_a_map_above_the_limit_needs_force(capsys):
    line = _refused(
        capsys, ["map", "lambda-R", *PULSE[:4], "--pga", "0.5", "--n-lambda", "100000", "--n-R", "100000"]
    )
    assert "map lambda-R 100000 x 100000: 10,000,000,000 analyses" in line
    assert (
        f"above the limit of {MAX_ANALYSES:,} analyses" in line
        and "rerun with --force to run it anyway" in line
    )
    line = _refused(capsys, ["map", "Tb-xi", *BLOCK, "--rho", "0.5", *PULSE[:4], "--pga", "0.5",
                             "--n-Tb", "10000", "--n-xi", "10000"])  # fmt: skip
    assert "map Tb-xi 10000 x 10000: 100,000,000 analyses" in line
    # at the limit: runs (a small map, its count checked exactly)
    argv = ["map", "lambda-R", *PULSE[:4], "--pga", "0.5", "--n-lambda", "3", "--n-R", "2", "--json"]
    assert main(argv) == 0


def test_a_map_dry_run_prints_its_cost_and_computes_nothing(capsys, tmp_path):
    out = tmp_path / "m.h5"
    grid = ["--n-lambda", "300", "--n-R", "200", "--threads", "2"]
    argv = ["map", "lambda-R", *PULSE[:4], "--pga", "0.5", *grid, "--out", str(out), "--dry-run"]
    assert main(argv) == 0
    printed = capsys.readouterr().out.strip()
    assert printed.startswith("cost estimate: map lambda-R 300 x 200: 60,000 analyses on 2 thread(s), about ")
    assert not out.exists()


def test_help_states_the_bounds_and_the_limit(capsys):
    with pytest.raises(SystemExit):
        main(["simulate", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "pulse half-cycle duration [s], 0.05 to 20" in text and "0 < mu <= 0.3" in text
    assert "isolation period [s], 0.05 to 20" in text and "0 < rho <= 10" in text
    for cmd in (["report", "--help"], ["map", "lambda-R", "--help"]):
        with pytest.raises(SystemExit):
            main(cmd)
        text = " ".join(capsys.readouterr().out.split())
        assert f"{MAX_ANALYSES / 1e6:g} million" in text and "--force" in text
