"""A newcomer's first tries at ``isorock simulate`` (issue 35, item 6): everything missing is named in one
error, ``--rho`` says it is required, and a mistyped option is answered with the one it resembles and
the command's own usage."""

from __future__ import annotations

from support.cli import run_cli


def test_everything_missing_at_once():
    p = run_cli(["simulate", "--isolation", "linear", "--pulse", "rect"])
    assert p.returncode == 2 and "Traceback" not in p.stderr
    line = p.stderr.strip().splitlines()
    assert len(line) == 1
    for what in ("give the block", "--Tb (isolation period, s)", "--xi (damping ratio)", "--rho", "--td"):
        assert what in line[0], line[0]


def test_fp_names_all_it_lacks():
    p = run_cli(
        ["simulate", "--lambda", "4", "--R", "1", "--isolation", "fp", "--pulse", "rect", "--td", "0.3"]
    )
    assert p.returncode == 2
    assert "isolation fp needs --mu (friction coefficient), --rho (mass ratio m/m_b), --Rb" in p.stderr


def test_rho_help_says_required():
    p = run_cli(["simulate", "--help"])
    assert "required with --isolation linear or fp" in " ".join(p.stdout.split())


def test_mistyped_option_suggests_the_close_one():
    p = run_cli(["simulate", "--lamda", "4", "--R", "1", "--pulse", "rect", "--td", "0.3", "--pga", "0.3"])
    assert p.returncode == 2
    assert "--lamda: did you mean --lambda?" in p.stderr
    assert "usage: isorock simulate" in p.stderr
