"""Lognormal fragility functions fitted by maximum likelihood to multiple-stripe analysis results, with
their uncertainty.

Baker (2015), "Efficient analytical fragility function fitting using dynamic structural analysis",
Earthquake Spectra 31(1), 579-599: at each intensity level ``x_j`` (a stripe) ``n_j`` records are
scaled to ``x_j`` and ``z_j`` of them reach the damage state (overturning, failure, uplift). With
``P(D | x) = Phi(ln(x / theta) / beta)`` the stripes are independent binomial observations, and the
fragility is the ``(theta, beta)`` that maximises

    sum_j [ z_j ln Phi(ln(x_j/theta)/beta) + (n_j - z_j) ln(1 - Phi(ln(x_j/theta)/beta)) ] .

No monotonicity is imposed on the data (a record may overturn the block at one level and not at a
higher one, the non-monotone boundary of rocking): every stripe enters with its own count.

The likelihood is that of a probit regression on ``ln x`` (``P = Phi(a + b ln x)``, ``beta = 1/b``,
``theta = exp(-a/b)``), which is concave in ``(a, b)``: it is maximised by Newton's method
(:func:`_probit_newton`), vectorised over the bootstrap resamples.

**Estimable or not.** The maximum does not exist when no run is damaged, when every run is, or when
the stripes separate the outcomes (the likelihood grows without bound as ``beta`` goes to 0); nor is
a fit with ``b <= 0`` a fragility (damage no more likely at a higher level). A maximum that exists
but describes no fragility is refused too: ``beta`` above :data:`BETA_MAX` (a flat stripe pattern,
3, 4, 3, 4 ... of 16, fits beta 27 and a median of 5.6e8 g: damage that hardly depends on the
intensity) or a median beyond :data:`MEDIAN_MAX_FACTOR` times the highest level (a median read far
outside the data). Such a fit is reported as *not estimable* (:attr:`Fragility.estimable` False, NaN
parameters, :attr:`Fragility.note` saying why): never as a number from a clamped ``beta``, never as
a probability of 0 or 1. What was observed is then what is reported, with its exact binomial bounds
(:func:`clopper_pearson`).

**Uncertainty.** :func:`bootstrap_fragility` resamples the records with replacement (a record is the
unit: it is run at every stripe) and refits each resample; the 95 % intervals of the median, of
``beta`` and of the probability at any level are the 2.5th and 97.5th percentiles over the resamples
(the percentile bootstrap, Efron & Tibshirani 1993, ch. 13). The resamples are drawn once per record
set and seed (:func:`resample_weights`): every fit of the same records (another damage state, another
isolator, another intensity measure) sees the same resamples, so that two of them can be compared
resample by resample (:mod:`isorock.assessment.design`). :func:`bootstrap_cloud` does the same for a
cloud of runs (one point per run, against a measure that differs record by record: PGV, Sa).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field

import numpy as np

# ndtr is what scipy.stats.norm.cdf computes (loc 0, scale 1), the same numbers without its checks of
# the arguments; scipy.stats (binomtest) is imported where it is used: it costs a job's start a second
from scipy.special import log_ndtr, ndtr

from isorock.errors import ParameterError

__all__ = [
    "BETA_MIN",
    "BETA_MAX",
    "MEDIAN_MAX_FACTOR",
    "N_BOOTSTRAP",
    "Fragility",
    "FragilityEstimate",
    "fit_fragility",
    "bootstrap_fragility",
    "bootstrap_cloud",
    "resample_weights",
    "clopper_pearson",
]

#: a fitted dispersion below this is taken as separation (the maximum is at beta -> 0) [-]
BETA_MIN = 0.02
#: a fitted dispersion above this is not a fragility: damage hardly depends on the intensity [-]
#: (fragilities of rocking objects and of structures fitted from stripes have beta of 0.2 to 1)
BETA_MAX = 2.0
#: a fitted median beyond this multiple of the highest level is not estimable: read too far from
#: the data to mean anything [-]
MEDIAN_MAX_FACTOR = 10.0
#: bootstrap resamples of the records, unless the configuration says otherwise
N_BOOTSTRAP = 1000

# status of a fit (of the data or of a resample)
_OK, _NONE, _ALL, _SEPARATED = 0, 1, 2, 3


@dataclass(frozen=True)
class Fragility:
    """A lognormal fragility function ``P(D | x) = Phi(ln(x / median) / beta)``, or why there is none.

    Attributes
    ----------
    median : float
        Median capacity ``theta``, in the unit of the intensity measure (g for PGA); NaN when not
        estimable.
    beta : float
        Logarithmic standard deviation [-]; NaN when not estimable.
    n_levels : int
        Stripes used.
    n_runs : int
        Analyses used.
    n_damaged : int
        Analyses that reached the damage state.
    log_likelihood : float
        Log-likelihood at the fit [-] (NaN when not estimable).
    note : str
        "" for a regular fit; otherwise why it is not estimable, or what limits it.
    """

    median: float
    beta: float
    n_levels: int
    n_runs: int
    n_damaged: int
    log_likelihood: float
    note: str = ""

    @property
    def estimable(self) -> bool:
        """Both parameters are finite: the maximum-likelihood fit exists."""
        return math.isfinite(self.median) and math.isfinite(self.beta)

    @property
    def defined(self) -> bool:
        """The same as :attr:`estimable` (the name of earlier versions)."""
        return self.estimable

    def probability(self, x: float | np.ndarray) -> float | np.ndarray:
        """``P(D | x)`` [-] at intensity ``x`` (same unit as the median); NaN when not estimable."""
        if not self.estimable:
            return np.full(np.shape(x), math.nan) if np.ndim(x) else math.nan
        p = ndtr(np.log(np.asarray(x, dtype=float) / self.median) / self.beta)
        return float(p) if np.ndim(p) == 0 else p

    def to_dict(self) -> dict:
        d = asdict(self)
        d["estimable"] = self.estimable
        return d


@dataclass(frozen=True)
class FragilityEstimate:
    """A fragility with its bootstrap over records.

    Attributes
    ----------
    fit : Fragility
        The fit of all the data.
    a, b : numpy.ndarray
        Probit parameters of each resample (``P = Phi(a + b ln x)``); meaningful where ``status`` is 0.
    status : numpy.ndarray of int
        Per resample: 0 fitted, 1 no damage, 2 all damaged, 3 separated or not increasing.
    """

    fit: Fragility
    a: np.ndarray = field(repr=False)
    b: np.ndarray = field(repr=False)
    status: np.ndarray = field(repr=False)

    @property
    def n_boot(self) -> int:
        """Resamples drawn."""
        return int(self.status.size)

    @property
    def n_boot_fitted(self) -> int:
        """Resamples whose fit is estimable."""
        return int(np.sum(self.status == _OK))

    def _interval(self, values: np.ndarray) -> list[float] | None:
        ok = self.status == _OK
        if not self.fit.estimable or not ok.any():
            return None
        lo, hi = np.percentile(values[ok], [2.5, 97.5])
        return [float(lo), float(hi)]

    @property
    def median_ci95(self) -> list[float] | None:
        """95 % interval of the median (over the resamples that could be fitted); None when not estimable."""
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            return self._interval(np.exp(-self.a / self.b))

    @property
    def beta_ci95(self) -> list[float] | None:
        """95 % interval of beta (over the resamples that could be fitted); None when not estimable."""
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            return self._interval(1.0 / self.b)

    def resampled_probability(self, x: float) -> np.ndarray:
        """``P(D | x)`` of every resample [-]: the fitted curve; 0 for a resample with no damage, 1 for
        one with every run damaged; a separated resample's curve is its steep limit."""
        p = ndtr(self.a + self.b * math.log(x))
        p = np.where(self.status == _NONE, 0.0, p)
        return np.where(self.status == _ALL, 1.0, p)

    def probability_ci95(self, x: float) -> list[float] | None:
        """95 % interval of ``P(D | x)`` [-] over all the resamples; None when not estimable."""
        if not self.fit.estimable or self.n_boot == 0:
            return None
        lo, hi = np.percentile(self.resampled_probability(x), [2.5, 97.5])
        return [float(lo), float(hi)]

    def summary(self) -> dict:
        """JSON-ready: ``median_g``, ``beta``, ``median_ci95_g``, ``beta_ci95``, ``estimable``, counts,
        ``note``, ``n_boot``, ``n_boot_fitted``."""
        f = self.fit
        return {
            "median_g": f.median if f.estimable else None,
            "beta": f.beta if f.estimable else None,
            "median_ci95_g": self.median_ci95,
            "beta_ci95": self.beta_ci95,
            "estimable": f.estimable,
            "n_levels": f.n_levels,
            "n_runs": f.n_runs,
            "n_damaged": f.n_damaged,
            "note": f.note,
            "n_boot": self.n_boot,
            "n_boot_fitted": self.n_boot_fitted,
        }


