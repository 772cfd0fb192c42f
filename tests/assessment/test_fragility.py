"""The maximum-likelihood lognormal fragility fit (Baker 2015) against an independent fit: the same
likelihood is a probit regression on ln(x), ``P = Phi(a + b ln x)`` with ``beta = 1/b`` and
``median = exp(-a/b)``, solved here by Fisher scoring (iteratively reweighted least squares); the
fits that cannot be estimated; the exact binomial bounds; the bootstrap's intervals."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import norm

from isorock.assessment.fragility import (
    BETA_MAX,
    bootstrap_cloud,
    bootstrap_fragility,
    clopper_pearson,
    fit_fragility,
    resample_weights,
)
from isorock.errors import ParameterError


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


def test_degenerate_fits_are_not_estimable_never_0_or_1():
    """No damage, every run damaged, separated stripes (completely or but for one stripe), damage falling
    with the level: not estimable, NaN parameters and probabilities, the reason in the note."""
    cases = [
        (([0.1, 0.2], [5, 5], [0, 0]), "no damage in 10 runs up to 0.2"),
        (([0.1, 0.2], [5, 5], [5, 5]), "every run damaged from 0.1"),
        (([0.1, 0.2, 0.3], [5, 5, 5], [0, 5, 5]), "separate"),
        (([0.1, 0.2, 0.3], [5, 5, 5], [0, 2, 5]), "separate"),
        (([0.1, 0.2, 0.3, 0.4], [5, 5, 5, 5], [0, 0, 0, 1]), "separate"),
        (([0.1, 0.2, 0.3], [5, 5, 5], [3, 2, 0]), "does not increase"),
    ]
    for args, words in cases:
        f = fit_fragility(*args)
        assert not f.estimable and math.isnan(f.median) and math.isnan(f.beta), args
        assert words in f.note and f.note.startswith("not estimable"), f.note
        assert math.isnan(f.probability(0.25))
    with pytest.raises(ParameterError):
        fit_fragility([0.1, -0.2], [5, 5], [1, 2])


def test_a_flat_or_far_fit_is_not_estimable():
    """A flat stripe pattern (3, 4, 3, 4 ... of 16) has a maximum of the likelihood, at beta ~ 27 and a
    median of ~5e8 g: no fragility. Nor is a median read far beyond the highest stripe."""
    x = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.8, 1.0]
    flat = fit_fragility(x, [16] * 8, [3, 4, 3, 4, 3, 4, 3, 4])
    assert not flat.estimable and "above 2" in flat.note and flat.note.startswith("not estimable")
    far = fit_fragility(x, [32] * 8, [0, 0, 0, 1, 0, 0, 1, 1])  # median 16.8 g, beta 1.6
    assert not far.estimable and "beyond 10 times the highest level (1)" in far.note, far.note
    # a regular one, for contrast
    ok = fit_fragility(x, [16] * 8, [0, 1, 3, 6, 9, 11, 14, 15])
    assert ok.estimable and ok.note == "" and 0.2 < ok.median < 0.6 and ok.beta < BETA_MAX


def test_resamples_are_shared_by_every_fit_of_one_record_set():
    """The same records and seed give the same resamples: two damage states, two bases, a cloud."""
    W = resample_weights(12, 300, seed=4)
    assert W.shape == (300, 12) and np.all(W.sum(1) == 12)
    assert np.array_equal(W, resample_weights(12, 300, seed=4))
    x = np.array([0.1, 0.3, 0.6, 1.0])
    rng = np.random.default_rng(1)
    D = x[None, :] >= rng.lognormal(np.log(0.4), 0.5, (12, 1))
    a = bootstrap_fragility(x, D, n_boot=300, seed=4)
    b = bootstrap_fragility(x, D, weights=W)
    assert np.array_equal(a.a, b.a) and np.array_equal(a.status, b.status)
    # the cloud of the same runs (one point per run) on the same resamples
    rec = np.repeat(np.arange(12), x.size)
    c = bootstrap_cloud(np.tile(x, 12), D.ravel(), rec, W)
    assert c.fit.median == pytest.approx(a.fit.median, rel=1e-6) and c.n_boot == 300
    assert c.beta_ci95 == pytest.approx(a.beta_ci95, rel=1e-6)
    with pytest.raises(ValueError):  # a ParameterError is a ValueError
        fit_fragility([0.1, 0.2], [5, 5], [1, 6])


def test_clopper_pearson_against_its_closed_forms():
    """0 of n: the one-sided 95 % bound is 1 - 0.05^(1/n) (17 % for 16 records, the issue's example); the
    two-sided bounds of k of n are the Beta quantiles, checked here against the binomial tails."""
    from scipy.stats import binom

    assert clopper_pearson(0, 16, side="upper")[1] == pytest.approx(1 - 0.05 ** (1 / 16))
    assert clopper_pearson(0, 16, side="upper")[1] == pytest.approx(0.171, abs=5e-4)
    lo, hi = clopper_pearson(3, 10)
    assert binom.sf(2, 10, lo) == pytest.approx(0.025, rel=1e-6)  # P(X >= 3 | lo) = 2.5 %
    assert binom.cdf(3, 10, hi) == pytest.approx(0.025, rel=1e-6)  # P(X <= 3 | hi) = 2.5 %
    assert clopper_pearson(10, 10)[1] == 1.0 and clopper_pearson(0, 10)[0] == 0.0


def test_clopper_pearson_equals_the_beta_quantiles_on_every_count():
    """scipy.stats.binomtest's exact interval (what clopper_pearson calls) equals the Beta-quantile
    form of Clopper & Pearson, two-sided and one-sided upper, for every k of n up to 60 records."""
    from scipy.stats import beta

    for n in range(1, 61):
        for k in range(n + 1):
            lo, hi = clopper_pearson(k, n)
            assert lo == pytest.approx(0.0 if k == 0 else beta.ppf(0.025, k, n - k + 1), abs=1e-9)
            assert hi == pytest.approx(1.0 if k == n else beta.ppf(0.975, k + 1, n - k), abs=1e-9)
            lo1, hi1 = clopper_pearson(k, n, conf=0.9, side="upper")
            assert lo1 == 0.0
            assert hi1 == pytest.approx(1.0 if k == n else beta.ppf(0.9, k + 1, n - k), abs=1e-9)
    with pytest.raises(ValueError, match="side"):
        clopper_pearson(1, 2, side="lower")


def test_bootstrap_intervals_cover_the_truth_at_the_nominal_rate():
    """Records with lognormal capacities (median 0.4 g, beta 0.4), 20 records at 7 stripes: over 60
    independent record sets the 95 % interval of the median covers 0.4 g in most (>= 85 %; the
    percentile bootstrap of a small sample is a little narrow), and its width shrinks with more records."""
    x = np.array([0.1, 0.2, 0.3, 0.4, 0.55, 0.7, 0.9])
    rng = np.random.default_rng(11)

    def interval(n_rec: int):
        cap = np.exp(np.log(0.4) + 0.4 * rng.standard_normal(n_rec))
        e = bootstrap_fragility(
            x, x[None, :] >= cap[:, None] * rng.lognormal(0, 0.15, (n_rec, 1)), n_boot=300
        )
        return e.median_ci95

    cover = [ci is not None and ci[0] <= 0.4 <= ci[1] for ci in (interval(20) for _ in range(60))]
    assert np.mean(cover) >= 0.85
    w20 = np.median([np.diff(interval(20))[0] for _ in range(10)])
    w80 = np.median([np.diff(interval(80))[0] for _ in range(10)])
    assert w80 < 0.7 * w20


def test_bootstrap_is_reproducible_and_counts_its_resamples():
    x = [0.1, 0.2, 0.4, 0.8]
    D = np.array([[0, 0, 1, 1], [0, 1, 1, 1], [0, 0, 0, 1], [0, 0, 1, 1], [0, 0, 0, 0], [1, 1, 1, 1]], bool)
    a = bootstrap_fragility(x, D, n_boot=500, seed=3)
    b = bootstrap_fragility(x, D, n_boot=500, seed=3)
    assert a.median_ci95 == b.median_ci95 and a.n_boot == 500 and 0 < a.n_boot_fitted <= 500
    lo, hi = a.probability_ci95(0.3)
    assert 0.0 <= lo < a.fit.probability(0.3) < hi <= 1.0


def test_fits_normal_log_functions_are_scipys_numbers():
    """The probit fits' log-cdf and log-pdf (without scipy.stats' per-call checks) give scipy.stats.norm's
    numbers bit for bit, infinities and NaN included: the assessment's tables do not change."""
    from isorock.assessment import fragility

    rng = np.random.default_rng(3)
    s = np.concatenate(
        [rng.normal(0, 3, 2000), rng.normal(0, 40, 200), [0.0, -0.0, 1e-300, -38.5, 40.0, 8.3, -8.3]]
    )
    s = np.concatenate([s, [np.inf, -np.inf, np.nan]]).reshape(-1, 10)
    np.testing.assert_array_equal(fragility._norm_logcdf(s), norm.logcdf(s))
    np.testing.assert_array_equal(fragility._norm_logcdf(-s), norm.logcdf(-s))
    np.testing.assert_array_equal(fragility._norm_logpdf(s), norm.logpdf(s))


