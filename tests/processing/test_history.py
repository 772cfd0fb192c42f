"""Structured provenance of processing: one AppliedStep per step, its line, its JSON, and old lines read
back (isorock.processing.history)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from obspy import Trace

from isorock import __version__
from isorock.processing import (
    STEPS,
    AppliedStep,
    applied_steps,
    default_config,
    parse_history,
    process,
    steps_from_json,
    steps_to_json,
)


def _quake(n=3000, dt=0.01) -> Trace:
    t = np.arange(n) * dt
    acc = 2.0 * np.sin(2 * np.pi * 1.2 * t) * np.exp(-0.3 * t) * np.minimum(t, 1.0) + 0.01
    return Trace(acc, header={"delta": dt})


def test_every_step_is_recorded_once_with_its_line():
    raw = _quake()
    out = process(raw)
    steps = applied_steps(out)
    assert [s.step for s in steps] == [s.name for s in default_config().steps]  # check_pga twice, ...
    assert [s.line() for s in steps] == list(out.stats.processing)
    assert applied_steps(raw) == []  # the input is not changed
    assert steps[1] == AppliedStep("detrend", {"type": "linear"}, steps[1].note)
    assert steps[1].note.startswith("mean before") and steps[1].note.endswith("m/s^2")
    bp = next(s for s in steps if s.step == "bandpass_filter")
    assert bp.parameters == {"freqmin": 0.05, "freqmax": 40.0, "corners": 4, "zerophase": True, "pad": True}
    assert applied_steps(out.copy()) == steps


def test_obspy_lines_are_folded_into_the_step():
    tr = _quake()
    STEPS["resample"](tr, dt=0.02)
    (step,) = applied_steps(tr)
    assert tr.stats.processing == [step.line()]  # ObsPy's own lines of filter and interpolate replaced
    assert step.parameters == {"dt": 0.02, "method": "lanczos"} and "-> 0.02 s" in step.note


def test_line_json_and_numpy_values():
    s = AppliedStep("taper", {"type": "hann", "max_percentage": np.float64(0.05), "max_length": None}, "x")
    assert type(s.parameters["max_percentage"]) is float
    assert s.line("9.9") == "isorock 9.9: taper(type='hann', max_percentage=0.05, max_length=None): x"
    assert AppliedStep("resample", {"dt": None}).line("1") == "isorock 1: resample(dt=None)"
    assert steps_from_json(steps_to_json([s])) == [s]
    assert s.to_dict() == {"step": "taper", "parameters": s.parameters, "note": "x"}


def test_parse_history_reads_the_lines_back():
    out = process(_quake())
    steps = applied_steps(out)
    parsed = parse_history(out.stats.processing)
    assert [(p.step, p.note) for p in parsed] == [(s.step, s.note) for s in steps]
    for p, s in zip(parsed, steps, strict=True):
        assert p.parameters == {
            k: pytest.approx(v) if isinstance(v, float) else v for k, v in s.parameters.items()
        }


def test_parse_history_leaves_out_what_is_not_a_step():
    lines = [
        "isorock: rotate_horizontal(140, 230 -> 53 deg)",
        "ObsPy 1.4.1: detrend(options={}::type='linear')",
        f"isorock {__version__}: check_pga(min_g=0.001, max_g=inf): PGA 0.3 g passed",
        "isorock 0.1.0: no_such_step(x=1)",
        "isorock 0.1.0: check_tail(duration=5, max_vel_ratio=nan, max_dis_ratio=-1e-05)",
    ]
    a, b = parse_history(lines)
    assert (a.step, a.parameters, a.note) == (
        "check_pga",
        {"min_g": 0.001, "max_g": math.inf},
        "PGA 0.3 g passed",
    )
    assert b.step == "check_tail" and b.note == "" and math.isnan(b.parameters["max_vel_ratio"])
    assert b.parameters["max_dis_ratio"] == -1e-05