def clopper_pearson(k: int, n: int, conf: float = 0.95, side: str = "two") -> tuple[float, float]:
    """Exact binomial (Clopper-Pearson 1934) confidence interval of a proportion ``k / n``.

    Parameters
    ----------
    k, n : int
        Successes and trials (``0 <= k <= n``, ``n >= 1``).
    conf : float
        Confidence level [-].
    side : {"two", "upper"}
        ``"two"``: the two-sided interval; ``"upper"``: the one-sided upper bound (lower bound 0), as
        "0 failures in 16 records: at most 17 % at 95 %".

    Returns
    -------
    (float, float)
        Lower and upper bound [-].
    """
    if not (n >= 1 and 0 <= k <= n):
        raise ParameterError(f"clopper_pearson: k={k}, n={n}: need 0 <= k <= n and n >= 1")
    if side not in ("two", "upper"):
        raise ParameterError(f"clopper_pearson: side={side!r}: need 'two' or 'upper'")
    return _exact_interval(int(k), int(n), float(conf), side)


@functools.lru_cache(maxsize=4096)
def _exact_interval(k: int, n: int, conf: float, side: str) -> tuple[float, float]:
    """:func:`clopper_pearson` of checked arguments, kept: an assessment asks for the same few counts
    hundreds of times (the same k of the same n records at every base and level), and each is a root
    search of scipy's."""
    # scipy's exact (Clopper-Pearson) interval; the one-sided upper bound is that of the test against
    # the alternative "less" (its lower bound is 0)
    from scipy.stats import binomtest

    test = binomtest(k, n, alternative="two-sided" if side == "two" else "less")
    ci = test.proportion_ci(confidence_level=conf, method="exact")
    return float(ci.low), float(ci.high)


