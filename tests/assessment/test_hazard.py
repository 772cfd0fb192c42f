"""The risk integral (isorock.assessment.hazard) against its closed form: a lognormal fragility and a
power-law hazard curve ``H = k0 x^-k`` give ``lambda = k0 theta^-k exp(k^2 beta^2 / 2)``; and the
curve's checks and bounds."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import norm

from isorock.assessment.hazard import HazardCurve, lognormal_powerlaw_rate, probability_in, risk_integral
from isorock.assessment.hazard_files import curve_from_config
from isorock.errors import ConfigError


@pytest.mark.parametrize(
    "theta, beta, k0, k", [(0.6, 0.4, 1e-4, 2.5), (0.25, 0.6, 3e-4, 1.8), (1.2, 0.2, 1e-5, 3.2)]
)
def test_risk_integral_matches_the_closed_form(theta, beta, k0, k):
    # a power-law curve sampled at a few points, wide enough that the ends hold no probability
    x = np.geomspace(theta * math.exp(-8 * beta), theta * math.exp(8 * beta), 7)
    curve = HazardCurve(x, k0 * x**-k)
    r = risk_integral(lambda q: norm.cdf(np.log(q / theta) / beta), curve)
    exact = lognormal_powerlaw_rate(theta, beta, k0, k)
    # above the last point the exceedances count at P(x_n) ~ 1: the closed form's tail, almost exactly
    assert r.annual_rate == pytest.approx(exact, rel=1e-6)
    assert r.p_at_first < 1e-12 and r.above_last_max < 1e-9 * exact
    assert probability_in(r.annual_rate, 50) == pytest.approx(1 - math.exp(-50 * exact), rel=1e-6)


def test_a_short_curve_says_what_it_leaves_out():
    theta, beta = 0.5, 0.5
    x = np.array([0.05, 0.1, 0.2, 0.4])  # ends below the median: most failures come from above it
    curve = HazardCurve(x, 1e-3 * (x / 0.05) ** -2.0)
    r = risk_integral(lambda q: norm.cdf(np.log(q / theta) / beta), curve)
    p_last = norm.cdf(np.log(0.4 / theta) / beta)
    assert r.above_last_max == pytest.approx(curve.annual_rate[-1] * (1 - p_last))
    assert r.annual_rate < lognormal_powerlaw_rate(theta, beta, 1e-3 * 0.05**2, 2.0)  # a lower bound


def test_curve_checks(tmp_path):
    with pytest.raises(ConfigError, match="at least 3"):
        HazardCurve(np.array([0.1, 0.2]), np.array([1e-2, 1e-3]))
    with pytest.raises(ConfigError, match="decrease"):
        HazardCurve(np.array([0.1, 0.2, 0.3]), np.array([1e-2, 1e-3, 2e-3]))
    f = tmp_path / "h.csv"
    f.write_text("level,annual_rate\n0.1,1e-2\n0.2,x\n")
    with pytest.raises(ConfigError, match=r"h.csv:3: expected two numbers"):
        HazardCurve.from_csv(f)
    f.write_text("level,annual_rate\n0.1,1e-2\n0.2,1e-3\n0.4,1e-4\n")
    c = curve_from_config({"file": "h.csv"}, tmp_path)
    assert c.rate(0.2) == pytest.approx(1e-3) and math.isnan(float(c.rate(0.5)))  # not extrapolated
    assert c.rate(math.sqrt(0.02)) == pytest.approx(math.sqrt(1e-5))  # log-log between points


def test_both_tails_of_a_curve_that_ends_too_early():
    """A strong object (theta 1.5 g, beta 0.4) on a power-law curve that ends at 1 g: the truncated value
    (exceedances of 1 g counted at P(D | 1 g)) is half the closed form of the whole power law (the
    review found -36 % on another curve); counting them as failures bounds it from above; the two are
    said to differ."""
    theta, beta, k0, k = 1.5, 0.4, 1e-4, 2.5
    x = np.array([0.05, 0.1, 0.2, 0.4, 0.6, 1.0])
    curve = HazardCurve(x, k0 * x**-k)
    r = risk_integral(lambda q: norm.cdf(np.log(q / theta) / beta), curve)
    exact = lognormal_powerlaw_rate(theta, beta, k0, k)
    assert r.annual_rate == pytest.approx(0.49 * exact, rel=0.02)
    assert r.annual_rate < exact < r.upper and r.tails_differ
    assert r.upper == pytest.approx(
        r.annual_rate + curve.annual_rate[-1] * (1 - norm.cdf(np.log(1 / 1.5) / 0.4))
    )
    # a weak object: the curve's end holds nothing more, the two tails agree
    w = risk_integral(lambda q: norm.cdf(np.log(q / 0.15) / 0.3), curve)
    assert not w.tails_differ and w.upper == pytest.approx(w.annual_rate, rel=1e-3)


def test_a_level_read_off_the_curve_by_its_return_period():
    x = np.array([0.1, 0.2, 0.4, 0.8])
    curve = HazardCurve(x, 1e-2 * (x / 0.1) ** -2.0)  # 100, 400, 1600, 6400 years
    assert curve.level_at_return_period(400) == pytest.approx(0.2)
    assert curve.level_at_return_period(800) == pytest.approx(0.2 * math.sqrt(2))  # log-log
    assert curve.rate(curve.level_at_return_period(2475)) == pytest.approx(1 / 2475)
    with pytest.raises(ConfigError, match=r"design_return_period_yr: 10000 years .* not extrapolated"):
        curve.level_at_return_period(10000, "design_return_period_yr")
