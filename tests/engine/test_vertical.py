"""Vertical ground motion in the rocking and sliding engine (docs/model.md §17, issue 24).

* A constant vertical acceleration ``a_v`` is gravity ``g + a_v``: every result equals that of the
  kernel run with the scaled gravity (and, for the friction pendulum, its forces scaled with it).
* The uplift (and slip) threshold is ``(g + a_v) tan(alpha)`` (``mu (g + a_v)``) at the instant
  itself: on ramps of both components the engine's uplift time equals the exact crossing.
* A vertical of zeros gives the horizontal-only answer (the vertical path against the exact one).
* ``g + a_v < 0`` during rocking is a jump.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from isorock import Block, FPIsolation, LinearIsolation, NoIsolation, System
from isorock.constants import G
from isorock.physics.engine import _result, pack_parameters, simulate
from isorock.physics.engine import kernel as K
from isorock.physics.excitation import GroundMotion

DT = 0.002
T_REC = 25.0
TD = 0.5
BASES = {
    "none": NoIsolation(),
    "linear": LinearIsolation(Tb=2.5, xi_b=0.1, rho=0.8),
    "fp": FPIsolation.from_period(mu_b=0.06, Tb=3.0, rho=0.8),
}


def _pulse_record(amp_g: float) -> np.ndarray:
    """A half-sine of ``amp_g`` [g] for ``TD`` seconds, then rest to ``T_REC`` (the motion ends inside it)."""
    t = np.arange(0.0, T_REC, DT)
    return np.where(t < TD, amp_g * G * np.sin(np.pi * t / TD), 0.0)


def _scaled_gravity(system: System, motion: GroundMotion, av: float, **kw):
    """The kernel run horizontal-only with gravity ``g + av`` (and the FP's forces following it)."""
    P, ekind, acc = pack_parameters(system, motion.horizontal_only(), **kw)
    ratio = (G + av) / G
    P[K.P_G] = G + av
    P[K.P_THR] = P[K.P_THR] * ratio
    if system.isolation.kind == "fp":
        P[K.P_KB] *= ratio
    return _result(*K.run(P, ekind, acc, False), histories=False, sliding=P[K.P_SLIDE] != 0.0)


@pytest.mark.parametrize("kind", sorted(BASES))
@pytest.mark.parametrize("amp_g", [0.5, 0.8, 1.5])
@pytest.mark.parametrize("av_g", [-0.3, 0.25])
def test_constant_vertical_is_scaled_gravity(kind, amp_g, av_g):
    system = System(Block.from_lambda_R(3.0, 1.0), BASES[kind])
    acc = _pulse_record(amp_g)
    motion = GroundMotion(DT, acc, "pulse", vertical=np.full(acc.size, av_g * G))
    got = simulate(system, motion)
    ref = _scaled_gravity(system, motion, av_g * G)
    assert got.outcome == ref.outcome
    assert got.n_impacts == ref.n_impacts
    assert math.isclose(got.max_theta_over_alpha, ref.max_theta_over_alpha, rel_tol=1e-6, abs_tol=1e-9)
    assert math.isclose(got.max_base_disp_m, ref.max_base_disp_m, rel_tol=1e-6, abs_tol=1e-12)
    if ref.t_uplift_s is None:
        assert got.t_uplift_s is None
    else:
        # the FP path with a vertical is Runge-Kutta where the horizontal-only one is a Taylor series
        tol = 1e-4 if kind == "fp" else 1e-9
        assert abs(got.t_uplift_s - ref.t_uplift_s) <= tol


@pytest.mark.parametrize("kind", sorted(BASES))
def test_constant_vertical_sliding_is_scaled_gravity(kind):
    system = System(Block.from_lambda_R(1.5, 0.8), BASES[kind])
    acc = _pulse_record(0.6)
    av = -0.2 * G
    motion = GroundMotion(DT, acc, "pulse", vertical=np.full(acc.size, av))
    got = simulate(system, motion, friction=0.25)
    ref = _scaled_gravity(system, motion, av, friction=0.25)
    assert got.mode == ref.mode == "sliding"
    assert got.n_slips == ref.n_slips
    assert math.isclose(got.sliding_peak_m, ref.sliding_peak_m, rel_tol=1e-6)
    assert math.isclose(got.sliding_residual_m, ref.sliding_residual_m, rel_tol=1e-6, abs_tol=1e-9)


@pytest.mark.parametrize("rate_h, rate_v", [(2.0, -3.0), (2.0, 4.0), (-1.5, 1.0)])
def test_uplift_threshold_follows_vertical_to_the_sample(rate_h, rate_v):
    """x_g'' = rate_h t, a_v = rate_v t: uplift where |rate_h| t = (g + rate_v t) tan(alpha), exactly."""
    block = Block.from_lambda_R(4.0, 1.0)
    t = np.arange(0.0, 5.0, 0.01)
    motion = GroundMotion(0.01, rate_h * t, "ramp", vertical=rate_v * t)
    res = simulate(System(block, NoIsolation()), motion, stop_at_uplift=True)
    exact = G * block.tan_alpha / (abs(rate_h) - rate_v * block.tan_alpha)
    assert res.t_uplift_s == pytest.approx(exact, abs=1e-12)
    # and the horizontal-only threshold g tan(alpha) is a different instant
    flat = simulate(System(block, NoIsolation()), motion.horizontal_only(), stop_at_uplift=True)
    assert abs(flat.t_uplift_s - exact) > 1e-3


@pytest.mark.parametrize("kind", sorted(BASES))
def test_slip_threshold_follows_vertical(kind):
    """Slip starts where |A| = mu (g + a_v): on the fixed base exactly at the crossing of the ramps."""
    block = Block.from_lambda_R(1.5, 0.8)
    t = np.arange(0.0, 5.0, 0.01)
    motion = GroundMotion(0.01, 2.0 * t, "ramp", vertical=-1.0 * t)
    res = simulate(System(block, BASES[kind]), motion, friction=0.2)
    assert res.mode == "sliding" and res.n_slips >= 1
    if kind == "none":
        assert res.t_first_slip_s == pytest.approx(0.2 * G / (2.0 + 1.0 * 0.2), abs=1e-12)


@pytest.mark.parametrize("kind", sorted(BASES))
def test_zero_vertical_equals_horizontal_only(kind):
    system = System(Block.from_lambda_R(3.0, 1.0), BASES[kind])
    acc = _pulse_record(0.8)
    plain = GroundMotion(DT, acc, "pulse")
    zero = GroundMotion(DT, acc, "pulse", vertical=np.zeros(acc.size))
    a, b = simulate(system, plain), simulate(system, zero)
    assert a.outcome == b.outcome and a.n_impacts == b.n_impacts
    assert math.isclose(a.max_theta_over_alpha, b.max_theta_over_alpha, rel_tol=1e-6)
    assert math.isclose(a.max_base_disp_m, b.max_base_disp_m, rel_tol=1e-6)


def test_vertical_below_minus_g_is_a_jump():
    """A downward vertical beyond g while the block rocks: the normal force vanishes."""
    system = System(Block.from_lambda_R(3.0, 1.0), NoIsolation())
    t = np.arange(0.0, 10.0, DT)
    acc = np.where(t < TD, 0.5 * G * np.sin(np.pi * t / TD), 0.0)
    av = np.where((t > 0.3) & (t < 0.4), -1.3 * G, 0.0)
    res = simulate(system, GroundMotion(DT, acc, "jump", vertical=av))
    assert res.jumps
    calm = simulate(system, GroundMotion(DT, acc, "calm", vertical=0.2 * av))
    assert not calm.jumps


def test_vertical_must_match_the_horizontal():
    with pytest.raises(ValueError, match="same instants"):
        GroundMotion(0.01, np.zeros(100), "x", vertical=np.zeros(99))


@pytest.mark.parametrize("kind", sorted(BASES))
@pytest.mark.parametrize("friction", [None, 0.3])
def test_a_vertical_below_minus_g_is_a_jump_in_every_mode(kind, friction):
    """g + a_v = -0.5 g for 0.1 s lifts the object off, rocking or sliding, on every base: the normal
    force g + a_v (in full contact and while sliding) or that of the rocking block goes below 0."""
    block = Block.from_lambda_R(1.5 if friction else 3.0, 0.8 if friction else 1.0)
    t = np.arange(0.0, 10.0, DT)
    acc = np.where(t < TD, 0.5 * G * np.sin(np.pi * t / TD), 0.0)
    av = np.where((t > 0.3) & (t < 0.4), -1.5 * G, 0.0)
    res = simulate(System(block, BASES[kind]), GroundMotion(DT, acc, "lift", vertical=av), friction=friction)
    assert res.jumps and res.min_normal_over_weight <= -0.4
    assert res.to_dict()["mu_required"] is None  # not defined once the object leaves its base
    calm = simulate(
        System(block, BASES[kind]), GroundMotion(DT, acc, "calm", vertical=0.5 * av), friction=friction
    )
    assert not calm.jumps and calm.min_normal_over_weight == pytest.approx(0.25, abs=0.05)


@pytest.mark.parametrize("kind", ["none", "linear"])
def test_uplift_amplitude_with_a_vertical_brackets_the_first_uplift(kind):
    """With a vertical the uplift PGA is no longer g tan(alpha) / max|A_1|: the search finds it by
    bisection, and the runs just below and above it agree."""
    from isorock.physics.overturning import uplift_amplitude

    block = Block.from_lambda_R(4.0, 1.0)
    t = np.arange(0.0, 8.0, DT)
    a = np.sin(2 * np.pi * 1.0 * t) * np.exp(-(((t - 3.0) / 1.0) ** 2))
    motion = GroundMotion(DT, a * G, "pkt", vertical=-0.3 * a * G)  # downward where the horizontal pushes
    system = System(block, BASES[kind])
    up, _ = uplift_amplitude(system, motion)
    flat, _ = uplift_amplitude(system, motion.horizontal_only())
    assert abs(up / flat - 1) > 0.01  # the vertical moves it
    for x, lifts in ((up * 0.999, False), (up * 1.001, True)):
        r = simulate(system, motion.with_pga(x), stop_at_uplift=True, early_stop=True)
        assert (r.t_uplift_s is not None) == lifts, x