#: log(sqrt(2 pi)), as scipy.stats.norm.logpdf subtracts it
_LOG_SQRT_2PI = np.log(np.sqrt(2 * np.pi))


def _norm_logcdf(s: np.ndarray) -> np.ndarray:
    """``scipy.stats.norm.logcdf(s)``, the same numbers without its per-call checks of the arguments
    (loc 0, scale 1: the fits call it some 40 000 times per assessment)."""
    return log_ndtr(s)


def _norm_logpdf(s: np.ndarray) -> np.ndarray:
    """``scipy.stats.norm.logpdf(s)``, the same numbers (its formula) without its per-call checks."""
    return -(s**2) / 2.0 - _LOG_SQRT_2PI


def _loglik(a: np.ndarray, b: np.ndarray, lx: np.ndarray, n: np.ndarray, z: np.ndarray) -> np.ndarray:
    s = a[:, None] + b[:, None] * lx[None, :]
    return np.sum(z * _norm_logcdf(s) + (n - z) * _norm_logcdf(-s), axis=1)


def _probit_newton(
    lx: np.ndarray, n: np.ndarray, z: np.ndarray, a0: np.ndarray, b0: np.ndarray, iters: int = 100
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Maximise the binomial probit likelihood of every row of ``(n, z)`` (rows x levels) by damped
    Newton steps from ``(a0, b0)``; returns ``(a, b, converged)``. The likelihood is concave in
    ``(a, b)``, so a step that does not raise it is halved until it does."""
    a, b = a0.astype(float).copy(), b0.astype(float).copy()
    ll = _loglik(a, b, lx, n, z)
    done = np.zeros(a.size, dtype=bool)
    b_cap = 10.0 / BETA_MIN  # far beyond the separation threshold: stop there
    for _ in range(iters):
        act = ~done
        if not act.any():
            break
        s = a[act, None] + b[act, None] * lx[None, :]
        na, za = n[act], z[act]
        lpdf = _norm_logpdf(s)
        lam_p = np.exp(lpdf - _norm_logcdf(s))  # phi / Phi(s)
        lam_m = np.exp(lpdf - _norm_logcdf(-s))  # phi / Phi(-s)
        d1 = za * lam_p - (na - za) * lam_m
        d2 = -za * lam_p * (s + lam_p) - (na - za) * lam_m * (lam_m - s)
        ga, gb = d1.sum(1), (d1 * lx).sum(1)
        haa, hab, hbb = d2.sum(1), (d2 * lx).sum(1), (d2 * lx * lx).sum(1)
        det = haa * hbb - hab**2
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            da = -(hbb * ga - hab * gb) / det
            db = -(-hab * ga + haa * gb) / det
        bad = ~np.isfinite(da) | ~np.isfinite(db)
        da, db = np.where(bad, 0.0, da), np.where(bad, 0.0, db)
        t = np.ones(da.size)
        a_act, b_act, ll_act = a[act], b[act], ll[act]
        new_a, new_b, new_ll = a_act.copy(), b_act.copy(), ll_act.copy()
        pending = ~bad
        for _h in range(40):
            if not pending.any():
                break
            # the likelihood of the rows still halving their step only (each row is its own fit)
            rows = np.flatnonzero(pending)
            ta = a_act[rows] + t[rows] * da[rows]
            tb = b_act[rows] + t[rows] * db[rows]
            tll = _loglik(ta, tb, lx, na[rows], za[rows])
            ok = tll >= ll_act[rows] - 1e-12
            up = rows[ok]
            new_a[up], new_b[up], new_ll[up] = ta[ok], tb[ok], tll[ok]
            pending[up] = False
            t = np.where(pending, 0.5 * t, t)
        idx = np.flatnonzero(act)
        small = (np.abs(da) <= 1e-10 * (1 + np.abs(a_act))) & (np.abs(db) <= 1e-10 * (1 + np.abs(b_act)))
        a[idx], b[idx], ll[idx] = new_a, new_b, new_ll
        done[idx] = bad | small | (new_ll >= -1e-12) | (np.abs(new_b) > b_cap)
    converged = np.isfinite(ll)
    return a, b, converged


def _separated(lx: np.ndarray, n: np.ndarray, z: np.ndarray) -> np.ndarray:
    """Per row: the levels separate the outcomes, completely or but for one level (none damaged below
    it, every run damaged above it): the likelihood then grows without bound as beta goes to 0."""
    u, inv = np.unique(lx, return_inverse=True)  # runs at one level (a cloud's ties) count together
    rows = n.shape[0]
    # the runs and the damaged ones of every row at each distinct level, added in the order of the
    # levels (as np.bincount adds them)
    nu, zu = np.zeros((rows, u.size)), np.zeros((rows, u.size))
    for j, k in enumerate(inv):
        nu[:, k] += n[:, j]
        zu[:, k] += z[:, j]
    v = nu > 0  # the levels with runs
    with np.errstate(invalid="ignore", divide="ignore"):
        f = np.where(v, zu / np.where(v, nu, 1.0), 0.0)  # the damaged fraction where there are runs
    size = v.sum(1)
    before = np.cumsum(v, axis=1)  # levels with runs up to and including each level
    some = v & (f != 0)  # a level with damage
    first = np.argmax(some, axis=1)
    # leading levels with no damage (all of them when none has damage)
    zeros = np.where(some.any(1), before[np.arange(rows), first] - 1, size)
    short = v & (f != 1)  # a level not all damaged
    last = u.size - 1 - np.argmax(short[:, ::-1], axis=1)
    # trailing levels all damaged (all of them when every level is)
    ones = np.where(short.any(1), size - before[np.arange(rows), last], size)
    return (size > 0) & (zeros + ones >= size - 1)


def _status(lx: np.ndarray, n: np.ndarray, z: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Status of each row's fit (see :class:`FragilityEstimate`)."""
    tot, dam = n.sum(1), z.sum(1)
    st = np.full(n.shape[0], _OK)
    st[(b <= 0) | (b > 1.0 / BETA_MIN) | _separated(lx, n, z)] = _SEPARATED
    st[dam == tot] = _ALL
    st[dam == 0] = _NONE
    return st


def _start(lx: np.ndarray, n: np.ndarray, z: np.ndarray) -> tuple[float, float]:
    """A starting point: where the (made monotone) damaged fraction crosses one half; beta 0.4."""
    order = np.argsort(lx)
    with np.errstate(invalid="ignore"):
        frac = np.where(n > 0, z / np.where(n > 0, n, 1), 0.0)[order]
    f = np.maximum.accumulate(frac) + np.arange(frac.size) * 1e-9
    ln_theta = float(np.interp(0.5, f, lx[order]))
    b0 = 1.0 / 0.4
    return -b0 * ln_theta, b0


def _check(
    levels: Sequence[float] | np.ndarray,
    n_runs: Sequence[int] | np.ndarray,
    n_damaged: Sequence[int] | np.ndarray,
):
    x = np.asarray(levels, dtype=float)
    n = np.asarray(n_runs, dtype=float)
    z = np.asarray(n_damaged, dtype=float)
    if not (x.shape == n.shape == z.shape) or x.ndim != 1:
        raise ParameterError("levels, n_runs and n_damaged must be 1-D sequences of the same length")
    if np.any(x <= 0) or np.any(n < 0) or np.any(z < 0) or np.any(z > n):
        raise ParameterError("levels must be > 0 and 0 <= n_damaged <= n_runs at every level")
    return x, n, z


def fit_fragility(
    levels: Sequence[float] | np.ndarray,
    n_runs: Sequence[int] | np.ndarray,
    n_damaged: Sequence[int] | np.ndarray,
) -> Fragility:
    """Maximum-likelihood lognormal fragility of multiple-stripe counts (Baker 2015).

    Parameters
    ----------
    levels : sequence of float
        Intensity of each stripe (> 0; e.g. PGA [g]).
    n_runs : sequence of int
        Records analysed at each stripe.
    n_damaged : sequence of int
        Records that reached the damage state at each stripe (0 <= z_j <= n_j).

    Returns
    -------
    Fragility
        Not estimable (NaN parameters, the reason in ``note``) when no run or every run is damaged,
        when the stripes separate the outcomes, or when damage does not increase with the level.

    Raises
    ------
    ParameterError
        Inconsistent lengths, a level <= 0, or counts out of range.
    """
    x, n, z = _check(levels, n_runs, n_damaged)
    keep = n > 0
    x, n, z = x[keep], n[keep], z[keep]
    total, damaged = int(n.sum()), int(z.sum())
    nan = math.nan
    if total == 0:
        return Fragility(nan, nan, 0, 0, 0, nan, "not estimable: no analyses")
    if damaged == 0:
        return Fragility(
            nan, nan, x.size, total, 0, nan, f"not estimable: no damage in {total} runs up to {x.max():g}"
        )
    if damaged == total:
        return Fragility(
            nan, nan, x.size, total, total, nan, f"not estimable: every run damaged from {x.min():g}"
        )
    lx = np.log(x)
    a0, b0 = _start(lx, n, z)
    a, b, _ = _probit_newton(lx, n[None, :], z[None, :], np.array([a0]), np.array([b0]))
    st = int(_status(lx, n[None, :], z[None, :], b)[0])
    if st == _SEPARATED:
        why = (
            "the stripes separate the outcomes (the likelihood grows as beta goes to 0)"
            if b[0] > 0
            else "damage does not increase with the intensity"
        )
        return Fragility(nan, nan, x.size, total, damaged, nan, f"not estimable: {why}")
    beta = 1.0 / float(b[0])
    median = math.exp(min(-float(a[0]) / float(b[0]), 700.0))
    if beta > BETA_MAX:
        return Fragility(
            nan, nan, x.size, total, damaged, nan,
            f"not estimable: the fit's beta {beta:.3g} is above {BETA_MAX:g} (median {median:.3g}): "
            "damage hardly depends on the intensity",
        )  # fmt: skip
    if median > MEDIAN_MAX_FACTOR * x.max():
        return Fragility(
            nan, nan, x.size, total, damaged, nan,
            f"not estimable: the fit's median {median:.3g} is beyond {MEDIAN_MAX_FACTOR:g} times the "
            f"highest level ({x.max():g})",
        )  # fmt: skip
    return Fragility(
        median=median,
        beta=beta,
        n_levels=int(x.size),
        n_runs=total,
        n_damaged=damaged,
        log_likelihood=float(_loglik(a, b, lx, n[None, :], z[None, :])[0]),
    )


def resample_weights(n_records: int, n_boot: int = N_BOOTSTRAP, seed: int = 0) -> np.ndarray:
    """The bootstrap resamples of ``n_records`` records: how many times each resample draws each record.

    Parameters
    ----------
    n_records : int
        Records of the set (>= 0).
    n_boot : int
        Resamples (>= 0), each of ``n_records`` draws with replacement.
    seed : int
        Seed: the same ``(n_records, n_boot, seed)`` give the same resamples, so that every fit of one
        record set is paired with every other.

    Returns
    -------
    numpy.ndarray of float, shape (n_boot, n_records)
    """
    if n_boot <= 0 or n_records <= 0:
        return np.zeros((0, max(n_records, 0)))
    rng = np.random.default_rng(seed)
    return rng.multinomial(n_records, np.full(n_records, 1.0 / n_records), size=n_boot).astype(float)


def bootstrap_fragility(
    levels: Sequence[float],
    damaged: np.ndarray,
    included: np.ndarray | None = None,
    *,
    n_boot: int = N_BOOTSTRAP,
    seed: int = 0,
    weights: np.ndarray | None = None,
) -> FragilityEstimate:
    """The fragility of per-record outcomes and its bootstrap over records.

    Parameters
    ----------
    levels : sequence of float
        The stripes' intensities (> 0), one per column.
    damaged : numpy.ndarray of bool, shape (records, levels)
        Whether each record reached the damage state at each stripe.
    included : numpy.ndarray of bool, same shape, optional
        Whether each run enters the fit (False: left out, e.g. outside the model); default all.
    n_boot : int
        Resamples of the records (with replacement, each the size of the record set) [-]; 0: none.
    seed : int
        Seed of the resampling (the same data and seed give the same intervals).
    weights : numpy.ndarray, shape (resamples, records), optional
        The resamples (:func:`resample_weights`); given, ``n_boot`` and ``seed`` are not used.

    Returns
    -------
    FragilityEstimate
    """
    x = np.asarray(levels, dtype=float)
    D = np.asarray(damaged, dtype=bool)
    inc = np.ones_like(D) if included is None else np.asarray(included, dtype=bool)
    if D.ndim != 2 or D.shape[1] != x.size or inc.shape != D.shape:
        raise ParameterError("damaged and included must be (records x levels) arrays matching the levels")
    n = inc.sum(0).astype(float)
    z = (D & inc).sum(0).astype(float)
    fit = fit_fragility(x, n, z)
    keep = n > 0
    W = resample_weights(D.shape[0], n_boot, seed) if weights is None else np.asarray(weights, dtype=float)
    if W.shape[0] == 0 or D.shape[0] == 0 or not keep.any():
        empty = np.zeros(0)
        return FragilityEstimate(fit, empty, empty, np.zeros(0, dtype=int))
    if W.shape[1] != D.shape[0]:
        raise ParameterError(f"weights: {W.shape[1]} records per resample for {D.shape[0]} records")
    n_boot = W.shape[0]
    nb = (W @ inc.astype(float))[:, keep]
    zb = (W @ (D & inc).astype(float))[:, keep]
    lx = np.log(x[keep])
    if fit.estimable:
        b0 = np.full(n_boot, 1.0 / fit.beta)
        a0 = -b0 * math.log(fit.median)
    else:
        s = _start(lx, n[keep], z[keep])
        a0, b0 = np.full(n_boot, s[0]), np.full(n_boot, s[1])
    a, b, _ = _probit_newton(lx, nb, zb, a0, b0)
    return FragilityEstimate(fit, a, b, _status(lx, nb, zb, b))


def bootstrap_cloud(
    x: np.ndarray, damaged: np.ndarray, record: np.ndarray, weights: np.ndarray
) -> FragilityEstimate:
    """The fragility of a cloud of runs and its bootstrap over records (paired with every fit that uses
    the same ``weights``).

    Parameters
    ----------
    x : numpy.ndarray
        The intensity measure of each run (> 0; e.g. PGV [m/s] or Sa [g]).
    damaged : numpy.ndarray of bool
        Whether each run reached the damage state.
    record : numpy.ndarray of int
        The record (column of ``weights``) of each run.
    weights : numpy.ndarray, shape (resamples, records)
        The resamples (:func:`resample_weights`).

    Returns
    -------
    FragilityEstimate
        The fit of every run (each its own level) and, per resample, every run weighted by the number
        of times its record is drawn.
    """
    x = np.asarray(x, dtype=float)
    d = np.asarray(damaged, dtype=bool)
    rec = np.asarray(record, dtype=int)
    fit = fit_fragility(x, np.ones(x.size), d.astype(float))
    W = np.asarray(weights, dtype=float)
    if W.shape[0] == 0 or x.size == 0:
        empty = np.zeros(0)
        return FragilityEstimate(fit, empty, empty, np.zeros(0, dtype=int))
    nb = W[:, rec]
    zb = nb * d[None, :]
    lx = np.log(x)
    if fit.estimable:
        b0 = np.full(W.shape[0], 1.0 / fit.beta)
        a0 = -b0 * math.log(fit.median)
    else:
        s = _start(lx, np.ones(x.size), d.astype(float))
        a0, b0 = np.full(W.shape[0], s[0]), np.full(W.shape[0], s[1])
    a, b, _ = _probit_newton(lx, nb, zb, a0, b0)
    return FragilityEstimate(fit, a, b, _status(lx, nb, zb, b))
