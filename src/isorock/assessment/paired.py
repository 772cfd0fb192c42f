"""Paired comparisons of bases that saw the same records: the difference on the same bootstrap resamples,
a one-sided test of "better" calibrated by a studentised, centred bootstrap, its familywise correction
over every candidate of a search (Westfall & Young 1993, single-step max-T), an equivalence test within
a margin (two one-sided tests), and how many records would decide.

Every base of an assessment is evaluated on the same resamples of the same records
(:func:`isorock.assessment.fragility.resample_weights`): the resampled metrics of two bases are paired,
resample ``b`` of one with resample ``b`` of the other.

**The test of "a is better than b"** (lower metric). The share of resamples in which ``a`` is lower
(``p_better``) describes the resamples but is no calibrated test: a rule "better in 95 % of the
resamples" rejects a true null in 7-9 % of the sites at 17 records. The test here is the bootstrap's
pivot: with ``d`` the observed difference, ``d_b`` its resampled values and ``s`` their standard
deviation, ``t = -d / s`` and, under the null, ``T_b = -(d_b - d) / s`` (the resampled differences
centred on the observed one); the one-sided p-value is ``(1 + #{T_b >= t}) / (B + 1)``.

**Familywise** (a search over many candidates: those it could recommend). Each candidate ``i`` has
its ``t_i`` and ``T_ib`` on the same resamples; the adjusted p-value is
``(1 + #{max_j T_jb >= t_i}) / (B + 1)``: the chance, under the complete null, that the best-looking of
all the candidates looks as good as ``i`` does. It keeps the familywise rate of a false "better" at the
nominal level whatever the correlation of the candidates, which the resamples carry (Westfall & Young
1993, ch. 2; the null simulation of ``tests/assessment/test_familywise.py``).

**Equivalence** (two one-sided tests, Schuirmann 1987): ``a`` is equivalent to ``b`` within ``margin``
when the 90 % percentile interval of the paired difference lies inside ``(-margin, margin)``; "cannot be
told apart" is never taken for "equivalent".
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

__all__ = ["ALPHA", "paired", "one_sided_p", "familywise", "equivalent", "records_to_decide"]

#: the level of every test of the decision (one-sided "better", each side of an equivalence)
ALPHA = 0.05


def paired(est_a: float, samples_a: np.ndarray, est_b: float, samples_b: np.ndarray) -> dict[str, Any]:
    """Candidate ``a`` against ``b`` on the same resamples (lower is better).

    Returns
    -------
    dict
        ``difference`` (``est_a - est_b``), ``difference_ci95`` (2.5th and 97.5th percentiles of the
        resampled differences; None without resamples), ``p_better`` (share of the resamples in which
        ``a`` is lower), ``p_worse`` (higher), ``n_better`` and ``n_worse`` (their counts), ``n``
        (resamples compared: those where both are defined), ``p_single`` (the one-sided p-value of "a is
        better", :func:`one_sided_p`; None where it cannot be computed).
    """
    a, b = np.asarray(samples_a, dtype=float), np.asarray(samples_b, dtype=float)
    diff = float(est_a - est_b) if math.isfinite(est_a) and math.isfinite(est_b) else math.nan
    ok = (np.isfinite(a) & np.isfinite(b)) if a.size and a.size == b.size else np.zeros(0, dtype=bool)
    if not ok.any():
        return {
            "difference": diff,
            "difference_ci95": None,
            "p_better": math.nan,
            "p_worse": math.nan,
            "n_better": 0,
            "n_worse": 0,
            "n": 0,
            "p_single": None,
        }
    d = a[ok] - b[ok]
    # differences below the floating-point noise of two equal estimates count as ties
    tol = 1e-12 * max(float(np.max(np.abs(a[ok]))), float(np.max(np.abs(b[ok]))), 1e-300)
    lo, hi = np.percentile(d, [2.5, 97.5])
    nb, nw = int(np.sum(d < -tol)), int(np.sum(d > tol))
    return {
        "difference": diff,
        "difference_ci95": [float(lo), float(hi)],
        "p_better": nb / d.size,
        "p_worse": nw / d.size,
        "n_better": nb,
        "n_worse": nw,
        "n": int(d.size),
        "p_single": one_sided_p(diff, a - b),
    }


def _pivot(diff: float, d: np.ndarray) -> tuple[float, np.ndarray] | None:
    """(t, T_b) of the studentised, centred bootstrap of a difference (see the module docstring); None
    where the difference or its spread is not defined. Undefined resamples are -inf (never extreme)."""
    d = np.asarray(d, dtype=float)
    fin = np.isfinite(d)
    if not math.isfinite(diff) or fin.sum() < 2:
        return None
    s = float(np.std(d[fin]))
    if not s > 1e-12 * max(abs(diff), float(np.max(np.abs(d[fin]))), 1e-300):
        return None
    T = np.full(d.size, -np.inf)
    T[fin] = -(d[fin] - diff) / s
    return -diff / s, T


def one_sided_p(diff: float, d: np.ndarray) -> float | None:
    """One-sided p-value of "the difference is below zero" from its resampled values ``d``
    (``(1 + #{T_b >= t}) / (B + 1)``); None where the spread is zero or nothing is defined."""
    pv = _pivot(diff, d)
    if pv is None:
        return None
    t, T = pv
    return float((1 + np.sum(T >= t)) / (T.size + 1))


def familywise(diffs: Sequence[float], samples: Sequence[np.ndarray]) -> list[float | None]:
    """Westfall-Young single-step max-T adjusted p-values of "candidate ``i`` is better" over every
    candidate of a family, on the same resamples (see the module docstring).

    Parameters
    ----------
    diffs : sequence of float
        The observed difference of each candidate from the reference (lower is better).
    samples : sequence of numpy.ndarray
        Their resampled differences, each of the same length ``B`` (NaN where undefined).

    Returns
    -------
    list
        The adjusted p-value of each (None where its spread is zero or it has no resamples: it takes
        no part in the family).
    """
    piv = [_pivot(float(d), np.asarray(s, dtype=float)) for d, s in zip(diffs, samples, strict=True)]
    Ts = [p[1] for p in piv if p is not None]
    if not Ts:
        return [None for _ in piv]
    B = min(t.size for t in Ts)
    mx = np.max(np.vstack([t[:B] for t in Ts]), axis=0)
    return [None if p is None else float((1 + np.sum(mx >= p[0])) / (B + 1)) for p in piv]


def equivalent(diff: float, d: np.ndarray, margin: float) -> bool:
    """Two one-sided tests at :data:`ALPHA`: the ``1 - 2 ALPHA`` percentile interval of the paired
    difference (resampled values ``d``) lies inside ``(-margin, margin)``."""
    d = np.asarray(d, dtype=float)
    d = d[np.isfinite(d)]
    if not (math.isfinite(diff) and d.size and margin > 0):
        return False
    lo, hi = np.percentile(d, [100 * ALPHA, 100 * (1 - ALPHA)])
    return bool(-margin < lo and hi < margin)


def records_to_decide(n_records: int, difference: float, samples: np.ndarray | None) -> int | None:
    """About how many records would make a paired difference decisive at ``1 - ALPHA`` (one-sided),
    were it what it is now: the bootstrap spread of the difference shrinks as one over the square root
    of the number of records, so ``n (z sd / |d|)^2`` with ``z`` the normal quantile. None when the
    difference is zero or its spread unknown (more records of the same kind would not separate
    them)."""
    if samples is None or np.asarray(samples).size < 2 or not math.isfinite(difference) or difference == 0:
        return None
    sd = float(np.nanstd(samples))
    if not sd > 0:
        return None
    z = 1.6448536269514722  # the 95 % one-sided normal quantile
    return max(n_records + 1, math.ceil(n_records * (z * sd / abs(difference)) ** 2))
