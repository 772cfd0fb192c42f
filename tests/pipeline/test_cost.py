"""The cost estimate of a workflow run (:mod:`isorock.control.cost`), counted by hand on small
configurations, and its limit (refused above it unless forced)."""

from __future__ import annotations

import math

import pytest

from isorock.control import cost as cost_mod
from isorock.control.cost import (
    FULL_RUN_MS,
    MAX_ANALYSES,
    SEARCH_MS,
    CostEstimate,
    StudyCost,
    check_cost,
    check_limit,
    estimate,
    format_duration,
    search_analyses,
)
from isorock.errors import IsorockError
from isorock.pipeline import load_config

SEARCH = {"amp_max_g": 5.0, "growth": 1.1, "rtol": 1e-2}
# one search at lambda 4 (uplift 0.25 g; amp_max 5 g is 20 times it, so the scan covers SCAN_SPAN = 3):
# scan ceil(ln 3 / ln 1.1) = ceil(11.53) = 12, bisection ceil(log2(0.1 / 0.01)) = ceil(3.32) = 4,
# 3 confirmations; uplift runs: none 0, linear 1, fp 25
STEPS = {"none": 12 + 4 + 3, "linear": 1 + 12 + 4 + 3, "fp": 25 + 12 + 4 + 3}
CASES = [
    {"name": "none", "kind": "none"},
    {"name": "linear", "kind": "linear", "Tb_s": 3.0, "xi_b": 0.35},
    {"name": "fp", "kind": "fp", "mu_b": 0.11, "R_b_m": 2.24},
]


def _config(**over) -> dict:
    base = {"isolation": {"rho": 0.5, "cases": CASES}, "search": SEARCH}
    base.update(over)
    return load_config(base)


def test_one_search_is_counted_as_the_engine_runs_it():
    assert STEPS == {"none": 19, "linear": 20, "fp": 44}
    for kind, n in STEPS.items():
        assert search_analyses(4.0, SEARCH, kind) == n
    # a squat block under a small amp_max: the scan stops at amp_max_g, not at 3 x the uplift PGA
    assert (
        search_analyses(1.0, {**SEARCH, "amp_max_g": 2.0}, "none")
        == math.ceil(math.log(2) / math.log(1.1)) + 7
    )
    # amp_max below the uplift PGA: no scan, no bisection beyond the confirmations
    assert search_analyses(4.0, {**SEARCH, "amp_max_g": 0.2}, "none") == 0 + 0 + 4 + 3


def test_search_estimate_is_within_a_factor_3_of_real_searches():
    """The estimate against the engine's own count (a 0.5 s full-sine pulse, lambda 4, R 3 m)."""
    from isorock import Block, Pulse, System
    from isorock.physics.model import make_isolation
    from isorock.physics.overturning import min_overturn_amplitude

    search = {"amp_max_g": 10.0, "growth": 1.005, "rtol": 1e-6}
    for kind, params in (("none", {}), ("linear", {"Tb_s": 3.0, "xi_b": 0.35, "rho": 0.5}),
                         ("fp", {"mu_b": 0.11, "R_b_m": 2.24, "rho": 0.5})):  # fmt: skip
        system = System(Block.from_lambda_R(4.0, 3.0), make_isolation(kind, **params))
        real = min_overturn_amplitude(
            system, Pulse("fullsine", 0.5, 1.0), amp_max=10.0, growth=1.005, rtol=1e-6
        ).n_analyses
        est = search_analyses(4.0, search, kind)
        assert real / 3 <= est <= 3 * real, (kind, real, est)


def test_overturn_and_maps_counted_by_hand():
    cfg = _config(
        studies=["overturn", "maps"],
        overturn={
            "lambda": [4.0],
            "R_m": [1.0, 2.0],
            "cases": ["none", {"case": "linear", "records": ["a"]}],
        },
        maps={
            "lambda_R": {"lambda": [2.0, 4.0, 6.0], "R_m": [1.0, 3.0], "cases": ["none", "linear"]},
            "Tb_xi": {
                "Tb_s": {"start": 1.0, "stop": 3.0, "num": 5},
                "xi_b": [0.1, 0.3],
                "blocks": [{"lambda": 4.0, "R_m": 6.0}, {"lambda": 3.0, "R_m": 2.0, "records": ["a", "b"]}],
            },
        },
    )
    est = estimate(cfg, 3, cores=4)
    # 2 blocks x (3 records x 19 on the fixed base + 1 record (the case names one) x 20 linear)
    overturn = 2 * (3 * 19 + 1 * 20)
    # lambda-R: 3 x 2 points x (3 + 3 records); Tb-xi: 5 x 2 points x (3 records + 2 named)
    maps = 3 * 2 * (3 + 3) + 5 * 2 * (3 + 2)
    assert est.by_study() == {"overturn": overturn, "maps": maps} == {"overturn": 154, "maps": 86}
    assert est.analyses == 240 and est.n_records == 3 and est.cores == 4
    assert est.studies[0].cpu_s == pytest.approx(
        2 * (57 * SEARCH_MS["none"] + 20 * SEARCH_MS["linear"]) / 1000
    )
    assert est.seconds == pytest.approx(est.cpu_s / 4)
    assert not est.over_limit
    text = est.text()
    assert "\n" not in text and text.startswith(
        "cost estimate: 240 analyses (overturn 154; maps 86) on 3 record(s)"
    )
    assert "on 4 core(s)" in text


