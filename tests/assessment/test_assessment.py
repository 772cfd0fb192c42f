"""The assessment core (isorock.assessment.stripes): stripe runs equal single analyses, stripe counts and
displacement statistics, fragility at the design levels, the design search and its recommendation."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from isorock import G, GroundMotion, LinearIsolation, NoIsolation, System
from isorock.assessment.design import design_table, recommend
from isorock.assessment.stripes import (
    AssessedObject,
    design_level_rows,
    fragility_rows,
    run_levels,
    stripe_table,
)
from isorock.engine import simulate


def _record(seed: int, pga_g: float = 0.4) -> GroundMotion:
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, 12.0, 0.01)
    a = np.sin(2 * np.pi * (0.6 + 0.4 * rng.random()) * t) * np.exp(-(((t - 4.0) / 1.5) ** 2))
    a += 0.3 * rng.standard_normal(t.size) * np.sin(np.pi * t / t[-1]) ** 2
    return GroundMotion(0.01, a / np.abs(a).max() * pga_g * G, f"synthetic-{seed}")


STATUE = AssessedObject.from_config({"name": "statue", "height_m": 1.8, "width_m": 0.6, "friction": 0.5})


def test_object_geometry():
    assert STATUE.lam == pytest.approx(3.0) and STATUE.R_m == pytest.approx(0.5 * math.hypot(1.8, 0.6))
    o = AssessedObject.from_config({"name": "x", "lambda": 4.0, "R_m": 1.2, "friction": 0.4})
    assert (o.lam, o.R_m, o.height_m) == (4.0, 1.2, None)
    assert o.columns()["tan_alpha"] == pytest.approx(0.25)


def test_stripe_runs_are_the_single_analyses():
    """Every row of run_levels is simulate() of the record scaled to the level (full run)."""
    gm = _record(1)
    systems = [System(STATUE.block(), NoIsolation()), System(STATUE.block(), LinearIsolation(2.5, 0.2, 0.5))]
    levels = [0.2, 0.5, 0.9]
    runs = run_levels(systems, gm, levels, STATUE.friction)
    assert len(runs) == 6
    for r in runs.itertuples():
        one = simulate(systems[r.system], gm, scale=r.pga_g / gm.pga_g)
        assert r.outcome == one.outcome
        assert r.max_theta_over_alpha == one.max_theta_over_alpha
        assert r.max_base_disp_m == one.max_base_disp_m
        assert r.mu_required == one.mu_required and r.min_normal_over_weight == one.min_normal_over_weight
        assert r.outside_model == one.outside_model(STATUE.friction)


def _fake_runs() -> pd.DataFrame:
    """Three stripes of four records with known outcomes and displacements."""
    rows = []
    outcomes = {0.1: [0, 0, 0, 1], 0.3: [0, 1, 2, 1], 0.6: [2, 2, 1, 2]}
    for x, codes in outcomes.items():
        for k, c in enumerate(codes):
            rows.append({"system": 0, "pga_g": x, "outcome_code": c, "max_base_disp_m": x * (k + 1) / 4,
                         "outside_model": k == 3 and x == 0.6})  # fmt: skip
    return pd.DataFrame(rows)


def test_stripe_table_counts_and_displacement():
    st = stripe_table(_fake_runs(), capacity_m=0.2)
    assert list(st["n_records"]) == [4, 4, 4]
    assert list(st["n_overturn"]) == [0, 1, 3] and list(st["n_uplift"]) == [1, 3, 4]
    d = np.array([0.3 * (k + 1) / 4 for k in range(4)])
    assert st.loc[1, "disp_median_m"] == pytest.approx(np.median(d))
    assert st.loc[1, "disp_p84_m"] == pytest.approx(np.percentile(d, 84))
    assert list(st["n_exceed_capacity"]) == [0, 2, 3] and list(st["n_outside_model"]) == [0, 0, 1]


def test_design_levels_use_the_fitted_fragility():
    runs = _fake_runs()
    st = stripe_table(runs, 0.2)
    fr = fragility_rows(st)
    fits = {r["damage"]: r["_fit"] for r in fr}
    (dl,) = design_level_rows(st, runs[runs["pga_g"] == 0.3], fits, [0.3], 0.2)
    assert dl["p_overturn"] == pytest.approx(fits["overturn"].probability(0.3))
    assert dl["p_overturn_observed"] == 0.25 and dl["frac_exceed_capacity"] == 0.5


def test_design_search_recommends_the_safest_isolator_within_capacity():
    gm_runs = []
    isos = [LinearIsolation(1.5, 0.1, 0.5), LinearIsolation(3.0, 0.1, 0.5), LinearIsolation(3.0, 0.4, 0.5)]
    # isolator 1 never overturns but moves too far; isolator 2 rarely overturns within capacity
    for si, (n_ov, disp) in enumerate([(2, 0.10), (0, 0.50), (1, 0.20)]):
        for x in (0.1, 0.3, 0.6):
            for k in range(4):
                over = x >= 0.3 and k < (n_ov if x == 0.3 else n_ov + 1)
                gm_runs.append({"system": si, "pga_g": x, "outcome_code": 2 if over else 1,
                                "max_base_disp_m": disp * x / 0.3, "outside_model": False})  # fmt: skip
    d = design_table(pd.DataFrame(gm_runs), isos, [0.1, 0.3, 0.6], [0.3], capacity_m=0.3)
    ranked = recommend(d)
    assert list(ranked["within_capacity"]) == [True, False, True]
    assert list(ranked["rank"]) == [2, 0, 1]  # isolator 2: P(overturn) below isolator 0's, within capacity
