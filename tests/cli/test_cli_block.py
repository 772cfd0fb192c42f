"""The block named by ``--height``/``--width`` or ``--lambda``/``--R`` (one pair, checked once), both
descriptions in the JSON, and the PGA actually applied in the text output (issue 17)."""

import math
import re

import pytest

from isorock.cli import build_parser, main
from support.cli import run_cli, run_json

HW = ["--height", "2.0", "--width", "0.5"]
LR = ["--lambda", "4", "--R", repr(0.5 * math.hypot(2.0, 0.5))]
PULSE = ["--pulse", "halfsine", "--td", "0.5", "--pga", "0.3"]
BLOCK_KEYS = {"lambda", "R_m", "height_m", "width_m"}
TBXI = ["map", "Tb-xi", "--rho", "0.5", "--n-Tb", "3", "--n-xi", "2", "--threads", "1"]


def _same_run(a: dict, b: dict) -> None:
    """Two JSON outputs of the same analysis: equal but for the timing and the block's descriptions
    (those computed from the other pair may differ in the last bit)."""
    skip = {"seconds", *BLOCK_KEYS}
    assert {k: v for k, v in a.items() if k not in skip} == {k: v for k, v in b.items() if k not in skip}
    for k in BLOCK_KEYS:
        assert a[k] == pytest.approx(b[k], rel=1e-12), k


def test_simulate_height_width_is_lambda_R(capsys):
    hw = run_json(capsys, ["simulate", *HW, *PULSE, "--json"])
    lr = run_json(capsys, ["simulate", *LR, *PULSE, "--json"])
    assert hw["outcome"] == "rocking"  # a run with something to compare
    _same_run(hw, lr)
    assert BLOCK_KEYS <= set(hw) and BLOCK_KEYS <= set(lr)
    assert hw["height_m"] == 2.0 and hw["width_m"] == 0.5  # given: as given
    assert hw["lambda"] == 4.0 and hw["R_m"] == 0.5 * math.hypot(2.0, 0.5)  # computed
    assert lr["lambda"] == 4.0 and lr["R_m"] == float(LR[3])  # given: as given
    assert lr["height_m"] == pytest.approx(2.0, rel=1e-12) and lr["width_m"] == pytest.approx(0.5, rel=1e-12)
    # the keys that were there before are still there
    assert {"outcome", "pga_g", "alpha_rad", "seconds", "mu_required"} <= set(hw)
    assert hw["alpha_rad"] == pytest.approx(math.atan(0.25), rel=1e-12)


def test_min_overturn_and_map_take_height_width(capsys):
    argv = ["min-overturn", "--pulse", "rect", "--td", "0.5", "--json"]
    hw = run_json(capsys, [argv[0], *HW, *argv[1:]])
    lr = run_json(capsys, [argv[0], *LR, *argv[1:]])
    _same_run(hw, lr)
    assert BLOCK_KEYS <= set(hw) and hw["uplift_g"] == pytest.approx(0.25)
    hw = run_json(capsys, [*TBXI, *HW, *PULSE, "--json"])
    lr = run_json(capsys, [*TBXI, *LR, *PULSE, "--json"])
    _same_run(hw, lr)
    assert BLOCK_KEYS <= set(hw) and hw["height_m"] == 2.0 and hw["lambda"] == 4.0


def test_text_output_names_both_descriptions(capsys):
    assert main(["simulate", *HW, *PULSE]) == 0
    out = capsys.readouterr().out
    assert "lambda=4, R=1.03078 m (height 2 m, width 0.5 m)" in out
    assert "PGA applied: 0.3 g" in out


def test_block_options_are_the_same_everywhere():
    """--lambda, --R, --height and --width: one definition, on every command that takes a block."""
    parser = build_parser()
    seen: dict = {}
    for argv in (["simulate"], ["min-overturn"], ["map", "Tb-xi"]):
        sub = parser
        for name in argv:
            sub = next(a for a in sub._actions if a.__class__.__name__ == "_SubParsersAction").choices[name]
        flags = {f: act for act in sub._actions for f in act.option_strings}
        for flag in ("--lambda", "--R", "--height", "--width"):
            act = flags[flag]
            assert not act.required
            seen.setdefault(flag, set()).add((act.dest, act.help, act.default))
    assert {k: len(v) for k, v in seen.items()} == {"--lambda": 1, "--R": 1, "--height": 1, "--width": 1}
    # a lambda-R map has the block as its axes: none of the four
    lam_r = parser.parse_args(["map", "lambda-R", "--pulse", "rect", "--td", "1", "--pga", "1"])
    assert not {"lam", "R", "height", "width"} & set(vars(lam_r))


