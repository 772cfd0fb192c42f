"""Integrals and intensity measures of an acceleration record (velocity, displacement, PGA, PGV,
Arias intensity, significant duration)."""

from __future__ import annotations

import math

import numpy as np
from obspy import Trace

from isorock.constants import G

__all__ = ["velocity", "displacement", "metrics", "cumulative_trapezoid"]


def cumulative_trapezoid(y: np.ndarray, dx: float, initial: float = 0.0) -> np.ndarray:
    """Cumulative trapezoidal integral of samples ``y`` at spacing ``dx``, ``initial`` (0) at the first
    sample: :func:`scipy.integrate.cumulative_trapezoid` with ``dx`` and ``initial=0``, computed by the
    same numpy operations (the same values bit for bit) without importing scipy.integrate, which
    loads most of scipy (about 0.3 s).

    Parameters
    ----------
    y : numpy.ndarray
        Samples, 1-D.
    dx : float
        Spacing of the samples.
    initial : float
        Value at the first sample; only 0 (scipy's rule).
    """
    y = np.asarray(y)
    if y.shape[-1] == 0:
        raise ValueError("At least one point is required along `axis`.")
    if initial != 0:
        raise ValueError("`initial` must be `None` or `0`.")
    res = np.cumsum(dx * (y[..., 1:] + y[..., :-1]) / 2.0, axis=-1)
    return np.concatenate((np.full(res.shape[:-1] + (1,), initial, dtype=res.dtype), res), axis=-1)


def velocity(tr: Trace) -> np.ndarray:
    """Ground velocity [m/s]: trapezoidal integral of the acceleration [m/s^2], zero at the first sample."""
    return cumulative_trapezoid(np.asarray(tr.data, dtype=float), dx=tr.stats.delta, initial=0.0)


def displacement(tr: Trace) -> np.ndarray:
    """Ground displacement [m]: double trapezoidal integral of the acceleration, zero at the first sample."""
    v = velocity(tr)
    return cumulative_trapezoid(v, dx=tr.stats.delta, initial=0.0)


def metrics(tr: Trace) -> dict[str, float]:
    """Intensity measures of an acceleration record.

    Parameters
    ----------
    tr : obspy.Trace
        Acceleration [m/s^2] (normally processed).

    Returns
    -------
    dict
        ``npts`` [-], ``dt_s`` [s], ``duration_s`` [s], ``pga_m_s2`` [m/s^2], ``pga_g`` [g],
        ``pgv_m_s`` [m/s], ``pgd_m`` [m], ``arias_m_s`` (Arias intensity ``pi/(2g) int a^2 dt``) [m/s],
        ``d5_95_s`` (significant duration between 5 % and 95 % of the Arias intensity) [s],
        ``final_disp_m`` (displacement at the last sample) [m].
    """
    a = np.asarray(tr.data, dtype=float)
    dt = float(tr.stats.delta)
    v = velocity(tr)
    d = displacement(tr)
    husid = cumulative_trapezoid(a * a, dx=dt, initial=0.0)
    total = float(husid[-1])
    arias = math.pi / (2.0 * G) * total
    if total > 0:
        t = np.arange(a.size) * dt
        t5, t95 = np.interp([0.05 * total, 0.95 * total], husid, t)
        d595 = float(t95 - t5)
    else:
        d595 = 0.0
    pga = float(np.max(np.abs(a)))
    return {
        "npts": int(a.size),
        "dt_s": dt,
        "duration_s": (a.size - 1) * dt,
        "pga_m_s2": pga,
        "pga_g": pga / G,
        "pgv_m_s": float(np.max(np.abs(v))),
        "pgd_m": float(np.max(np.abs(d))),
        "arias_m_s": arias,
        "d5_95_s": d595,
        "final_disp_m": float(d[-1]),
    }