def test_pulse_studies_counted_by_hand():
    cfg = _config(
        studies=["pulses"],
        maps={"lambda_R": {"lambda": [2.0, 4.0, 6.0], "R_m": [1.0, 3.0]}},
        pulses={
            "enabled": True,
            "lambda": 4.0,
            "amp_max_g": 5.0,
            "shapes": {"rect": ["none"], "halfsine": [], "fullsine": ["none", "linear"]},
            "vs_R": {"td_s": [0.5], "R_m": [1.0, 5.0]},
            "vs_omega": {"R_m": [3.0], "omega_p_rad_s": [2.0, 10.0]},
            "vs_isolation": {"shapes": ["fullsine"], "base_case": "linear", "R_m": [3.0], "td_s": [0.5],
                             "Tb_s": [2.0, 3.0], "xi_b": [0.1, 0.35], "rho": [0.5]},
            "maps": {"cases": ["none", "linear"],
                     "excitations": [{"shape": "fullsine", "td_s": 0.5}, {"shape": "halfsine", "td_s": 0.2}]},
        },
    )  # fmt: skip
    est = estimate(cfg, 7)  # no record enters the pulse studies
    per_case = 1 * 2 + 1 * 2  # td x R + R x omega_p
    searches = per_case * 19 + per_case * 19 + per_case * 20  # rect: none; fullsine: none, linear
    combos, varied = 1 + 1, 2 + 2 + 1  # (R + td) curves; Tb, xi, rho values
    searches += combos * 19 + combos * varied * 20  # Fig 5: the fixed base and the varied linear case
    points = 2 * 2 * 3 * 2  # excitations x cases x lambda x R
    assert est.by_study() == {"pulses": searches + points} == {"pulses": 494}
    off = estimate(load_config({**cfg, "pulses": {**cfg["pulses"], "enabled": False}}), 7)
    assert off.by_study() == {}


def test_assessment_counted_by_hand():
    cfg = _config(
        studies=[],
        assessment={
            "objects": [{"name": "s", "height_m": 1.2, "width_m": 0.3, "friction": 0.5}],  # lambda 4
            "cases": ["none", "linear"],
            "stripes_g": [0.1, 0.2, 0.4],
            "design_g": [0.2],
            "mce_g": [0.3],  # levels 0.1, 0.2, 0.3, 0.4
            "design_grid": {"kind": "linear", "Tb_s": [2.0, 3.0], "xi_b": [0.1, 0.2, 0.3]},
        },
    )
    est = estimate(cfg, 3)
    stripes = 1 * 2 * 3 * 4  # objects x cases x records x levels
    first = 3 * 19 + 3 * 20  # one first-overturning search per object, case and record
    design = 1 * 3 * 4 * (1 + 2 * 3)  # objects x records x levels x (fixed base + 6 isolators)
    assert est.by_study() == {"assessment": stripes + first + design} == {"assessment": 225}
    cpu_ms = 3 * 4 * (FULL_RUN_MS["none"] + FULL_RUN_MS["linear"]) + 57 * SEARCH_MS["none"]
    cpu_ms += 60 * SEARCH_MS["linear"] + 12 * (FULL_RUN_MS["none"] + 6 * FULL_RUN_MS["linear"])
    assert est.cpu_s == pytest.approx(cpu_ms / 1000)


def test_a_huge_grid_is_over_the_limit_and_refused_unless_forced():
    cfg = _config(
        studies=["maps"],
        maps={"lambda_R": {"lambda": {"start": 1.5, "stop": 8.0, "num": 100000},
                           "R_m": {"start": 0.5, "stop": 15.0, "num": 100000}, "cases": ["none"]}},
    )  # fmt: skip
    est = estimate(cfg, 2)
    assert est.by_study()["maps"] == 2 * 10**10 + 2 * cfg["maps"]["Tb_xi"]["Tb_s"]["num"] * 40
    assert est.over_limit
    with pytest.raises(IsorockError, match="rerun with --force to run it anyway") as e:
        check_cost(est)
    msg = str(e.value)
    assert (
        "\n" not in msg and "cost estimate: 20,000," in msg and f"limit of {MAX_ANALYSES:,} analyses" in msg
    )
    check_cost(est, force=True)  # forced: no error


def test_a_search_too_fine_is_over_the_limit():
    cfg = _config(studies=["overturn"], search={**SEARCH, "growth": 1.0000001, "rtol": 1e-9})
    assert estimate(cfg, 16).over_limit


def test_check_limit_and_durations():
    check_limit(MAX_ANALYSES, 1.0, "a map")
    with pytest.raises(IsorockError, match=r"^a map, about 3.0 h: above the limit .* rerun with --force"):
        check_limit(MAX_ANALYSES + 1, 3 * 3600.0, "a map")
    check_limit(MAX_ANALYSES + 1, 3 * 3600.0, "a map", force=True)
    assert [format_duration(s) for s in (5, 600, 7200, 5 * 86400, 4e8)] == [
        "< 1 min", "10 min", "2.0 h", "5.0 days", "12.7 years"
    ]  # fmt: skip


def test_estimate_sums_its_studies():
    est = CostEstimate((StudyCost("a", 3, 1.5), StudyCost("b", 4, 2.5)), n_records=1, cores=2)
    assert (est.analyses, est.cpu_s, est.seconds) == (7, 4.0, 2.0)
    assert cost_mod.DEFAULT_CORES == 2 and CostEstimate((), 0).cores == 2