BAD = [
    ([*HW, *LR], "not both pairs"),
    (["--height", "2", "--lambda", "4"], "not both pairs"),
    (["--width", "0.5", "--R", "1"], "not both pairs"),
    (["--height", "2"], "--height needs --width"),
    (["--width", "0.5"], "--width needs --height"),
    (["--lambda", "4"], "--lambda needs --R"),
    (["--R", "1"], "--R needs --lambda"),
    ([], "give the block"),
    (["--height", "0", "--width", "0.5"], "--height 0 must be > 0 m"),
    (["--height", "2", "--width", "-0.5"], "--width -0.5 must be > 0 m"),
    (["--lambda", "-4", "--R", "1"], "--lambda -4 must be > 0"),
    (["--lambda", "4", "--R", "0"], "--R 0 must be > 0 m"),
    (["--height", "nan", "--width", "0.5"], "--height nan must be > 0 m"),
]


@pytest.mark.parametrize("block, words", BAD)
@pytest.mark.parametrize("command", ["simulate", "min-overturn", "map"])
def test_bad_block_is_one_line_exit_2(capsys, command, block, words):
    rest = {
        "simulate": ["simulate", *PULSE],
        "min-overturn": ["min-overturn", "--pulse", "rect", "--td", "0.5"],
        "map": [*TBXI, *PULSE],
    }[command]
    assert main([*rest, *block]) == 2
    cap = capsys.readouterr()
    lines = [ln for ln in cap.err.splitlines() if ln.strip()]
    assert cap.out == "" and len(lines) == 1 and words in lines[0], cap.err


@pytest.mark.parametrize("block", [[*HW, "--lambda", "4"], ["--height", "2"]])
def test_bad_block_from_the_shell(block):
    """The same errors as a user sees them: one line, exit code 2, no traceback, no usage line."""
    p = run_cli(["simulate", *block, *PULSE])
    lines = [ln for ln in p.stderr.splitlines() if ln.strip()]
    assert p.returncode == 2 and len(lines) == 1 and lines[0].startswith("isorock: error: --"), p.stderr


def _applied(out: str) -> tuple[float, float, float]:
    """The PGA applied, the record's own PGA and the scale factor of a text output."""
    m = re.search(r"^PGA applied: (\S+) g \(record's own PGA (\S+) g x scale factor (\S+)\)$", out, re.M)
    assert m, out
    return float(m[1]), float(m[2]), float(m[3])


@pytest.mark.parametrize("block", [HW, LR])
def test_text_output_prints_the_pga_applied_to_a_record(capsys, plain_file, block):
    common = ["simulate", *block, "--record", str(plain_file), "--dt", "0.01", "--units", "g"]
    record_pga = run_json(capsys, [*common, "--json"])["pga_g"]  # as processed, unscaled
    assert abs(record_pga - 0.3) > 0.1  # so that the two cannot be confused
    assert main([*common, "--pga", "0.3"]) == 0
    out = capsys.readouterr().out
    applied, own, scale = _applied(out)
    assert applied == 0.3
    assert own == pytest.approx(record_pga, rel=1e-3) and scale == pytest.approx(0.3 / record_pga, rel=1e-3)
    assert "PGA=" not in out  # the record's own PGA is never printed unlabelled
    # --scale F: the PGA applied is F x the record's
    assert main([*common, "--scale", "2"]) == 0
    applied, own, scale = _applied(capsys.readouterr().out)
    assert scale == 2 and applied == pytest.approx(2 * record_pga, rel=1e-3)
    # the JSON says the same
    out = run_json(capsys, [*common, "--pga", "0.3", "--json"])
    assert out["pga_g"] == 0.3 and out["record_pga_g"] == pytest.approx(record_pga, rel=1e-12)
    assert out["scale"] == pytest.approx(0.3 / record_pga, rel=1e-12)


def test_map_text_prints_the_pga_applied_to_a_record(capsys, plain_file):
    rec = ["--record", str(plain_file), "--dt", "0.01", "--units", "g", "--pga", "0.3"]
    assert main([*TBXI, *HW, *rec]) == 0
    out = capsys.readouterr().out
    m = re.search(r"^PGA applied: (\S+) g \(record's own PGA (\S+) g x scale factor (\S+)\)$", out, re.M)
    assert m and float(m[1]) == 0.3 and float(m[1]) == pytest.approx(float(m[2]) * float(m[3]), rel=1e-3)
