"""Objects of measured geometry in the assessment (issue 34): the configuration's rigid bodies and parts,
their checks (one line naming the key), both polarities of every record (each run the worse of the two)
and the words of the report beside the uniform block of the same outline."""

from __future__ import annotations

import math

import numpy as np
import pytest

from isorock import GroundMotion, NoIsolation
from isorock.assessment.stripes import AssessedObject, run_levels
from isorock.assessment.words import body_words
from isorock.errors import ConfigError
from isorock.pipeline import load_config

PARTS = [
    {"width_m": 0.6, "height_m": 0.3, "x_m": 0.0, "y_m": 0.0, "mass_kg": 150},
    {"width_m": 0.4, "height_m": 1.5, "x_m": 0.05, "y_m": 0.3, "mass_kg": 250},
]


def _cfg(**obj) -> dict:
    o = {"name": "s", "friction": 0.5, **obj}
    a = {"objects": [o], "cases": ["none"], "stripes_g": [0.1, 0.2], "design_g": [0.15], "mce_g": [0.2]}
    return {"studies": [], "assessment": a}


def test_parts_object():
    o = AssessedObject.from_config({"name": "s", "friction": 0.5, "parts": PARTS})
    assert (o.height_m, o.width_m) == (1.8, pytest.approx(0.6))
    assert o.polarities == (1.0, -1.0)
    body = o.block()
    assert body.h_cg == pytest.approx((150 * 0.15 + 250 * 1.05) / 400)
    assert body.b_right == pytest.approx(0.3 - 250 * 0.05 / 400)
    cols = o.columns()
    assert cols["tan_alpha"] == pytest.approx(min(cols["tan_alpha_left"], cols["tan_alpha_right"]))
    once = AssessedObject.from_config(
        {"name": "s", "friction": 0.5, "parts": PARTS, "polarity": "as_recorded"}
    )
    assert once.polarities == (1.0,)
    sym = AssessedObject.from_config(
        {"name": "s", "friction": 0.5, "b_left_m": 0.2, "b_right_m": 0.2, "h_cg_m": 0.8, "r_gyration_m": 0.4}
    )
    assert sym.polarities == (1.0,) and math.isnan(cols["b_left_m"]) is False


@pytest.mark.parametrize(
    ("obj", "words"),
    [
        ({"b_left_m": 0.2, "b_right_m": 0.2, "h_cg_m": 0.8}, "a rigid body needs b_left_m"),
        ({"parts": PARTS, "height_m": 1.8, "width_m": 0.6}, "give one description of the object"),
        ({"height_m": 1.8, "width_m": 0.6, "restitution": 0.9}, "restitution is for a rigid body"),
        ({"parts": [{**PARTS[0], "y_m": 0.1}]}, "no part stands on the base"),
        ({"parts": [PARTS[0], {**PARTS[1], "x_m": 2.0}]}, "outside the footprint"),
        ({"parts": PARTS, "friction": 0.2}, "give slide_allow_m"),
        ({"parts": [{**PARTS[0], "mass": 1}]}, "mass"),
    ],
)
def test_config_refusals(obj, words):
    with pytest.raises(ConfigError) as e:
        load_config(_cfg(**obj))
    msg = str(e.value)
    assert words in msg and "\n" not in msg, msg


def test_config_accepts_a_body():
    load_config(_cfg(parts=PARTS))
    load_config(_cfg(b_left_m=0.2, b_right_m=0.3, h_cg_m=0.8, r_gyration_m=0.4, restitution=0.9))


def _record() -> GroundMotion:
    rng = np.random.default_rng(7)
    acc = np.convolve(rng.standard_normal(800), np.exp(-0.5 * (np.arange(-25, 26) / 6.0) ** 2), "same")
    acc *= np.hanning(800)
    return GroundMotion(0.01, acc / np.abs(acc).max() * 9.81, name="synthetic")


