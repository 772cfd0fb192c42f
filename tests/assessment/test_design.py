"""The design decision (isorock.assessment.design): adequacy against the target, paired comparisons on
the same resamples corrected for the search, the verdict (isolate, fixed_base, restrain,
inconclusive), the recommendation (the lowest estimate unless a simpler isolator is shown equivalent),
never worse than the fixed base, exact bounds where the resamples cannot decide, and the grid's ends.
The candidates here carry evaluations built from designed resamples, so that each test controls what
the paired and the unpaired rules see."""

from __future__ import annotations

import math

import numpy as np
import pytest

from isorock.assessment.case import Settings
from isorock.assessment.design import (
    P_DECIDE,
    extend_axis,
    grid_edges,
    paired,
    rank,
    records_to_decide,
)
from support.design import candidate as _cand
from support.design import observed

N_BOOT = 2000
RNG = np.random.default_rng(7)


def _level(cands):
    (lvl,) = rank(cands, Settings(stripes=(0.1, 0.3, 0.6), design=(0.3,), mce=(0.45,), n_boot=N_BOOT))
    return lvl


def _overlap_rule(lvl):
    """The rule of earlier versions: the candidates whose separate 95 % intervals overlap the best
    one's are equivalent, and the simplest of them (no isolation, then the shortest period) wins."""
    rows = [r for r in lvl["candidates"] if r["rank"]]
    best = min(rows, key=lambda r: r["estimate"])
    eq = [r for r in rows if r["estimate_ci95"][0] <= best["estimate_ci95"][1]
          and best["estimate_ci95"][0] <= r["estimate_ci95"][1]]  # fmt: skip
    return min(eq, key=lambda r: (r["period_s"], r["estimate"]))


def test_the_overlap_rule_could_recommend_worse_than_the_fixed_base_the_paired_rule_does_not():
    """The fixed base fails at 10 % (8-12 %), the best isolator at 1 % (0.5-2 %): their intervals do not
    overlap. A short-period isolator whose estimate, 12 %, is above the fixed base's has so wide an
    interval that it overlaps the best one's: the overlap rule calls it equivalent and, being the
    simpler, recommends it. The paired rule compares every candidate with the fixed base on the same
    resamples: the wide one is lower in a third of them only, the best in all."""
    base = RNG.normal(0.0, 1.0, N_BOOT)
    floor = _cand("none", "floor", 0.10 + 0.01 * base, est=0.10)
    best = _cand("best", "case", np.clip(0.011 + 0.0035 * base, 0.001, None), est=0.01, period=3.0)
    wide = _cand(
        "wide", "case", np.clip(0.12 + 0.06 * RNG.normal(size=N_BOOT), 0.0015, None), est=0.12, period=1.5
    )
    lvl = _level([floor, best, wide])
    old = _overlap_rule(lvl)
    assert old["name"] == "wide" and old["estimate"] > lvl["floor"]["estimate"]  # the flaw, shown
    assert lvl["verdict"] == "isolate"
    rec = lvl["recommended"]
    assert rec["name"] == "best" and rec["estimate"] < lvl["floor"]["estimate"]
    rows = {r["name"]: r for r in lvl["candidates"]}
    assert rows["wide"]["vs_floor"]["p_better"] < 0.5 and not rows["wide"]["beats_floor"]
    assert rows["best"]["vs_floor"]["p_better"] >= P_DECIDE


def test_overlapping_intervals_can_still_differ_on_every_resample():
    """Two bases that saw the same records move together from resample to resample: their separate
    intervals overlap widely, their paired difference does not straddle zero."""
    common = RNG.lognormal(np.log(0.05), 0.6, N_BOOT)
    floor = _cand("none", "floor", common + 0.01)
    iso = _cand("iso", "case", common + 0.001 * RNG.normal(size=N_BOOT), period=2.0)
    lvl = _level([floor, iso])
    f, i = lvl["floor"]["estimate_ci95"], next(r for r in lvl["candidates"] if r["name"] == "iso")
    assert i["estimate_ci95"][1] > f[0]  # the separate intervals overlap
    assert i["vs_floor"]["difference_ci95"][1] < 0 and i["vs_floor"]["p_better"] == 1.0
    assert i["vs_floor"]["p_adjusted"] == pytest.approx(1 / (N_BOOT + 1))
    assert lvl["verdict"] == "isolate" and lvl["recommended"]["name"] == "iso"


