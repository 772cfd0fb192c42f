"""The engine's rigid body against the independent scipy integrator of the general body
(``tests/engine/body_oracle.py``, written apart from the engine): outcome and impact count equal, peaks
within 1e-6, on the fixed, linear and friction-pendulum bases, pulses and a sampled record, both
polarities (issue 34; docs/model.md §18, docs/validation.md)."""

from __future__ import annotations

import numpy as np
import pytest

from isorock import FPIsolation, GroundMotion, LinearIsolation, NoIsolation, Pulse, System
from isorock.physics.body import RigidBody
from isorock.physics.engine import simulate
from support.modules import load_beside

bo = load_beside(__file__, "body_oracle")

BODY = RigidBody(b_left=0.16, b_right=0.28, h_cg=0.72, r_gyration=0.42)
BASES = {
    "none": (NoIsolation(), ("none",)),
    "linear": (LinearIsolation(Tb=2.5, xi_b=0.15, rho=0.7), ("linear", 2.5, 0.15, 0.7)),
    "fp": (FPIsolation.from_period(mu_b=0.07, Tb=3.0, rho=0.7), None),
}


def _iso(kind: str):
    iso, tup = BASES[kind]
    if tup is None:
        tup = ("fp", iso.mu_b, iso.R_b, iso.rho, iso.Y, iso.beta, iso.gamma)
    return iso, tup


def _record() -> GroundMotion:
    rng = np.random.default_rng(11)
    acc = np.convolve(rng.standard_normal(600), np.exp(-0.5 * (np.arange(-20, 21) / 5.0) ** 2), "same")
    acc *= np.hanning(600)
    return GroundMotion(0.01, acc / np.abs(acc).max() * 9.81, name="synthetic")


CASES = [
    # (base, shape or "record", td [s], amplitude [g] or record scale, polarity): each with impacts
    ("none", "halfsine", 0.5, 0.30, 1.0),
    ("none", "fullsine", 0.6, 0.25, -1.0),
    ("none", "fullsine", 1.0, 0.30, 1.0),  # overturns after an impact
    ("none", "rect", 0.25, 0.35, 1.0),
    ("none", "record", None, 0.35, 1.0),
    ("linear", "halfsine", 0.8, 0.40, -1.0),
    ("linear", "fullsine", 1.0, 0.35, -1.0),  # overturns after 21 impacts
    ("linear", "rect", 0.25, 0.8, -1.0),
    ("linear", "record", None, 0.8, 1.0),
    ("fp", "halfsine", 0.5, 0.60, -1.0),
    ("fp", "fullsine", 0.6, 0.40, 1.0),
    ("fp", "halfsine", 0.8, 0.50, -1.0),  # overturns after 9 impacts
    ("fp", "rect", 0.25, 0.5, 1.0),
]


@pytest.mark.parametrize(("kind", "shape", "td", "amp", "pol"), CASES)
def test_engine_equals_oracle(kind, shape, td, amp, pol):
    iso, tup = _iso(kind)
    if shape == "record":
        gm = _record()
        res = simulate(System(BODY, iso), gm, scale=amp * pol)
        exc = (gm.dt, gm.acc * amp * pol)
    else:
        res = simulate(System(BODY, iso), Pulse(shape, td=td, amp=amp), scale=pol)
        fun, dur = bo.pulse_excitation(shape, td, amp * pol)
        exc = (fun, dur, [td]) if shape == "rect" else (fun, dur)
    t_end = res.t_end_s + (0.5 if res.outcome == "overturn" else 0.0)
    ref = bo.simulate_body(
        BODY.b_left, BODY.b_right, BODY.h_cg, BODY.r_gyration, isolation=tup, excitation=exc, t_end=t_end
    )
    assert res.outcome == ref["outcome"]
    assert res.n_impacts == ref["n_impacts"]
    assert res.max_theta_over_alpha == pytest.approx(ref["max_theta_over_alpha"], rel=1e-6, abs=1e-6)
    assert res.max_base_disp_m == pytest.approx(ref["max_base_disp"], rel=1e-6, abs=1e-9)
    if ref["t_uplift"] is not None:
        assert res.t_uplift_s == pytest.approx(ref["t_uplift"], abs=1e-6)


def test_cases_have_impacts_and_both_outcomes():
    # the comparison above means something only if the cases rock, impact and overturn
    outcomes, impacts = set(), 0
    for kind, shape, td, amp, pol in CASES:
        iso, _ = _iso(kind)
        if shape == "record":
            r = simulate(System(BODY, iso), _record(), scale=amp * pol)
        else:
            r = simulate(System(BODY, iso), Pulse(shape, td=td, amp=amp), scale=pol)
        outcomes.add(r.outcome)
        impacts += r.n_impacts > 0
    assert {"rocking", "overturn"} <= outcomes
    assert impacts >= 12


def _with_vertical() -> GroundMotion:
    gm = _record()
    rng = np.random.default_rng(5)
    av = np.convolve(rng.standard_normal(600), np.exp(-0.5 * (np.arange(-10, 11) / 3.0) ** 2), "same")
    av *= np.hanning(600)
    return GroundMotion(gm.dt, gm.acc, name="synthetic", vertical=av / np.abs(av).max() * 0.5 * 9.81)


@pytest.mark.parametrize(
    ("kind", "scale"),
    [("none", 0.35), ("none", -0.35), ("none", 0.5), ("none", 0.8), ("linear", 0.8), ("fp", 0.8)],
)
def test_engine_equals_oracle_with_a_vertical(kind, scale):
    # g + a_v in the rocking equation, the thresholds of both sides and the friction pendulum's force
    iso, tup = _iso(kind)
    gm = _with_vertical()
    res = simulate(System(BODY, iso), gm, scale=scale)
    assert res.outcome != "no_uplift" and not res.jumps
    t_end = res.t_end_s + (0.5 if res.outcome == "overturn" else 0.0)
    ref = bo.simulate_body(
        BODY.b_left,
        BODY.b_right,
        BODY.h_cg,
        BODY.r_gyration,
        isolation=tup,
        excitation=(gm.dt, gm.acc * scale),
        vertical=gm.vertical * scale,
        t_end=t_end,
    )
    assert (res.outcome, res.n_impacts) == (ref["outcome"], ref["n_impacts"])
    assert res.max_theta_over_alpha == pytest.approx(ref["max_theta_over_alpha"], rel=1e-6, abs=1e-6)
    assert res.max_base_disp_m == pytest.approx(ref["max_base_disp"], rel=1e-6, abs=1e-9)
    assert res.t_uplift_s == pytest.approx(ref["t_uplift"], abs=1e-6)