def test_both_polarities_envelope():
    o = AssessedObject.from_config({"name": "s", "friction": 0.9, "parts": PARTS})
    gm = _record()
    levels = [0.2, 0.35, 0.5, 0.8]
    system = o.system(NoIsolation())
    kw = {"slide_allow_m": None}
    both = run_levels([system], gm, levels, o.friction, polarities=(1.0, -1.0), **kw)
    plus = run_levels([system], gm, levels, o.friction, **kw)
    minus = run_levels([system], gm.scaled(-1.0), levels, o.friction, basis=gm.pga_g, **kw)
    assert len(both) == len(levels)
    np.testing.assert_array_equal(
        both["outcome_code"], np.maximum(plus["outcome_code"], minus["outcome_code"])
    )
    np.testing.assert_array_equal(
        both["max_theta_over_alpha"], np.maximum(plus["max_theta_over_alpha"], minus["max_theta_over_alpha"])
    )
    np.testing.assert_array_equal(both["mu_required"], np.maximum(plus["mu_required"], minus["mu_required"]))
    # the polarities differ somewhere for this asymmetric body, and the governing one is named
    assert (plus["outcome_code"] != minus["outcome_code"]).any() or (
        plus["max_theta_over_alpha"] != minus["max_theta_over_alpha"]
    ).any()
    gov = np.where(plus["outcome_code"] >= minus["outcome_code"], 1.0, -1.0)
    strict = plus["outcome_code"] != minus["outcome_code"]
    np.testing.assert_array_equal(both["polarity"][strict], gov[strict])


def test_words_beside_the_uniform_block():
    body = {
        "b_left_m": 0.33,
        "b_right_m": 0.27,
        "h_cg_m": 0.7125,
        "r_gyration_m": 0.45,
        "tan_alpha_left": 0.33 / 0.7125,
        "tan_alpha_right": 0.27 / 0.7125,
        "polarities": 2,
    }
    stripes = [{"n_records": 10, "n_overturn": 3}, {"n_records": 10, "n_overturn": 6}]
    summary = {
        "objects": [
            {"name": "statue", "height_m": 1.8, "width_m": 0.6, "tan_alpha": 1 / 3, "body": None},
            {"name": "statue-measured", "height_m": 1.8, "width_m": 0.6, "body": body},
        ],
        "cases": [
            {"object": "statue", "isolation": "none", "stripes": stripes},
            {"object": "statue-measured", "isolation": "none", "stripes": stripes[:1] + [stripes[0]]},
        ],
    }
    text = body_words(summary["objects"][1], summary)
    assert "0.713 m above its base" in text and "0.463 g onto its left edge" in text
    assert "as recorded and reversed" in text
    assert "Beside statue, the uniform block of the same 1.8 m x 0.6 m outline" in text
    assert (
        "lower (0.713 m against 0.9 m)" in text
        and "0.379 g on its weaker side against 0.333 g, later" in text
    )
    assert "none 6 of 20 against 9 of 20" in text


def test_object_runs_both_polarities():
    # every job (stripes, design, its extension) runs an object through AssessedObject.runs
    o = AssessedObject.from_config({"name": "s", "friction": 0.9, "parts": PARTS})
    gm = _record()
    system = o.system(NoIsolation())
    mine = o.runs([system], gm, [0.35, 0.5])
    both = run_levels([system], gm, [0.35, 0.5], o.friction, slide_allow_m=None, polarities=(1.0, -1.0))
    assert mine.equals(both)
    once = AssessedObject.from_config(
        {"name": "s", "friction": 0.9, "parts": PARTS, "polarity": "as_recorded"}
    )
    plain = run_levels([system], gm, [0.35, 0.5], o.friction, slide_allow_m=None)
    assert once.runs([system], gm, [0.35, 0.5]).equals(plain)


def test_first_overturn_search_per_direction():
    from isorock import Pulse
    from isorock.jobs.record import search_row
    from isorock.physics.overturning import min_overturn_amplitude

    o = AssessedObject.from_config({"name": "s", "friction": 0.9, "parts": PARTS})
    system = o.system(NoIsolation())
    pulse = Pulse("halfsine", 0.5, 1.0)
    search = {"amp_max_g": 3.0, "growth": 1.01, "rtol": 1e-4}
    row = search_row(system, pulse, search, polarities=o.polarities)
    kw = {"amp_max": 3.0, "growth": 1.01, "rtol": 1e-4}
    plus = min_overturn_amplitude(system, pulse, polarity=1.0, **kw).min_overturn_g
    minus = min_overturn_amplitude(system, pulse, polarity=-1.0, **kw).min_overturn_g
    assert plus != minus
    assert row["min_overturn_as_recorded_g"] == plus and row["min_overturn_reversed_g"] == minus
    assert row["min_overturn_g"] == min(plus, minus)
    assert "min_overturn_reversed_g" not in search_row(system, pulse, search)