def test_the_fixed_base_wins_when_it_beats_every_eligible_isolator():
    base = RNG.normal(0.0, 1.0, N_BOOT)
    floor = _cand("none", "floor", 0.02 + 0.004 * base, est=0.02)
    worse = [_cand(f"i{k}", "case", 0.05 + 0.01 * k + 0.006 * base, period=1.0 + k) for k in range(3)]
    beyond = _cand("beyond", "case", 0.001 + 0.0001 * base, period=5.0, within=False)  # best, not eligible
    lvl = _level([floor, *worse, beyond])
    assert lvl["verdict"] == "fixed_base" and lvl["recommended"]["name"] == "none"
    rows = {r["name"]: r for r in lvl["candidates"]}
    assert rows["beyond"]["rank"] == 0 and not rows["beyond"]["eligible"]
    assert all(rows[f"i{k}"]["vs_floor"]["p_worse"] >= P_DECIDE for k in range(3))


def test_neither_way_is_inconclusive_and_says_what_would_decide():
    base = RNG.normal(0.0, 1.0, N_BOOT)
    noise = RNG.normal(0.0, 1.0, N_BOOT)
    # the fixed base is not shown to meet the target (15 %, 5 % to 30 % at the MCE)
    floor = _cand("none", "floor", 0.05 + 0.01 * base, est=0.05, p_mce=(0.15, [0.05, 0.3]))
    iso = _cand("iso", "case", 0.045 + 0.01 * base + 0.01 * noise, est=0.045, period=2.0)
    lvl = _level([floor, iso])
    assert lvl["verdict"] == "inconclusive" and lvl["recommended"] is None
    p = next(r for r in lvl["candidates"] if r["name"] == "iso")["vs_floor"]
    assert P_DECIDE > p["p_better"] > 0.5 and p["p_worse"] < P_DECIDE
    # sd of the difference 0.01, difference 0.005: n (1.645 x 2)^2 = 10.8 n records
    assert lvl["records_to_decide"] == pytest.approx(20 * (1.645 * 0.01 / 0.005) ** 2, rel=0.1)


def test_records_to_decide():
    d = RNG.normal(0.0, 0.01, 4000)
    assert records_to_decide(18, -0.005, d) == pytest.approx(18 * (1.6449 * 0.01 / 0.005) ** 2, rel=0.05)
    assert records_to_decide(18, 0.0, d) is None
    assert records_to_decide(18, -0.1, d) == 19  # decided already: at least one more than now


def test_no_failure_on_the_fixed_base_keeps_it():
    """Nothing beats zero: an isolator with the same (no) failures is no reason to isolate."""
    floor = _cand("none", "floor", np.zeros(N_BOOT), est=0.0)
    iso = _cand("iso", "case", np.zeros(N_BOOT), est=0.0, period=2.0)
    lvl = _level([floor, iso])
    assert lvl["verdict"] == "fixed_base" and lvl["recommended"]["name"] == "none"
    assert "the fixed base meets the target" in lvl["reason"]


def test_the_simplest_of_the_winners_that_the_paired_test_cannot_tell_from_the_best():
    base = RNG.normal(0.0, 1.0, N_BOOT)
    floor = _cand("none", "floor", 0.10 + 0.01 * base, est=0.10)
    long_ = _cand("long", "case", 0.020 + 0.004 * base, est=0.020, period=4.0)
    short = _cand(
        "short", "case", 0.021 + 0.004 * base + 0.003 * RNG.normal(size=N_BOOT), est=0.021, period=2.0
    )
    lvl = _level([floor, long_, short])
    assert lvl["best"]["name"] == "long" and lvl["recommended"]["name"] == "short"
    assert set(lvl["equivalent"]) == {"long", "short"}


def test_paired_counts_ties_as_neither():
    p = paired(0.0, np.zeros(10), 0.0, np.zeros(10))
    assert p["p_better"] == 0.0 and p["p_worse"] == 0.0 and p["difference_ci95"] == [0.0, 0.0]
    q = paired(0.1, np.array([0.1, 0.2, math.nan]), 0.2, np.array([0.2, 0.1, 0.3]))
    assert q["n"] == 2 and q["p_better"] == 0.5 and q["p_worse"] == 0.5


