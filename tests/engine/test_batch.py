"""The engine's batch interface (:func:`isorock.physics.engine.run_many`) against one analysis at a time.

The batch runs the same compiled kernel in parallel threads; every decoded field must equal, bit for
bit, what :func:`isorock.physics.engine.simulate` gives for the same system, excitation and scale.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from isorock import Block, FPIsolation, GroundMotion, LinearIsolation, NoIsolation, Pulse, System
from isorock.physics.engine import BatchResult, run_many, simulate

FIELDS = (
    "max_theta_over_alpha",
    "n_impacts",
    "max_base_disp_m",
    "t_end_s",
    "decided",
    "n_steps",
    "stalls",
    "mu_required",
    "min_normal_over_weight",
    "jumps",
)


def _systems() -> list[System]:
    blocks = [Block.from_lambda_R(4.0, 1.0), Block.from_lambda_R(2.5, 0.6), Block.from_lambda_R(6.0, 2.0)]
    isos = [
        NoIsolation(),
        LinearIsolation(Tb=3.0, xi_b=0.2, rho=0.5),
        FPIsolation.from_period(0.08, 2.5, 0.7),
    ]
    return [System(b, i) for b in blocks for i in isos]


def _record() -> GroundMotion:
    rng = np.random.default_rng(7)
    a = np.convolve(rng.standard_normal(800), np.hanning(25), mode="same") * np.hanning(800)
    return GroundMotion(0.01, a / np.max(np.abs(a)) * 3.0)


@pytest.mark.parametrize("early_stop", [False, True])
@pytest.mark.parametrize("exc", [Pulse("fullsine", 0.6, 1.0), _record()], ids=["pulse", "record"])
def test_run_many_equals_simulate_bit_for_bit(exc, early_stop):
    systems = _systems()
    scales = np.linspace(0.2, 1.4, len(systems))
    batch = run_many(systems, exc, scales, early_stop=early_stop, threads=2)
    assert isinstance(batch, BatchResult) and len(batch) == len(systems)
    outcomes = set()
    for i, (s, k) in enumerate(zip(systems, scales, strict=True)):
        one = simulate(s, exc, scale=float(k), early_stop=early_stop)
        assert batch.outcome[i] == one.outcome
        outcomes.add(one.outcome)
        for f in FIELDS:
            assert getattr(batch, f)[i] == getattr(one, f), (i, f)
        t_up = batch.t_uplift_s[i]
        assert (one.t_uplift_s is None and math.isnan(t_up)) or t_up == one.t_uplift_s
    assert len(outcomes) >= 2  # the cases are not all alike


def test_run_many_broadcasts_one_scale_and_chunks_with_progress():
    systems = _systems()
    done = []
    a = run_many(systems, Pulse("halfsine", 0.4, 1.0), 0.8, chunk=4, progress=done.append)
    b = run_many(systems, Pulse("halfsine", 0.4, 1.0), [0.8] * len(systems))
    assert done == [4, 4, 1]
    for f in ("outcome_code", *FIELDS):
        assert np.array_equal(getattr(a, f), getattr(b, f))


def test_run_many_empty_and_mismatched_scales():
    assert len(run_many([], Pulse("rect", 0.3, 1.0), 1.0)) == 0
    with pytest.raises(ValueError):
        run_many(_systems()[:3], Pulse("rect", 0.3, 1.0), [1.0, 2.0])
