"""The maximum-likelihood lognormal fragility fit (Baker 2015) against an independent fit: the same
likelihood is a probit regression on ln(x), ``P = Phi(a + b ln x)`` with ``beta = 1/b`` and
``median = exp(-a/b)``, solved here by Newton's method (iteratively reweighted least squares)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import norm

from isorock.assessment.fragility import BETA_MIN, fit_fragility


def _probit_irls(x, n, z, iters: int = 100) -> tuple[float, float]:
    """(median, beta) of the binomial probit model on ln(x), by Newton-Raphson on the log-likelihood."""
    X = np.column_stack([np.ones(len(x)), np.log(x)])
    n, z = np.asarray(n, float), np.asarray(z, float)
    w = np.array([0.0, 1.0])
    for _ in range(iters):
        eta = X @ w
        p = np.clip(norm.cdf(eta), 1e-12, 1 - 1e-12)
        phi = norm.pdf(eta)
        # score and Fisher information of the binomial probit model
        score = X.T @ ((z - n * p) * phi / (p * (1 - p)))
        info = (X * (n * phi**2 / (p * (1 - p)))[:, None]).T @ X
        step = np.linalg.solve(info, score)
        w = w + step
        if np.max(np.abs(step)) < 1e-12:
            break
    a, b = w
    return math.exp(-a / b), 1.0 / b


@pytest.mark.parametrize(
    "x, n, z",
    [
        ([0.1, 0.2, 0.3, 0.5, 0.8], [20] * 5, [0, 2, 6, 12, 19]),
        ([0.1, 0.2, 0.3, 0.5], [10] * 4, [0, 3, 2, 7]),  # non-monotone: kept as observed
        ([0.05, 0.1, 0.2, 0.4, 0.8, 1.6], [22] * 6, [0, 1, 4, 9, 15, 21]),
        ([0.3, 0.6, 0.9], [7, 7, 6], [1, 4, 5]),
    ],
)
def test_mle_matches_an_independent_probit_fit(x, n, z):
    f = fit_fragility(x, n, z)
    median, beta = _probit_irls(x, n, z)
    assert f.note == ""
    assert f.median == pytest.approx(median, rel=1e-4)
    assert f.beta == pytest.approx(beta, rel=1e-4)
    # and it is the maximum: the likelihood is lower at nearby parameters
    lx = np.log(x)

    def ll(m, b):
        s = (lx - math.log(m)) / b
        return float(np.sum(np.asarray(z) * norm.logcdf(s) + (np.asarray(n) - z) * norm.logcdf(-s)))

    assert f.log_likelihood == pytest.approx(ll(f.median, f.beta), rel=1e-9)
    for dm, db in ((1.02, 1.0), (0.98, 1.0), (1.0, 1.05), (1.0, 0.95)):
        assert ll(f.median * dm, f.beta * db) < f.log_likelihood


def test_recovers_the_parameters_of_simulated_stripes():
    """Many records per stripe drawn from a known fragility: the fit converges to it."""
    rng = np.random.default_rng(7)
    x = np.array([0.1, 0.2, 0.3, 0.4, 0.6, 0.8, 1.0])
    n = np.full(x.size, 4000)
    z = rng.binomial(n, norm.cdf(np.log(x / 0.45) / 0.35))
    f = fit_fragility(x, n, z)
    assert f.median == pytest.approx(0.45, rel=0.02) and f.beta == pytest.approx(0.35, rel=0.05)
    assert f.probability(0.45) == pytest.approx(0.5, abs=0.02)


def test_undefined_and_degenerate_fits_are_reported_not_extrapolated():
    none = fit_fragility([0.1, 0.2], [5, 5], [0, 0])
    assert math.isnan(none.median) and "above 0.2" in none.note and none.probability(1.0) == 0.0
    every = fit_fragility([0.1, 0.2], [5, 5], [5, 5])
    assert math.isnan(every.median) and "below 0.1" in every.note and every.probability(0.01) == 1.0
    sep = fit_fragility([0.1, 0.2, 0.3], [5, 5, 5], [0, 5, 5])
    assert sep.beta == BETA_MIN and 0.1 < sep.median < 0.2 and "separate" in sep.note
    with pytest.raises(ValueError):
        fit_fragility([0.1, -0.2], [5, 5], [1, 2])
    with pytest.raises(ValueError):
        fit_fragility([0.1, 0.2], [5, 5], [1, 6])