def test_the_ends_of_the_grid_to_search_beyond():
    base = RNG.normal(0.0, 1.0, N_BOOT)
    shape = (3, 3)
    est = {(i, j): 0.1 - 0.02 * i - 0.01 * j for i in range(3) for j in range(3)}  # best at (2, 2)
    grid = [_cand(f"g{i}{j}", "grid", v + 0.005 * base, est=v, period=1.0 + i, grid=(i, j), shape=shape)
            for (i, j), v in est.items()]  # fmt: skip
    assert grid_edges(grid, [c.evaluation.levels[0]["p_failure"] for c in grid]) == [(0, "high"), (1, "high")]
    lvl = _level([_cand("none", "floor", 0.2 + 0.01 * base, est=0.2), *grid])
    assert lvl["edge_of_grid"] and lvl["best"]["name"] == "g22" and lvl["edges"] == [(0, "high"), (1, "high")]
    # an interior optimum needs no extension; nor do a tie that reaches inside, or a zero
    est[(1, 1)] = 0.01
    assert grid_edges(grid, [est[c.grid_index] for c in grid]) == []
    est[(1, 1)], est[(0, 0)] = 0.04, 0.04
    assert grid_edges(grid, [est[c.grid_index] for c in grid]) == []
    est[(1, 1)], est[(0, 0)] = 0.05, 0.03
    assert grid_edges(grid, [est[c.grid_index] for c in grid]) == [(0, "low"), (1, "low")]
    assert grid_edges(grid, [0.0] * 9) == []


@pytest.mark.parametrize(
    "values, side, bound, spacing, expected",
    [([1.5, 2.0, 2.5], "high", 6.0, "linear", 3.0), ([1.5, 2.0, 5.8], "high", 6.0, "linear", 6.0),
     ([1.5, 2.0, 6.0], "high", 6.0, "linear", None), ([1.5, 2.0], "low", 1.0, "linear", 1.0),
     ([0.05, 0.1], "low", 0.02, "log", 0.025), ([0.05, 0.1], "high", 0.5, "log", 0.2),
     ([2.0], "high", 6.0, "linear", None)],
)  # fmt: skip
def test_extend_axis(values, side, bound, spacing, expected):
    got = extend_axis(values, side, bound, spacing)
    assert got == (None if expected is None else pytest.approx(expected))


def test_a_count_of_zero_is_compared_with_counts_not_with_a_fit():
    """An isolator with no fitted fragility and 0 of 20 failures at the design level, against a fixed
    base fitted at 3.7 % with 1 of 20 observed: compared fit against zero, the zero would be lower in
    nearly every resample; compared count against count, only in those that draw the failing record
    (1 - 0.95^20 = 64 %): no decision."""
    base = RNG.normal(0.0, 1.0, N_BOOT)
    floor = _cand(
        "none", "floor", 0.037 + 0.01 * base, est=0.037, observed=observed([4]), p_mce=(0.2, [0.05, 0.4])
    )
    iso = _cand("iso", "case", np.zeros(N_BOOT), period=2.0, fitted=False, observed=observed([]))
    lvl = _level([floor, iso])
    vs = next(r for r in lvl["candidates"] if r["name"] == "iso")["vs_floor"]
    assert vs["basis"] == "observed" and vs["p_better"] == pytest.approx(1 - 0.95**20, abs=0.03)
    assert lvl["verdict"] == "inconclusive" and lvl["recommended"] is None
    both = _level(
        [
            _cand("none", "floor", 0.037 + 0.01 * base, est=0.037),
            _cand("i", "case", 0.01 + 0.004 * base, period=2.0),
        ]
    )
    assert both["candidates"][0]["vs_floor"]["basis"] == "fitted"


@pytest.mark.parametrize(
    "isolators, verdict, words",
    [
        ([], "fixed_base", "no isolator was assessed"),
        ([dict(within=False)], "fixed_base", "no isolator assessed is within the displacement capacity"),
    ],
)
def test_the_reason_of_a_verdict_without_a_comparison(isolators, verdict, words):
    base = RNG.normal(0.0, 1.0, N_BOOT)
    floor = _cand("none", "floor", 0.05 + 0.01 * base, est=0.05)
    others = [_cand(f"i{k}", "case", 0.01 + 0.004 * base, period=2.0, **kw) for k, kw in enumerate(isolators)]
    lvl = _level([floor, *others])
    assert lvl["verdict"] == verdict and words in lvl["reason"]