def _separated_one_row_at_a_time(lx, n, z):
    """The separation test written row by row (the definition the vectorised one must follow)."""
    u, inv = np.unique(lx, return_inverse=True)
    out = np.zeros(n.shape[0], dtype=bool)
    for i in range(n.shape[0]):
        ni = np.bincount(inv, weights=n[i], minlength=u.size)
        zi = np.bincount(inv, weights=z[i], minlength=u.size)
        v = ni > 0
        f = zi[v] / ni[v]
        if f.size == 0:
            continue
        zeros = int(np.argmax(f != 0)) if np.any(f != 0) else f.size
        ones = int(np.argmax(f[::-1] != 1)) if np.any(f != 1) else f.size
        out[i] = zeros + ones >= f.size - 1
    return out


@pytest.mark.parametrize("seed", range(6))
def test_separation_of_many_rows_is_that_of_each_row(seed):
    """The separation test of all rows at once (a bootstrap's thousands) answers as each row alone:
    stripes and clouds with ties, levels without runs, rows with no runs at all, none or all damaged."""
    from isorock.assessment import fragility

    rng = np.random.default_rng(seed)
    levels = rng.integers(2, 9)
    lx = np.log(rng.choice([0.1, 0.2, 0.3, 0.4, 0.6], size=levels))  # ties: a cloud's repeated levels
    n = rng.integers(0, 4, size=(300, levels)).astype(float)
    n[:5] = 0.0  # rows without runs
    z = np.minimum(n, rng.integers(0, 4, size=(300, levels))).astype(float)
    z[5:20] = n[5:20]  # every run damaged
    z[20:35] = 0.0  # none damaged
    order = np.argsort(lx)  # separated by construction: damaged above a threshold only
    z[35:60] = np.where(np.arange(levels)[np.argsort(order)] >= levels // 2, n[35:60], 0.0)
    got = fragility._separated(lx, n, z)
    np.testing.assert_array_equal(got, _separated_one_row_at_a_time(lx, n, z))
    assert got[35:60].all() and got[5:35].all() and not got[:5].any()
