"""Expected errors against bugs on the command line, and the options shared by the commands.

A user error (an :class:`~isorock.errors.IsorockError`, among them a
:class:`~isorock.errors.ParameterError` of the model or the excitations) is one line on stderr and exit
code 2, without a traceback; any other exception, a bare ``ValueError`` included, is a bug and keeps
its traceback. ``--id`` and ``--records`` are defined once, and the component chosen for ``--id`` is
returned by :func:`isorock.cli.options.excitation_from_args`, not left on the namespace.
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys

import numpy as np
import pytest

from isorock import FPIsolation, GroundMotion, LinearIsolation, Pulse
from isorock.cli import build_parser, main
from isorock.cli.options import LoadedExcitation, excitation_from_args
from isorock.constants import G
from isorock.errors import IsorockError, ParameterError
from isorock.physics.model import make_isolation
from isorock.pulse import mp_acceleration
from support.cli import run_cli

BLOCK = ["--lambda", "4", "--R", "1"]
LINEAR = ["--isolation", "linear", "--Tb", "3", "--rho", "0.5"]


# ------------------------------------------------------------------------------- ParameterError
@pytest.mark.parametrize(
    "make, words",
    [
        (lambda: Pulse("rect", -1.0), "td=-1.0 is out of range"),
        (lambda: Pulse("square", 1.0), "is not a pulse"),
        (lambda: GroundMotion(0.0, np.zeros(4)), "dt=0.0 is out of range"),
        (lambda: GroundMotion(0.01, np.zeros(4)).with_pga(0.3), "all zeros"),
        (lambda: LinearIsolation(Tb=3.0, xi_b=1.5, rho=0.5), "xi_b=1.5 is out of range"),
        (lambda: FPIsolation(mu_b=-0.1, R_b=2.0, rho=0.5), "mu_b=-0.1"),
        (lambda: make_isolation("linear", Tb_s=3.0, rho=0.5), "isolation linear needs xi_b"),
        (lambda: make_isolation("viscous"), "is not known"),
    ],
)
def test_invalid_parameters_raise_parameter_error(make, words):
    """A ParameterError is an IsorockError (the CLI's one line) and a ValueError (older callers)."""
    with pytest.raises(ParameterError, match=words) as info:
        make()
    assert isinstance(info.value, IsorockError) and isinstance(info.value, ValueError)


@pytest.mark.parametrize(
    "argv, words",
    [
        # the options are named as typed (--td), not as the model's parameters (td)
        (
            ["simulate", *BLOCK, "--pulse", "rect", "--td", "-1", "--pga", "1"],
            "--td -1 is outside 0.05 to 20 s",
        ),
        (["simulate", *BLOCK, "--pulse", "rect", "--td", "1", "--pga", "-1"], "--pga -1 must be > 0 g"),
        (
            ["simulate", *BLOCK, *LINEAR, "--xi", "2", "--pulse", "rect", "--td", "1", "--pga", "1"],
            "--xi 2 is out of range",
        ),
        (["min-overturn", *BLOCK, "--pulse", "rect", "--td", "1", "--growth", "1"], "growth=1.0"),
        (["min-overturn", *BLOCK, "--pulse", "rect", "--td", "1", "--rtol", "2"], "rtol=2.0"),
        (["demo", "--pga-max", "0"], "--pga-max 0 is outside (0, 50] g"),
        # values that read like another unit: refused with both readings (isorock.plausibility)
        (
            ["simulate", "--height", "180", "--width", "50", "--pulse", "rect", "--td", "1", "--pga", "1"],
            "--height 180 reads like centimetres: 180 m is above 10 m for an object's height, while 180 cm "
            "would be 1.8 m; give metres (--height 1.8)",
        ),
        (
            ["simulate", "--height", "1.8", "--width", "50", "--pulse", "rect", "--td", "1", "--pga", "1"],
            "--width 50 reads like centimetres",
        ),
        (
            [
                "simulate",
                *BLOCK,
                *"--isolation fp --mu 1.5 --Rb 2 --rho 0.5 --pulse rect --td 1 --pga 1".split(),
            ],
            "--mu 1.5 is above 0.3: friction pendulum isolators have 0.02 to 0.2",
        ),  # fmt: skip
    ],
)
def test_bad_parameter_is_one_line_exit_2_no_traceback(argv, words):
    p = run_cli(argv)
    assert p.returncode == 2, p.stderr
    assert "Traceback" not in p.stderr
    lines = [ln for ln in p.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("isorock: error: ") and words in lines[0], p.stderr
    assert p.stdout == ""


def test_bad_parameter_in_process(capsys):
    assert main(["simulate", *BLOCK, "--pulse", "halfsine", "--td", "0", "--pga", "1"]) == 2
    out, err = capsys.readouterr()
    assert (
        out == ""
        and err.startswith("isorock: error: --td 0 is outside 0.05 to 20 s")
        and err.count("\n") == 1
    )


# ------------------------------------------------------------------------------- bugs propagate
@pytest.mark.parametrize("exc", [RuntimeError("a bug"), ValueError("a bug"), ZeroDivisionError("a bug")])
def test_unexpected_exception_is_not_swallowed(monkeypatch, capsys, exc):
    """An exception that is not an IsorockError is a bug: main() lets it through, with its traceback."""
    import isorock.physics.engine

    def broken(*args, **kwargs):
        raise exc

    monkeypatch.setattr(isorock.physics.engine, "simulate", broken)
    with pytest.raises(type(exc), match="a bug"):
        main(["simulate", *BLOCK, "--pulse", "rect", "--td", "1", "--pga", "0.2"])
    assert "isorock: error" not in capsys.readouterr().err


def test_unexpected_exception_of_a_command_is_not_swallowed(monkeypatch):
    from isorock.cli import signal

    def broken(a: argparse.Namespace) -> int:
        raise ValueError("not a user error")

    monkeypatch.setattr(signal, "cmd_info", broken)  # register() reads it when main() builds the parser
    with pytest.raises(ValueError, match="not a user error"):
        main(["info", "whatever.txt"])


def test_a_bug_keeps_its_traceback_and_a_non_zero_exit():
    code = (
        "import sys, isorock.physics.engine\n"
        "def broken(*a, **k):\n"
        "    raise ValueError('a bug in the engine')\n"
        "isorock.physics.engine.simulate = broken\n"
        "from isorock.cli import main\n"
        "argv = ['simulate', '--lambda', '4', '--R', '1', '--pulse', 'rect', '--td', '1', '--pga', '1']\n"
        "sys.exit(main(argv))\n"
    )
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert p.returncode != 0
    assert "Traceback" in p.stderr and "ValueError: a bug in the engine" in p.stderr
    assert "isorock: error" not in p.stderr


# ------------------------------------------------------------------------------- shared options
def test_id_and_records_are_the_same_options_everywhere():
    """One definition of --id and --records: the same dest, metavar and help in every command."""
    parser = build_parser()
    seen = {}
    for argv in (["simulate", *BLOCK], ["min-overturn", *BLOCK], ["map", "lambda-R"], ["info"], ["pulse"]):
        sub = parser
        for word in argv[:2] if argv[0] == "map" else argv[:1]:
            sub = next(a for a in sub._actions if isinstance(a, argparse._SubParsersAction)).choices[word]
        for flag in ("--id", "--records"):
            act = sub._option_string_actions[flag]
            seen.setdefault(flag, set()).add((act.dest, act.metavar, act.help, act.default))
    assert {k: len(v) for k, v in seen.items()} == {"--id": 1, "--records": 1}
    assert next(iter(seen["--id"]))[0] == "table1_id"


def test_id_with_pulse_or_record_is_a_usage_error(capsys):
    with pytest.raises(SystemExit) as info:
        build_parser().parse_args(["simulate", *BLOCK, "--pulse", "rect", "--id", "NOR94-RRS"])
    assert info.value.code == 2 and "not allowed with argument" in capsys.readouterr().err


@pytest.fixture()
def e04_records(tmp_path):
    """Two synthetic components (140 and 230) of the Table 1 row IMV79-E04 in a records directory."""
    t = np.arange(0.0, 20.0, 0.01)
    acc = mp_acceleration(t, 0.8, 1.0 / 1.6, math.pi / 2, 2.0, 6.0)
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


def test_excitation_from_args_returns_the_component_chosen(e04_records):
    argv = ["simulate", *BLOCK, "--id", "IMV79-E04", "--records", str(e04_records), "--pga", "0.3"]
    a = build_parser().parse_args(argv)
    loaded = excitation_from_args(a, amplitude=True)
    assert isinstance(loaded, LoadedExcitation)
    assert isinstance(loaded.excitation, GroundMotion) and loaded.source is not None
    assert loaded.choice is not None and loaded.choice.component
    assert loaded.scale == pytest.approx(0.3 / loaded.excitation.pga_g)
    assert not hasattr(a, "_choice")  # no state left on the namespace
    b = build_parser().parse_args(["simulate", *BLOCK, "--pulse", "rect", "--td", "1", "--pga", "0.2"])
    pulse = excitation_from_args(b, amplitude=True)
    assert pulse == LoadedExcitation(Pulse("rect", 1.0, 0.2), 1.0, None, None)


def test_simulate_by_id_reports_the_component(capsys, e04_records):
    argv = ["simulate", *BLOCK, "--id", "IMV79-E04", "--records", str(e04_records), "--pga", "0.3", "--json"]
    assert main(argv) == 0, capsys.readouterr().err
    out = json.loads(capsys.readouterr().out)
    assert out["id"] == "IMV79-E04" and out["pga_g"] == 0.3 and "component" in out and "record" in out
    assert main(argv[:-1]) == 0
    text = capsys.readouterr().out
    assert "component: " in text
    # the PGA applied is --pga, labelled apart from the record's own PGA and the factor
    own = out["record_pga_g"]
    assert abs(own - 0.3) > 0.01 and out["scale"] == pytest.approx(0.3 / own, rel=1e-12)
    assert f"PGA applied: 0.3 g (record's own PGA {own:.4g} g x scale factor {0.3 / own:.4g})" in text