def test_the_lowest_estimate_is_recommended_when_the_simpler_one_is_not_shown_equivalent():
    """A shorter-period isolator that cannot be told apart from the best (its difference straddles zero
    widely) is not equivalent: "cannot be distinguished" is no evidence of equivalence."""
    base = RNG.normal(0.0, 1.0, N_BOOT)
    floor = _cand("none", "floor", 0.10 + 0.01 * base, est=0.10)
    long_ = _cand("long", "case", 0.020 + 0.004 * base, est=0.020, period=4.0)
    short = _cand(
        "short", "case", 0.022 + 0.004 * base + 0.02 * RNG.normal(size=N_BOOT), est=0.022, period=2.0
    )
    lvl = _level([floor, long_, short])
    rows = {r["name"]: r for r in lvl["candidates"]}
    assert rows["short"]["vs_best"]["p_worse"] < P_DECIDE  # the paired test cannot tell them apart ...
    assert lvl["recommended"]["name"] == "long" and lvl["equivalent"] == ["long"]  # ... nor are they equal


def test_every_base_clearly_missing_the_target_is_restrain_and_names_the_closest():
    """The slender object: the fixed base fails at the MCE in 90 % (70 % to 100 %), the isolators fail
    less but their lower ends are above 10 % too: restrain it, and say which base comes closest."""
    base = RNG.normal(0.0, 1.0, N_BOOT)
    floor = _cand("none", "floor", 0.8 + 0.05 * base, est=0.8, p_mce=(0.9, [0.7, 1.0]))
    a = _cand("a", "case", 0.4 + 0.05 * base + 0.01 * RNG.normal(size=N_BOOT), est=0.4, period=2.0,
              p_mce=(0.5, [0.3, 0.7]))  # fmt: skip
    b = _cand("b", "case", 0.3 + 0.05 * base + 0.01 * RNG.normal(size=N_BOOT), est=0.3, period=3.0,
              p_mce=(0.33, [0.18, 0.52]))  # fmt: skip
    lvl = _level([floor, a, b])
    assert lvl["verdict"] == "restrain" and lvl["recommended"] is None
    assert lvl["closest"]["name"] == "b" and all(r["adequate"] is False for r in lvl["candidates"])
    assert rows_beat(lvl) == {"a", "b"}  # better than the fixed base, and still not safe


def rows_beat(lvl):
    return {r["name"] for r in lvl["candidates"] if r["beats_floor"]}


def test_an_isolator_better_than_the_fixed_base_but_not_shown_safe_is_not_recommended():
    base = RNG.normal(0.0, 1.0, N_BOOT)
    floor = _cand("none", "floor", 0.8 + 0.05 * base, est=0.8, p_mce=(0.9, [0.7, 1.0]))
    iso = _cand("iso", "case", 0.1 + 0.05 * base + 0.01 * RNG.normal(size=N_BOOT), est=0.1, period=3.0,
                p_mce=(0.2, [0.05, 0.4]))  # fmt: skip
    lvl = _level([floor, iso])
    assert rows_beat(lvl) == {"iso"} and lvl["candidates"][0]["adequate"] is None
    assert lvl["verdict"] == "inconclusive" and "no isolator is shown to meet the target" in lvl["reason"]


def test_isolate_needs_an_isolator_that_meets_the_target_and_beats_the_fixed_base():
    base = RNG.normal(0.0, 1.0, N_BOOT)
    floor = _cand("none", "floor", 0.3 + 0.03 * base, est=0.3, p_mce=(0.5, [0.3, 0.7]))
    iso = _cand("iso", "case", 0.02 + 0.01 * base, est=0.02, period=3.0, p_mce=(0.05, [0.01, 0.12]))
    lvl = _level([floor, iso])
    assert lvl["verdict"] == "isolate" and lvl["recommended"]["name"] == "iso"
    assert lvl["target"]["kind"] == "p_mce" and lvl["target"]["value"] == 0.1
    r = lvl["recommended"]
    assert r["adequate"] is True and r["vs_floor"]["p_adjusted"] <= 0.05 and r["vs_floor"]["n_family"] == 1


