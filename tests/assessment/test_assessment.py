"""The assessment core (isorock.assessment): stripe runs equal single analyses, the failure modes per
stripe, runs outside the model, not-estimable fits reported with what was seen, intervals, the MCE
displacement statistic, and the design search: the floor as a candidate, the capacity at the MCE, the
edge of the grid."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from isorock import GroundMotion, LinearIsolation, NoIsolation, System
from isorock.assessment.case import Settings, displacement_statistic, evaluate
from isorock.assessment.design import Candidate, evaluate_candidates, rank
from isorock.assessment.fragility import clopper_pearson, resample_weights
from isorock.assessment.stripes import AssessedObject, outcome_matrices, run_levels, stripe_table
from isorock.physics.engine import simulate
from support.records import synthetic_record


def _record(seed: int, pga_g: float = 0.4) -> GroundMotion:
    return synthetic_record(seed, pga_g)


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
    runs = run_levels(systems, gm, levels, STATUE.friction, slide_allow_m=None)
    assert len(runs) == 6
    for r in runs.itertuples():
        one = simulate(systems[r.system], gm, scale=r.level / gm.pga_g)
        assert r.outcome == one.outcome
        assert r.max_theta_over_alpha == one.max_theta_over_alpha
        assert r.max_base_disp_m == one.max_base_disp_m
        assert r.mu_required == one.mu_required and r.min_normal_over_weight == one.min_normal_over_weight
        assert r.outside_model == one.outside_model(STATUE.friction)


def _fake_runs(isolated: bool = True) -> pd.DataFrame:
    """Three stripes of four records with known outcomes and displacements (record k moves k+1 quarters)."""
    rows = []
    outcomes = {0.1: [0, 0, 0, 1], 0.3: [0, 1, 2, 1], 0.6: [2, 2, 1, 2]}
    for x, codes in outcomes.items():
        for k, c in enumerate(codes):
            out = k == 3 and x == 0.6
            rows.append({"system": 0, "record": f"r{k}", "level": x, "outcome_code": c,
                         "max_base_disp_m": x * (k + 1) / 4 if isolated else 0.0,
                         "outside_model": out, "slides": out, "jumps": False})  # fmt: skip
    return pd.DataFrame(rows)


def test_stripe_table_counts_every_failure_mode():
    st = stripe_table(_fake_runs(), capacity_m=0.2)
    assert list(st["n_records"]) == [4, 4, 4]
    assert list(st["n_overturn"]) == [0, 1, 3] and list(st["n_uplift"]) == [1, 3, 4]
    d = np.array([0.3 * (k + 1) / 4 for k in range(4)])
    assert st.loc[1, "disp_median_m"] == pytest.approx(np.median(d))
    assert st.loc[1, "disp_p84_m"] == pytest.approx(np.percentile(d, 84))
    assert list(st["n_exceed_capacity"]) == [0, 2, 3] and list(st["n_outside_model"]) == [0, 0, 1]
    # failure = overturn or beyond the capacity, run by run: 0.3 g: records 2 (both) and 3 (beyond)
    assert list(st["n_failure"]) == [0, 2, 4]
    fixed = stripe_table(_fake_runs(isolated=False), capacity_m=0.2)
    assert list(fixed["n_exceed_capacity"]) == [0, 0, 0] and list(fixed["n_failure"]) == [0, 1, 3]


def test_runs_outside_the_model_are_left_out_or_counted_as_failures():
    runs = _fake_runs()
    _, m = outcome_matrices(runs, [0.1, 0.3, 0.6], 0.2, "exclude")
    dmg, inc = m["failure"]
    assert not inc[3, 2] and inc.sum() == 11  # record r3 at 0.6 g slides: out of every fit
    _, m = outcome_matrices(runs, [0.1, 0.3, 0.6], 0.2, "failure")
    dmg, inc = m["failure"]
    assert inc[3, 2] and dmg[3, 2] and inc.sum() == 12
    assert not m["overturn"][1][3, 2]  # still out of the overturning fit


def _settings(**kw) -> Settings:
    base = {"stripes": (0.1, 0.3, 0.6), "design": (0.3,), "mce": (0.45,), "capacity_m": 0.2, "n_boot": 200,
            "gamma_x": 1.0}  # fmt: skip
    return Settings(**{**base, **kw})


def test_a_degenerate_fit_is_not_estimable_and_reports_what_was_seen():
    """No overturn anywhere: 'not estimable' with the count and its Clopper-Pearson bound, never 0."""
    runs = _fake_runs()
    runs["outcome_code"] = 1
    ev = evaluate(runs, _settings())
    (lvl,) = ev.levels
    assert lvl["p_overturn"] is None and not lvl["overturn_estimable"]
    assert lvl["n_overturn_observed"] == 0 and lvl["n_overturn_counted"] == 4
    assert lvl["p_overturn_upper95"] == pytest.approx(1 - 0.05 ** (1 / 4))  # exact bound of 0 in 4
    assert not ev.estimates["overturn"].fit.estimable
    assert "not estimable" in ev.estimates["overturn"].fit.note


def test_a_fitted_probability_carries_its_interval_and_the_observed_fraction():
    rng = np.random.default_rng(5)
    rows = []
    for k in range(30):
        cap = float(np.exp(np.log(0.35) + 0.4 * rng.standard_normal()))
        for x in (0.1, 0.2, 0.3, 0.45, 0.6, 0.8):
            rows.append({"record": f"r{k}", "level": x, "outcome_code": 2 if x >= cap else 1,
                         "max_base_disp_m": 0.0, "outside_model": False, "slides": False,
                         "jumps": False})  # fmt: skip
    ev = evaluate(pd.DataFrame(rows), _settings(stripes=(0.1, 0.2, 0.3, 0.45, 0.6, 0.8), n_boot=300))
    (lvl,) = ev.levels
    lo, hi = lvl["p_overturn_ci95"]
    assert lo < lvl["p_overturn"] < hi and hi - lo > 0.05
    assert lvl["p_overturn_observed"] == pytest.approx(lvl["n_overturn_observed"] / 30)
    f = ev.estimates["overturn"]
    assert f.median_ci95[0] < f.fit.median < f.median_ci95[1]
    assert 0.25 < f.fit.median < 0.5


def test_mce_displacement_is_the_codes_statistic():
    d = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7])
    assert displacement_statistic(d) == (pytest.approx(0.4), "mean of 7 records")
    stat, how = displacement_statistic(d[:5])
    assert stat == 0.5 and how.startswith("maximum of 5 records")


def test_mce_displacement_carries_its_interval_and_the_share_beyond_the_capacity():
    """8 records, MCE displacements 0.05 ... 0.40 m, capacity 0.2 m: the mean, 0.225 m, with its bootstrap
    interval; 4 of 8 beyond the capacity with the exact interval; the run that overturns is counted."""
    rows = []
    for k in range(8):
        for x in (0.1, 0.3, 0.45, 0.6):
            d = 0.05 * (k + 1) * x / 0.45
            code = 2 if (x == 0.45 and k == 7) else 1
            rows.append({"record": f"r{k}", "level": x, "outcome_code": code, "max_base_disp_m": d,
                         "outside_model": False, "slides": False, "jumps": False})  # fmt: skip
    ev = evaluate(pd.DataFrame(rows), _settings(n_boot=400), {"isolation": "linear"})
    (lvl,) = ev.levels
    assert lvl["disp_mce_m"] == pytest.approx(0.225) and lvl["disp_mce_statistic"] == "mean of 8 records"
    lo, hi = lvl["disp_mce_ci95_m"]
    assert 0.1 < lo < 0.225 < hi < 0.35
    assert not lvl["mce_within_capacity"]
    assert (lvl["n_mce_exceed_capacity"], lvl["p_mce_exceed_capacity"]) == (4, 0.5)
    assert lvl["p_mce_exceed_capacity_ci95"] == pytest.approx(list(clopper_pearson(4, 8)))
    assert lvl["n_mce_overturn"] == 1 and "a lower bound" in lvl["disp_mce_overturned"]
    # at the design level (0.3 g: 0.033 ... 0.27 m): 2 of 8 beyond
    assert (lvl["n_exceed_capacity"], lvl["p_exceed_capacity"]) == (2, 0.25)
    # the fixed base has no isolator: nothing beyond a capacity, nothing to count
    fixed = evaluate(
        pd.DataFrame(rows).assign(max_base_disp_m=0.0), _settings(n_boot=50), {"isolation": "none"}
    )
    assert fixed.levels[0]["p_mce_exceed_capacity"] is None and fixed.levels[0]["disp_mce_ci95_m"] is None


def test_every_base_of_one_record_set_sees_the_same_resamples():
    """Bases evaluated on the same record list see the same resamples, record for record: a base that
    differs from another only in record r1 failing at the design level differs exactly in the resamples
    that draw r1; a base without record r2 equals the first wherever r2 is not drawn."""
    recs = ["r0", "r1", "r2", "r3"]
    s = _settings(n_boot=400)
    a = evaluate(_fake_runs(), s, records=recs)
    other = _fake_runs()
    other.loc[(other["record"] == "r1") & (other["level"] == 0.3), "outcome_code"] = 2
    b = evaluate(other, s, records=recs)
    no_r2 = _fake_runs()
    c = evaluate(no_r2[no_r2["record"] != "r2"], s, records=recs)
    W = resample_weights(4, 400, 0)
    pa, pb, pc = (e.samples["p_failure_observed"][0] for e in (a, b, c))
    assert np.array_equal(pb != pa, W[:, 1] > 0) and np.all(pb >= pa)
    assert np.array_equal(pc[W[:, 2] == 0], pa[W[:, 2] == 0])
    assert a.levels[0]["n_failure_observed"] == 2 and b.levels[0]["n_failure_observed"] == 3


def _candidate_runs(n_ov: int, disp: float, seed: int = 0, n_high: int | None = None) -> pd.DataFrame:
    """8 records: ``n_ov`` overturn at 0.3 g, ``n_high`` (default ``n_ov + 2``) at 0.45 g (the MCE) and
    0.6 g."""
    high = min(8, n_ov + 2) if n_high is None else n_high
    rows = []
    for x in (0.1, 0.3, 0.45, 0.6):
        for k in range(8):
            over = x >= 0.3 and k < (n_ov if x == 0.3 else high)
            rows.append({"record": f"r{k}", "level": x, "outcome_code": 2 if over else 1,
                         "max_base_disp_m": disp * x / 0.3, "outside_model": False, "slides": False,
                         "jumps": False})  # fmt: skip
    return pd.DataFrame(rows)


def _rank(cands, **kw):
    s = _settings(stripes=(0.1, 0.3, 0.6), mce=(0.45,), **kw)
    evaluate_candidates(cands, s)
    (lvl,) = rank(cands, s)
    return lvl


def _iso(kind, Tb=None, xi=None):
    return {"isolation": kind, "Tb_s": Tb, "xi_b": xi, "mu_b": None, "R_b_m": None, "rho": 0.5}


def test_the_floor_is_a_candidate_and_wins_when_isolation_does_not_help():
    """No isolation never fails, not even at the MCE: it meets the target, and an isolator with the same
    (no) failures cannot fail less: the floor wins."""
    cands = [
        Candidate("none", "floor", _iso("none"), _candidate_runs(0, 0.0, n_high=0)),
        Candidate("lin3", "case", _iso("linear", 3.0, 0.2), _candidate_runs(0, 0.05, n_high=0)),
    ]
    lvl = _rank(cands)
    assert lvl["recommended"]["name"] == "none" and not lvl["beats_floor"]
    assert lvl["equivalent"] == []  # only isolators are equivalent to a recommended isolator
    assert lvl["verdict"] == "fixed_base" and "the fixed base meets the target" in lvl["reason"]
    floor = next(r for r in lvl["candidates"] if r["name"] == "none")
    assert floor["adequate"] is True and floor["target_estimate"] == 0.0  # 0 of 8 at the MCE


def test_an_isolator_beyond_the_capacity_at_the_mce_is_not_eligible():
    cands = [
        Candidate("none", "floor", _iso("none"), _candidate_runs(8, 0.0)),
        Candidate("long", "case", _iso("linear", 4.0, 0.1), _candidate_runs(0, 0.19)),  # 0.285 m at the MCE
        Candidate("short", "case", _iso("linear", 2.0, 0.1), _candidate_runs(0, 0.10, n_high=0)),
    ]
    lvl = _rank(cands)
    rows = {r["name"]: r for r in lvl["candidates"]}
    assert rows["long"]["adequate"] is False and rows["long"]["adequacy_note"]
    # no spread over the resamples (every record fails on the fixed base, none on the isolator): exact
    # bounds decide, 0 of 8 against 8 of 8
    assert rows["short"]["vs_floor"]["decided_by"] == "exact bounds" and lvl["verdict"] == "isolate"
    assert not rows["long"]["within_capacity"] and rows["long"]["rank"] == 0
    assert rows["short"]["within_capacity"] and lvl["recommended"]["name"] == "short"
    assert rows["short"]["disp_mce_m"] == pytest.approx(0.10 * 0.45 / 0.3)
    assert lvl["beats_floor"]


def test_an_optimum_on_the_edge_of_the_grid_is_flagged():
    """The best grid isolator (1 of 8 fails at the design level) is the last of its axis: an end to
    search beyond. Had it no failure at all, there would be nothing to search for."""
    grid = [
        Candidate(f"grid-{k}", "grid", _iso("linear", Tb, 0.2), _candidate_runs(n, 0.05), (k, 0), (3, 1))
        for k, (Tb, n) in enumerate([(1.5, 6), (2.5, 4), (3.5, 1)])
    ]
    lvl = _rank([Candidate("none", "floor", _iso("none"), _candidate_runs(8, 0.0)), *grid])
    assert lvl["best"]["name"] == "grid-2" and lvl["edge_of_grid"] and lvl["edges"] == [(0, "high")]
    grid[2].runs = _candidate_runs(0, 0.05)
    lvl = _rank([Candidate("none", "floor", _iso("none"), _candidate_runs(8, 0.0)), *grid])
    assert lvl["best"]["name"] == "grid-2" and not lvl["edge_of_grid"]


def test_candidates_evaluated_on_two_processes_have_the_same_numbers_as_on_one():
    """The merge and the grid's extension evaluate their candidates on the rule's cores
    (``evaluate_candidates(..., workers=2)``): every fit, interval and resampled value is the one that
    one process computes, and each candidate keeps its own (not its neighbour's)."""
    s = _settings(stripes=(0.1, 0.3, 0.6), mce=(0.45,), n_boot=200)
    runs = [(1, 0.05), (3, 0.10), (0, 0.02), (5, 0.2), (2, 0.08)]

    def cands():
        return [
            Candidate(f"c{k}", "grid", _iso("linear", 1.0 + k, 0.1), _candidate_runs(n, d))
            for k, (n, d) in enumerate(runs)
        ]

    one, two = cands(), cands()
    evaluate_candidates(one, s, workers=1)
    evaluate_candidates(two, s, workers=2)
    for a, b in zip(one, two, strict=True):
        assert a.evaluation.levels == b.evaluation.levels
        assert a.evaluation.fragility_rows() == b.evaluation.fragility_rows()
        for key, v in a.evaluation.samples.items():
            u, w = np.asarray(v, dtype=float), np.asarray(b.evaluation.samples[key], dtype=float)
            assert np.array_equal(u, w, equal_nan=True), key
    # the candidates differ (a worker that returned another's evaluation would be caught)
    assert len({str(c.evaluation.levels[0]["n_failure_observed"]) for c in two}) > 1
