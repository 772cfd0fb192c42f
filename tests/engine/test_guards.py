"""Zero-progress guards of the engine.

The uplift test refuses an uplift after 1000 impacts in a row at one instant, and counts it; the
contact step at a grazing uplift threshold is lengthened so that time advances.

An uplift-amplitude bisection drives the scale factor to the value at which the peak isolator
force just touches ``g tan(alpha)``: there the Runge-Kutta step kept being cut a round-off
distance ahead of the start (41 million steps, 95 s for one analysis of a 30 s record before the
guard; a few thousand steps with it).
"""

from __future__ import annotations

import pytest

from isorock import Block, FPIsolation, G, Pulse, System
from isorock.physics.engine import pack_parameters, simulate
from isorock.physics.engine._contact import _uplift_check
from isorock.records.directory import sample_records
from isorock.records.motion import load_motion

# far above the ~3,000 steps of an ordinary uplift analysis of this record, far below a stall
MAX_STEPS = 200_000


def _duzce():
    for rec in sample_records():
        if rec.name.startswith("Duzce_1999_375-090"):
            return load_motion(rec.path, format=rec.format)
    pytest.fail("pyslammer's Duzce 1999 sample record (a test dependency) is missing")


def test_uplift_bisection_to_round_off_makes_progress():
    """Every run of a bisection on the onset of uplift, to the last bit, ends in few steps."""
    unit = _duzce().with_pga(1.0)
    system = System(Block.from_lambda_R(4.0, 4.125), FPIsolation(0.11, 2.24, 0.5))
    lo, hi = 3.0, 5.0
    first = {}
    for a in (lo, hi):
        first[a] = simulate(system, unit, scale=a, stop_at_uplift=True, early_stop=True)
    assert first[lo].t_uplift_s is None and first[hi].t_uplift_s is not None
    runs = 0
    while True:
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        r = simulate(system, unit, scale=mid, stop_at_uplift=True, early_stop=True)
        runs += 1
        assert r.n_steps < MAX_STEPS, f"scale {mid!r}: {r.n_steps} steps"
        if r.t_uplift_s is not None:
            hi = mid
        else:
            lo = mid
    assert runs > 40  # the bisection did reach the threshold to round-off
    up = simulate(system, unit, scale=hi, stop_at_uplift=True, early_stop=True)
    assert up.t_uplift_s is not None and up.n_steps < MAX_STEPS


def test_uplift_refused_after_1000_stalled_impacts_is_counted():
    """At |A| above g tan(alpha) the block uplifts, unless 1000 impacts have stalled at that instant."""
    system = System(Block.from_lambda_R(4.0, 1.0), FPIsolation(0.08, 2.24, 0.5))
    P, _, _ = pack_parameters(system, Pulse("rect", 1.0, 0.0))
    P = tuple(float(x) for x in P)
    thr = G * system.block.tan_alpha  # [m/s^2]
    u = -1.01 * thr / system.isolation.kb  # base displaced so that |A| = kb |u| + mu g > g tan(alpha)
    for stall, up, refused in ((0, True, False), (999, True, False), (1000, False, True)):
        got = _uplift_check(0.0, u, 0.0, -1.0, 0, 0.0, 0.0, 0.0, 0.0, stall, P)
        assert (got[0], got[3]) == (up, refused)
        # the peak |A| in full contact: the threshold at an uplift (contact holds no more than that,
        # docs/model.md §15), the whole |A| where the guard keeps the block in contact
        assert got[2] == thr if up else got[2] > thr
