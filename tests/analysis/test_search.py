"""The minimum-overturning search: honest resolution, and disagreements resolved by full runs."""

from __future__ import annotations

import pytest

import isorock.physics.overturning as assess_mod
from isorock import Block, NoIsolation, Pulse, System
from isorock.physics.engine import simulate as real_simulate
from isorock.physics.overturning import min_overturn_amplitude


def test_resolution_is_the_scan_step():
    system = System(Block.from_lambda_R(4.0, 1.0), NoIsolation())
    fine = min_overturn_amplitude(system, Pulse("fullsine", 0.5), growth=1.005)
    coarse = min_overturn_amplitude(system, Pulse("fullsine", 0.5), growth=1.05, rtol=1e-3)
    assert fine.resolution == pytest.approx(0.005) and coarse.resolution == pytest.approx(0.05)
    assert fine.bisection_width <= 1e-6 and coarse.bisection_width <= 1e-3
    # the coarse answer lies within its stated resolution of the fine one
    assert abs(coarse.min_overturn_g / fine.min_overturn_g - 1) <= coarse.resolution
    assert not fine.full_runs_only and fine.stalls == 0


def test_disagreeing_early_decision_is_resolved_by_full_runs(monkeypatch):
    """An early-stopped run that says 'overturn' where the full run does not must not raise: the search
    is run again with full runs only, and their answer is returned."""
    system = System(Block.from_lambda_R(4.0, 1.0), NoIsolation())
    pulse = Pulse("halfsine", 0.5)
    truth = min_overturn_amplitude(system, pulse)
    calls = {"early": 0, "full": 0}

    def lying(sysm, exc, *, scale=1.0, early_stop=False, **kw):
        calls["early" if early_stop else "full"] += 1
        res = real_simulate(sysm, exc, scale=scale, early_stop=early_stop, **kw)
        if early_stop and scale > 0.8 * truth.min_overturn_g:
            res.outcome = "overturn"  # a wrong early decision below the true minimum
        return res

    monkeypatch.setattr(assess_mod, "simulate", lying)
    m = min_overturn_amplitude(system, pulse)
    assert m.full_runs_only
    assert m.min_overturn_g == pytest.approx(truth.min_overturn_g, rel=1e-5)
    assert calls["full"] > 10  # the scan and the bisection ran again with full runs
