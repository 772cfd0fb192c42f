"""The levels of an assessment (isorock.assessment.levels): the MCE given in g, or read off the site's
hazard curve (its 2475-year level unless given), never assumed; design and MCE levels read off the
site's hazard curve by their return periods; the configuration refuses what cannot be read."""

from __future__ import annotations

import pytest

from isorock.assessment.hazard_files import curve_from_config
from isorock.assessment.levels import MCE_FACTOR, mce_levels, resolve_levels, run_levels_of
from isorock.control.config import workflow_config
from isorock.errors import ConfigError

CURVE = {"points": [[0.05, 2.0e-2], [0.1, 7.0e-3], [0.2, 2.1e-3], [0.3, 9.0e-4], [0.4, 4.0e-4],
                    [0.6, 1.2e-4], [1.0, 2.0e-5]]}  # fmt: skip


def test_mce_levels_keep_the_stripe_they_equal():
    assert mce_levels([0.4]) == [0.6] and 0.4 * MCE_FACTOR != 0.6  # 0.6000000000000001: a second level
    a = {"stripes_g": [0.2, 0.4, 0.6, 0.8], "design_g": [0.4], "mce_g": [0.6]}
    assert run_levels_of(a) == [0.2, 0.4, 0.6, 0.8]
    lv = resolve_levels(a)
    assert lv.mce_basis == ("given (mce_g)",) and lv.design_basis == ("given (design_g)",)


def test_without_a_hazard_curve_the_mce_must_be_given():
    """No ratio of MCE to design level is assumed: the codes' 1.5 is no site's ratio for the PGA."""
    with pytest.raises(ConfigError, match="the MCE level is needed .* give mce_g"):
        resolve_levels({"stripes_g": [0.2, 0.4, 0.6, 0.8], "design_g": [0.4]})


def test_with_a_hazard_curve_the_mce_is_its_2475_year_level_unless_given():
    a = {"stripes_g": [0.1, 0.2, 0.3, 0.5, 0.8], "design_g": [0.2], "hazard": CURVE}
    lv = resolve_levels(a)
    assert lv.mce == (float(f"{curve_from_config(CURVE).level_at_return_period(2475):.3g}"),)
    assert "2475-year" in lv.mce_basis[0] and "default" in lv.mce_basis[0]
    assert resolve_levels({**a, "mce_g": [0.45]}).mce == (0.45,)


def test_levels_from_return_periods():
    a = {"stripes_g": [0.1, 0.2, 0.3, 0.5, 0.8], "design_return_period_yr": [475],
         "mce_return_period_yr": 2475, "hazard": CURVE}  # fmt: skip
    lv = resolve_levels(a)
    # 1/475 = 2.1e-3 is the curve's 0.2 g point; 1/2475 = 4.04e-4 is just below its 0.4 g point
    assert lv.design == pytest.approx((0.2,), rel=2e-3) and 0.39 < lv.mce[0] < 0.41
    assert lv.design_basis == ("the 475-year level of the curve given inline",)
    assert "2475-year" in lv.mce_basis[0]


@pytest.mark.parametrize(
    "change, words",
    [
        ({"design_return_period_yr": [475], "hazard": None}, "read off the site's hazard curve"),
        ({"design_return_period_yr": [475], "design_g": [0.3]}, "give design_g or design_return_period_yr"),
        (
            {"design_return_period_yr": [100000]},
            "100000 years .annual rate 1e-05. is outside the hazard curve",
        ),
        ({"design_return_period_yr": [60]}, "design_return_period_yr: 0.0564 g is outside the stripes"),
        ({"mce_return_period_yr": 2475, "mce_g": 0.5}, "give mce_g or mce_return_period_yr"),
    ],
)
def test_the_configuration_refuses_levels_it_cannot_read(tmp_path, monkeypatch, change, words):
    monkeypatch.chdir(tmp_path)
    a = {"objects": [{"name": "s", "height_m": 1.8, "width_m": 0.6, "friction": 0.5}], "cases": ["none"],
         "stripes_g": [0.1, 0.2, 0.3, 0.5, 0.8], "design_g": [], "hazard": CURVE}  # fmt: skip
    a.update(change)
    cfg = {"isolation": {"rho": 0.5, "cases": [{"name": "none", "kind": "none"}]}, "assessment": a}
    with pytest.raises(ConfigError, match=words):
        workflow_config(cfg)