def test_with_fewer_than_seven_records_exact_bounds_decide():
    """5 records: the resamples of 5 records would call an isolator better in nearly all of them; the
    exact intervals of 3 of 5 (15 % to 95 %) and 0 of 5 (0 to 52 %) overlap: not shown."""
    base = RNG.normal(0.0, 1.0, N_BOOT)
    floor = _cand("none", "floor", 0.5 + 0.05 * base, est=0.5, observed=observed([0, 1, 2], n=5), n=5)
    iso = _cand("iso", "case", 0.02 + 0.01 * base, est=0.02, period=3.0, observed=observed([], n=5), n=5)
    lvl = _level([floor, iso])
    vs = next(r for r in lvl["candidates"] if r["name"] == "iso")["vs_floor"]
    assert (
        vs["p_better"] == 1.0 and vs["decided_by"] == "exact bounds" and lvl["decided_by"] == "exact bounds"
    )
    assert not rows_beat(lvl) and lvl["verdict"] != "isolate"


def test_no_failure_observed_on_either_base_rests_on_exact_bounds():
    """Both fitted tails at the design level (0 of 20 observed on both): not evidence of a difference."""
    base = RNG.normal(0.0, 1.0, N_BOOT)
    floor = _cand(
        "none", "floor", 0.05 + 0.01 * base, est=0.05, observed=observed([]), p_mce=(0.15, [0.05, 0.3])
    )
    iso = _cand("iso", "case", 0.01 + 0.003 * base, est=0.01, period=3.0, observed=observed([]))
    lvl = _level([floor, iso])
    vs = next(r for r in lvl["candidates"] if r["name"] == "iso")["vs_floor"]
    assert vs["p_better"] == 1.0 and vs["decided_by"] == "exact bounds" and not rows_beat(lvl)


def test_every_isolator_beyond_the_capacity_is_said_so_when_the_fixed_base_is_not_shown_safe():
    """It read "... beyond the displacement capacity at the MCE or has no estimate" (a hedge)."""
    base = RNG.normal(0.0, 1.0, N_BOOT)
    floor = _cand("none", "floor", 0.05 + 0.01 * base, est=0.05, p_mce=(0.13, [0.03, 0.28]))
    iso = _cand("i", "case", 0.09 + 0.01 * base, period=3.0, within=False)
    lvl = _level([floor, iso])
    assert lvl["verdict"] == "inconclusive"
    assert lvl["reason"].startswith(
        "every isolator assessed is beyond the displacement capacity at the MCE, and"
    )


def test_evaluations_kept_between_rounds_are_reused_only_for_the_same_runs(monkeypatch):
    """The rounds of a grid extension evaluate only what they add: a candidate of the same kind,
    parameters and runs table on the same records reuses its evaluation; other runs or another set of
    records are evaluated again; without a cache every candidate is evaluated."""
    import pandas as pd

    from isorock.assessment import design

    calls = []

    def fake_evaluate(runs, settings, params, records=None, measures=True):
        calls.append((params["Tb_s"], tuple(records)))
        return ("evaluation", params["Tb_s"], tuple(records), len(calls))

    monkeypatch.setattr(design, "evaluate", fake_evaluate)
    recs = pd.DataFrame({"record": ["a", "b"]})
    runs = {tb: recs.copy() for tb in (1.0, 2.0, 3.0)}

    def cands(tbs, table=runs):
        return [design.Candidate(f"grid-{k}", "grid", {"Tb_s": tb}, table[tb]) for k, tb in enumerate(tbs)]

    cache: dict = {}
    first = cands([1.0, 2.0])
    design.evaluate_candidates(first, Settings(stripes=(0.3,)), cache)
    assert len(calls) == 2
    second = cands([1.0, 2.0, 3.0])  # renamed on the larger grid: the same isolators and runs
    design.evaluate_candidates(second, Settings(stripes=(0.3,)), cache)
    assert calls[2:] == [(3.0, ("a", "b"))]
    assert [c.evaluation for c in second[:2]] == [c.evaluation for c in first]
    other = {tb: pd.DataFrame({"record": ["a", "b"]}) for tb in runs}  # the same parameters, other runs
    design.evaluate_candidates(cands([1.0], other), Settings(stripes=(0.3,)), cache)
    assert len(calls) == 4
    more = {1.0: pd.DataFrame({"record": ["a", "b", "c"]})}  # another set of records
    design.evaluate_candidates(cands([1.0], more), Settings(stripes=(0.3,)), cache)
    assert calls[-1] == (1.0, ("a", "b", "c"))
    design.evaluate_candidates(cands([1.0, 2.0]), Settings(stripes=(0.3,)))  # no cache: every one evaluated
    assert len(calls) == 7
