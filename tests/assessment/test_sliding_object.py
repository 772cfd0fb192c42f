"""An assessed object whose friction is below tan(alpha) (issue 24): its runs are sliding analyses equal
to ``simulate(..., friction=...)``, a slide beyond its allowance is a failure beside the isolator's
capacity, the stripes count and measure the slips, its failure fragility is fitted like any other, and
the words say what it does (slides, never rocks) and what fails it."""

from __future__ import annotations

import math

import pandas as pd

from isorock import GroundMotion, LinearIsolation, NoIsolation
from isorock.assessment.case import Settings, evaluate
from isorock.assessment.stripes import AssessedObject, classify_runs, run_levels, stripe_table
from isorock.physics.engine import simulate
from support.records import synthetic_record

SHOWCASE = AssessedObject.from_config(
    {"name": "showcase", "height_m": 1.2, "width_m": 0.5, "friction": 0.35, "slide_allow_m": 0.05}
)


def _record(seed: int, pga_g: float = 0.5) -> GroundMotion:
    return synthetic_record(seed, pga_g)


def test_a_sliding_object_is_marked_and_accepted_below_the_no_bounce_limit():
    assert SHOWCASE.slides and SHOWCASE.columns()["mode"] == "sliding"
    assert SHOWCASE.columns()["slide_allow_m"] == 0.05
    vase = AssessedObject.from_config(
        {"name": "vase", "height_m": 0.3, "width_m": 0.5, "friction": 0.4, "slide_allow_m": 0.02}
    )
    s = vase.system(LinearIsolation(2.5, 0.1, 0.8))  # lambda 0.6: a rocking analysis would bounce
    assert s.sliding_only


def test_sliding_runs_are_the_single_sliding_analyses():
    gm = _record(3)
    systems = [SHOWCASE.system(NoIsolation()), SHOWCASE.system(LinearIsolation(2.5, 0.2, 0.5))]
    levels = [0.2, 0.5, 0.9]
    runs = run_levels(systems, gm, levels, SHOWCASE.friction, slide_allow_m=SHOWCASE.slide_allow_m)
    assert set(runs["mode"]) == {"sliding"}
    for r in runs.itertuples():
        one = simulate(systems[r.system], gm, scale=r.level / gm.pga_g, friction=SHOWCASE.friction)
        assert r.sliding_peak_m == one.sliding_peak_m and r.n_slips == one.n_slips
        assert r.sliding_residual_m == one.sliding_residual_m
        assert r.max_base_disp_m == one.max_base_disp_m
        # the slip is the motion analysed, not a departure from the model
        assert not r.slides and not r.outside_model and r.outcome == "no_uplift"
    assert runs["n_slips"].max() >= 1
    c = classify_runs(runs, capacity_m=None)
    assert (c["slides_beyond"] == (runs["sliding_peak_m"] > 0.05)).all()
    assert (c["failure"] == c["slides_beyond"]).all()
    assert c["slides_beyond"].any() and not c["slides_beyond"].all()


def test_failure_is_a_slide_beyond_the_allowance_or_the_capacity():
    runs = pd.DataFrame(
        {
            "outcome_code": [0, 0, 0, 0],
            "max_base_disp_m": [0.1, 0.5, 0.1, 0.5],
            "sliding_peak_m": [0.01, 0.01, 0.2, math.nan],
            "slide_allow_m": [0.05, 0.05, 0.05, math.nan],
        }
    )
    c = classify_runs(runs, capacity_m=0.3)
    assert c["slides_beyond"].tolist() == [False, False, True, False]
    assert c["exceeds_capacity"].tolist() == [False, True, False, True]
    assert c["failure"].tolist() == [False, True, True, True]


def test_stripes_and_failure_fragility_of_a_sliding_object():
    recs = [_record(k) for k in range(8)]
    levels = [0.2, 0.4, 0.6, 0.7, 0.8, 0.9, 1.0]
    parts = []
    for gm in recs:
        # an allowance of 0.1 m: at 0.8 g some records slide beyond it, some do not (a fit, not a step)
        r = run_levels([SHOWCASE.system(NoIsolation())], gm, levels, SHOWCASE.friction, slide_allow_m=0.1)
        r["record"] = gm.name
        parts.append(r)
    runs = pd.concat(parts, ignore_index=True)
    st = stripe_table(runs)
    assert {"n_slid", "n_slides_beyond", "slide_median_m", "slide_p84_m", "slide_max_m"} <= set(st.columns)
    assert (st["n_slides_beyond"] == st["n_failure"]).all() and (st["n_overturn"] == 0).all()
    assert st["n_slides_beyond"].iloc[-1] > st["n_slides_beyond"].iloc[0]
    assert st["slide_max_m"].is_monotonic_increasing
    runs["stripe"] = True
    runs["design"] = runs["level"] == 0.4
    runs["mce"] = runs["level"] == 0.6
    settings = Settings.from_config(
        {"stripes_g": levels, "design_g": [0.4], "mce_g": [0.6], "bootstrap": 200}
    )
    ev = evaluate(runs, settings, {"isolation": "none"})
    frag = {f["damage"]: f for f in ev.fragility_rows()}
    assert not frag["overturn"]["estimable"]  # it never rocks
    assert frag["failure"]["estimable"] and 0.2 < frag["failure"]["median_g"] < 1.5
    assert ev.levels[0]["n_mce_slides_beyond"] == int(
        ((runs["level"] == 0.6) & (runs["sliding_peak_m"] > 0.1)).sum()
    )


def test_words_say_it_slides_and_what_fails_it():
    from isorock.assessment.words import _sliding_words

    cs = [{"isolation": "none", "stripes": [
        {"level": 0.4, "n_records": 8, "n_slid": 0, "n_slides_beyond": 0},
        {"level": 0.8, "n_records": 8, "n_slid": 6, "n_slides_beyond": 2, "slide_median_m": 0.031,
         "slide_max_m": 0.21},
    ]}]  # fmt: skip
    text = _sliding_words(cs, 0.05)
    assert "at 0.8 g PGA 6 of 8 records slide" in text and "largest 0.21 m, 2 beyond 0.05 m" in text
