"""Lognormal fragility functions fitted by maximum likelihood to multiple-stripe analysis results.

Baker (2015), "Efficient analytical fragility function fitting using dynamic structural analysis",
Earthquake Spectra 31(1), 579-599: at each intensity level ``x_j`` (a stripe) ``n_j`` records are
scaled to ``x_j`` and ``z_j`` of them reach the damage state (here: overturning, or uplift). With
``P(D | x) = Phi(ln(x / theta) / beta)`` the stripes are independent binomial observations, and the
fragility is the ``(theta, beta)`` that maximises

    sum_j [ z_j ln Phi(ln(x_j/theta)/beta) + (n_j - z_j) ln(1 - Phi(ln(x_j/theta)/beta)) ] .

No monotonicity is imposed on the data (a record may overturn the block at one level and not at a
higher one, the non-monotone boundary of rocking): every stripe enters with its own count.

The fit is undefined when no stripe has a damaged record (the median lies above the highest stripe)
or when every record is damaged at every stripe (below the lowest); those cases are reported as
such (:attr:`Fragility.note`), with NaN parameters, rather than with an extrapolated number. When the
stripes separate perfectly (none damaged below some level, all above) the likelihood grows without
bound as ``beta`` goes to 0; ``beta`` is then held at :data:`BETA_MIN` and the note says so.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass

import numpy as np
from scipy.optimize import minimize
from scipy.stats import norm

__all__ = ["BETA_MIN", "BETA_MAX", "Fragility", "fit_fragility"]

#: bounds of the dispersion searched [-]
BETA_MIN = 0.02
BETA_MAX = 5.0


@dataclass(frozen=True)
class Fragility:
    """A lognormal fragility function ``P(D | x) = Phi(ln(x / median) / beta)``.

    Attributes
    ----------
    median : float
        Median capacity ``theta``, in the unit of the intensity measure (g for PGA); NaN when the fit
        is undefined (see ``note``).
    beta : float
        Logarithmic standard deviation [-]; NaN when undefined.
    n_levels : int
        Stripes used.
    n_runs : int
        Analyses used.
    n_damaged : int
        Analyses that reached the damage state.
    log_likelihood : float
        Log-likelihood at the fit [-].
    note : str
        "" for a regular fit; otherwise why the fit is undefined or at a bound.
    """

    median: float
    beta: float
    n_levels: int
    n_runs: int
    n_damaged: int
    log_likelihood: float
    note: str = ""

    @property
    def defined(self) -> bool:
        """Both parameters are finite."""
        return math.isfinite(self.median) and math.isfinite(self.beta)

    def probability(self, x: float | np.ndarray) -> float | np.ndarray:
        """``P(D | x)`` [-] at intensity ``x`` (same unit as the median). Where the fit is undefined:
        0 when no run was damaged, 1 when every run was, NaN otherwise."""
        if not self.defined:
            fill = 0.0 if self.n_damaged == 0 else (1.0 if self.n_damaged == self.n_runs else math.nan)
            return np.full(np.shape(x), fill) if np.ndim(x) else fill
        p = norm.cdf(np.log(np.asarray(x, dtype=float) / self.median) / self.beta)
        return float(p) if np.ndim(p) == 0 else p

    def to_dict(self) -> dict:
        return asdict(self)


def _neg_log_likelihood(params: np.ndarray, lx: np.ndarray, n: np.ndarray, z: np.ndarray) -> float:
    ln_theta, ln_beta = params
    s = (lx - ln_theta) / math.exp(ln_beta)
    # log Phi and log(1 - Phi) = log Phi(-s), accurate in the tails
    return -float(np.sum(z * norm.logcdf(s) + (n - z) * norm.logcdf(-s)))


def fit_fragility(levels: Sequence[float], n_runs: Sequence[int], n_damaged: Sequence[int]) -> Fragility:
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

    Raises
    ------
    ValueError
        Inconsistent lengths, a level <= 0, or counts out of range.
    """
    x = np.asarray(levels, dtype=float)
    n = np.asarray(n_runs, dtype=float)
    z = np.asarray(n_damaged, dtype=float)
    if not (x.shape == n.shape == z.shape) or x.ndim != 1:
        raise ValueError("levels, n_runs and n_damaged must be 1-D sequences of the same length")
    if np.any(x <= 0) or np.any(n < 0) or np.any(z < 0) or np.any(z > n):
        raise ValueError("levels must be > 0 and 0 <= n_damaged <= n_runs at every level")
    keep = n > 0
    x, n, z = x[keep], n[keep], z[keep]
    total, damaged = int(n.sum()), int(z.sum())
    if total == 0:
        return Fragility(math.nan, math.nan, 0, 0, 0, math.nan, "no analyses")
    if damaged == 0:
        return Fragility(
            math.nan,
            math.nan,
            x.size,
            total,
            0,
            0.0,
            f"no damage at any level: the median is above {x.max():g}",
        )
    if damaged == total:
        return Fragility(
            math.nan,
            math.nan,
            x.size,
            total,
            total,
            0.0,
            f"damage at every level: the median is below {x.min():g}",
        )
    lx = np.log(x)
    order = np.argsort(x)
    fr = (z / n)[order]
    if np.all((fr == 0) | (fr == 1)) and np.all(np.diff(fr) >= 0):
        # perfect separation: no finite maximum (beta -> 0); the median between the two levels
        k = int(np.argmax(fr))
        lo, hi = x[order][k - 1], x[order][k]
        return Fragility(
            median=math.sqrt(lo * hi),
            beta=BETA_MIN,
            n_levels=int(x.size),
            n_runs=total,
            n_damaged=damaged,
            log_likelihood=0.0,
            note=f"the stripes separate the outcomes (none below {hi:g}, all from it): the median is "
            f"between {lo:g} and {hi:g}, beta held at its lower bound {BETA_MIN:g}",
        )
    # start: where the (made monotone) damaged fraction crosses one half; a moderate dispersion
    f, lxs = _monotone(z / n, lx)
    start = np.array([float(np.interp(0.5, f, lxs)), math.log(0.4)])
    bounds = [(lx.min() - 5.0, lx.max() + 5.0), (math.log(BETA_MIN), math.log(BETA_MAX))]
    res = minimize(_neg_log_likelihood, start, args=(lx, n, z), method="L-BFGS-B", bounds=bounds)
    ln_theta, ln_beta = res.x
    beta = math.exp(ln_beta)
    note = ""
    if beta <= BETA_MIN * (1 + 1e-6):
        note = f"the stripes separate the outcomes: beta held at its lower bound {BETA_MIN:g}"
    elif beta >= BETA_MAX * (1 - 1e-6):
        note = f"beta at its upper bound {BETA_MAX:g}: the data hardly depend on the intensity"
    return Fragility(
        median=math.exp(ln_theta),
        beta=beta,
        n_levels=int(x.size),
        n_runs=total,
        n_damaged=damaged,
        log_likelihood=-float(res.fun),
        note=note,
    )


def _monotone(frac: np.ndarray, lx: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(increasing damaged fractions, their log levels) for a starting guess by interpolation."""
    order = np.argsort(lx)
    f = np.maximum.accumulate(frac[order])
    f = f + np.arange(f.size) * 1e-9  # strictly increasing for np.interp
    return f, lx[order]
