"""isorock's probit fit (vectorised damped Newton) against statsmodels' GLM probit (issue 25).

The fragility of :mod:`isorock.assessment.fragility` is a binomial probit regression on ``ln x``,
maximised by damped Newton steps vectorised over the bootstrap resamples. statsmodels' ``GLM`` with
``Binomial(link=Probit())`` maximises the same likelihood by IRLS, one fit at a time. This script
fits both to the same multiple-stripe data and reports:

* agreement: the largest relative difference of the median and of beta between the two, and which
  reached the higher log-likelihood, over many synthetic record sets (records with lognormal
  capacities, the kind of data an assessment produces: 6 to 40 records, 5 to 9 stripes);
* the separated sets (every stripe below some level undamaged, every one above damaged): isorock calls
  them not estimable; what statsmodels returns there;
* the time of one record set's 1000 bootstrap refits: isorock's one vectorised call against 1000
  GLM fits (a ratio, measured in this run).

Usage (statsmodels is not a dependency of isorock; install it to run this)::

    pip install statsmodels
    python benchmarks/compare_probit_glm.py [--sets 300] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import math
import time
import warnings

import numpy as np

from isorock.assessment.fragility import bootstrap_fragility, fit_fragility, resample_weights


def _glm(lx: np.ndarray, n: np.ndarray, z: np.ndarray):
    import statsmodels.api as sm

    X = sm.add_constant(lx)
    y = np.column_stack([z, n - z])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return sm.GLM(y, X, family=sm.families.Binomial(link=sm.families.links.Probit())).fit()


def _loglik(a: float, b: float, lx: np.ndarray, n: np.ndarray, z: np.ndarray) -> float:
    from scipy.stats import norm

    s = a + b * lx
    return float(np.sum(z * norm.logcdf(s) + (n - z) * norm.logcdf(-s)))


def _record_set(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Per-record outcomes (records x stripes) of records with lognormal capacities."""
    n_rec = int(rng.integers(6, 41))
    n_lev = int(rng.integers(5, 10))
    median, beta = float(rng.uniform(0.2, 1.0)), float(rng.uniform(0.2, 0.7))
    levels = median * np.exp(np.linspace(-1.6, 1.6, n_lev) * beta)
    cap = median * np.exp(beta * rng.standard_normal(n_rec))
    return levels, cap[:, None] <= levels[None, :]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sets", type=int, default=300, help="synthetic record sets (default 300)")
    ap.add_argument("--seed", type=int, default=1, help="seed of the record sets (default 1)")
    ap.add_argument("--json", help="write the figures to this JSON file")
    a = ap.parse_args()
    rng = np.random.default_rng(a.seed)
    d_med, d_beta, d_ll = [], [], []
    separated = {"sets": 0, "glm_converged": 0, "glm_beta_min": math.inf}
    for _ in range(a.sets):
        levels, D = _record_set(rng)
        n = np.full(levels.size, D.shape[0], dtype=float)
        z = D.sum(0).astype(float)
        fit = fit_fragility(levels, n, z)
        lx = np.log(levels)
        if not fit.estimable:
            if 0 < z.sum() < n.sum():
                r = _glm(lx, n, z)
                separated["sets"] += 1
                separated["glm_converged"] += bool(r.converged)
                if r.params[1] > 0:
                    separated["glm_beta_min"] = min(separated["glm_beta_min"], 1.0 / r.params[1])
            continue
        r = _glm(lx, n, z)
        b0, b1 = float(r.params[0]), float(r.params[1])
        d_med.append(abs(math.exp(-b0 / b1) / fit.median - 1.0))
        d_beta.append(abs((1.0 / b1) / fit.beta - 1.0))
        ours = fit.log_likelihood
        d_ll.append(ours - _loglik(b0, b1, lx, n, z))
    # the bootstrap of one typical set: 20 records, 7 stripes
    cap = 0.4 * np.exp(0.4 * np.random.default_rng(7).standard_normal(20))
    levels = 0.4 * np.exp(np.linspace(-1.2, 1.2, 7) * 0.4)
    D = cap[:, None] <= levels[None, :]
    W = resample_weights(D.shape[0], 1000, 0)
    t0 = time.perf_counter()
    bootstrap_fragility(levels, D, weights=W)
    t_ours = time.perf_counter() - t0
    lx = np.log(levels)
    t0 = time.perf_counter()
    for w in W:
        nb, zb = w @ np.ones_like(D, dtype=float), w @ D.astype(float)
        if 0 < zb.sum() < nb.sum():
            _glm(lx, nb, zb)
    t_glm = time.perf_counter() - t0
    out = {
        "estimable_sets": len(d_med),
        "median_rel_diff_max": float(np.max(d_med)),
        "beta_rel_diff_max": float(np.max(d_beta)),
        "loglik_ours_minus_glm_min": float(np.min(d_ll)),
        "loglik_ours_minus_glm_max": float(np.max(d_ll)),
        "separated": separated,
        "bootstrap_1000_glm_over_ours": t_glm / t_ours,
    }
    print(f"{len(d_med)} estimable record sets of {a.sets}:")
    print(f"  median: largest relative difference {out['median_rel_diff_max']:.1e}")
    print(f"  beta:   largest relative difference {out['beta_rel_diff_max']:.1e}")
    print(
        f"  log-likelihood, isorock minus GLM: {out['loglik_ours_minus_glm_min']:.1e} to "
        f"{out['loglik_ours_minus_glm_max']:.1e}"
    )
    print(
        f"{separated['sets']} separated sets (isorock: not estimable): GLM said converged on "
        f"{separated['glm_converged']}, its smallest beta {separated['glm_beta_min']:.2g}"
    )
    print(f"1000 bootstrap refits of 20 records x 7 stripes: GLM / isorock time = {t_glm / t_ours:.0f}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f, indent=2)


if __name__ == "__main__":
    main()
