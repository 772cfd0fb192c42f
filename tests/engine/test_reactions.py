"""Contact reactions and the validity of the model (docs/model.md §15): ``mu_required``, the peak ratio
of the horizontal to the normal contact force, and ``min_normal_over_weight``.

Closed forms in full contact (fixed base: the ground acceleration in g; isolated base: the total base
acceleration in g, after the input too), and the rocking regime against reactions computed from the
scipy oracle's trajectory with the oracle's own equations.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from isorock import Block, FPIsolation, G, GroundMotion, LinearIsolation, NoIsolation, Pulse, System
from isorock.engine import max_contact_acceleration, simulate
from isorock.engine.oracle import OracleModel, simulate_trace
from isorock.engine.oracle.model import Segment, input_segments


def _record(pga_g: float) -> GroundMotion:
    t = np.arange(0.0, 8.0, 0.01)
    a = np.sin(2 * np.pi * 1.3 * t) * np.exp(-(((t - 3.0) / 1.5) ** 2)) + 0.3 * np.sin(2 * np.pi * 4.1 * t)
    a *= np.sin(np.pi * t / t[-1]) ** 2
    return GroundMotion(0.01, a / np.abs(a).max() * pga_g * G)


# ------------------------------------------------------------------ full contact: closed forms
@pytest.mark.parametrize(
    "exc, pga_g",
    [(Pulse("halfsine", 0.5, 0.1), 0.1), (Pulse("rect", 0.3, 0.2), 0.2), (Pulse("fullsine", 0.2, 0.15), 0.15),
     (_record(0.2), 0.2)],
    ids=["halfsine", "rect", "fullsine", "record"],
)  # fmt: skip
def test_fixed_base_in_full_contact_needs_the_ground_acceleration_in_g(exc, pga_g):
    """No uplift on a fixed base: the block moves with the ground, H / N = |x_g''| / g."""
    sysm = System(Block.from_lambda_R(4.0, 1.0), NoIsolation())  # tan(alpha) = 0.25
    r = simulate(sysm, exc)
    assert r.outcome == "no_uplift"
    assert r.mu_required == pytest.approx(pga_g, rel=1e-12)
    assert r.min_normal_over_weight == 1.0


@pytest.mark.parametrize(
    "iso, exc",
    [(LinearIsolation(3.0, 0.2, 0.5), Pulse("halfsine", 0.5, 0.1)),
     (LinearIsolation(2.0, 0.05, 1.0), Pulse("rect", 0.2, 0.15)),
     (LinearIsolation(2.5, 0.3, 0.5), _record(0.3)),
     (FPIsolation(0.05, 2.24, 0.5), Pulse("fullsine", 0.3, 1.0))],
    ids=["linear-halfsine", "linear-rect", "linear-record", "fp-fullsine"],
)  # fmt: skip
def test_isolated_base_in_full_contact_needs_the_total_base_acceleration_in_g(iso, exc):
    """No uplift on an isolated base: H / N = |A| / g with A the total base acceleration, whose peak
    the no-uplift run of the same system gives, the free vibration after the input included."""
    sysm = System(Block.from_lambda_R(4.0, 1.0), iso)
    r = simulate(sysm, exc)
    assert r.outcome == "no_uplift"
    assert r.mu_required == pytest.approx(max_contact_acceleration(sysm, exc) / G, rel=1e-6)
    assert r.min_normal_over_weight == 1.0


def test_the_peak_after_the_input_ends_is_not_cut_short():
    """Linear isolator, 0.1 s rectangular pulse: |A| peaks in the free vibration after the pulse (the
    isolator force keeps growing while the base swings out), and a full run reports that peak."""
    sysm = System(Block.from_lambda_R(4.0, 1.0), LinearIsolation(3.0, 0.1, 0.5))
    exc = Pulse("rect", 0.1, 0.2)
    r = simulate(sysm, exc, histories=True)
    assert r.outcome == "no_uplift"
    k = LinearIsolation(3.0, 0.1, 0.5)
    w = 2 * math.pi / k.Tb
    a_during = np.abs(w**2 * r.u + 2 * k.xi_b * w * r.u_dot)[r.t <= exc.td].max() / G
    assert r.mu_required > 2.0 * a_during  # the peak comes after the input
    assert r.mu_required == pytest.approx(max_contact_acceleration(sysm, exc) / G, rel=1e-6)
    assert r.t_end_s > exc.td


# ------------------------------------------------------------------ rocking: against the oracle
def _oracle_reactions(system: System, exc) -> tuple[str, float, float]:
    """Peak |H| / N and least N / (m g) from the oracle's trajectory and equations, the fall after
    the last passage below |theta| = alpha of an overturning block left out (as the engine does)."""
    res, tr = simulate_trace(system, exc, histories=True)
    m = OracleModel(system)
    segs = input_segments(exc)
    blk = system.block
    n = len(tr.t)
    if res.outcome == "overturn":
        n = int(np.nonzero(np.abs(tr.y[:, 2]) <= blk.alpha)[0][-1]) + 1
    mu, n_min = 0.0, 1.0
    for t, y, side, regime in zip(tr.t[:n], tr.y[:n], tr.side[:n], tr.regime[:n], strict=True):
        seg = next((sg for sg in segs if sg.t0 <= t <= sg.t1), Segment(segs[-1].t1, math.inf))
        if regime == 0:
            mu = max(mu, abs(m.total_acc_contact(t, y, seg)) / G)
            continue
        d = m.rhs_rocking(t, y, seg, int(side))
        th, w = y[2], y[3]
        c = blk.h * math.cos(th) + side * blk.b * math.sin(th)
        s = side * blk.b * math.cos(th) - blk.h * math.sin(th)
        h = seg.acc(t) + d[1] + c * d[3] + s * w * w
        nz = G + s * d[3] - c * w * w
        n_min = min(n_min, nz / G)
        mu = math.inf if nz <= 0 else max(mu, abs(h) / nz)
    return res.outcome, mu, n_min


@pytest.mark.parametrize(
    "system, exc",
    [(System(Block.from_lambda_R(4, 1.0), NoIsolation()), Pulse("halfsine", 0.5, 0.4)),
     (System(Block.from_lambda_R(4, 1.0), NoIsolation()), Pulse("rect", 0.3, 0.5)),
     (System(Block.from_lambda_R(6, 2.0), NoIsolation()), Pulse("fullsine", 0.4, 0.6)),
     (System(Block.from_lambda_R(4, 1.0), LinearIsolation(2, 0.2, 0.5)), Pulse("fullsine", 0.3, 1.0)),
     (System(Block.from_lambda_R(3, 0.5), LinearIsolation(3, 0.1, 1.0)), Pulse("halfsine", 0.2, 2.0)),
     (System(Block.from_lambda_R(4, 1.0), FPIsolation(0.02, 2.24, 0.5)), Pulse("fullsine", 0.3, 1.5)),
     (System(Block.from_lambda_R(3, 1.0), NoIsolation()), Pulse("fullsine", 0.05, 6.0))],
    ids=["none-rocks", "none-rect-overturns", "none-fullsine", "linear-fullsine", "linear-halfsine",
         "fp-fullsine", "none-jumps"],
)  # fmt: skip
def test_rocking_reactions_match_the_oracle(system, exc):
    outcome, mu, n_min = _oracle_reactions(system, exc)
    r = simulate(system, exc, rtol=1e-10, atol=1e-12)
    assert r.outcome == outcome
    assert r.min_normal_over_weight == pytest.approx(n_min, abs=0.01)
    if math.isinf(mu):
        assert math.isinf(r.mu_required) and r.min_normal_over_weight < 0.0  # the block would jump
    else:
        # both sample the peak at their steps: agreement to the sampling
        assert r.mu_required == pytest.approx(mu, rel=3e-3)


def test_outside_model_flags_sliding_and_jumping():
    sysm = System(Block.from_lambda_R(3, 1.0), NoIsolation())
    jumps = simulate(sysm, Pulse("fullsine", 0.05, 6.0))
    assert jumps.outcome == "rocking" and jumps.outside_model(friction=10.0)  # N < 0: no friction holds it
    slow = simulate(sysm, Pulse("halfsine", 0.5, 0.2))
    assert slow.mu_required == pytest.approx(0.2)
    assert not slow.outside_model(friction=0.5) and slow.outside_model(friction=0.15)
