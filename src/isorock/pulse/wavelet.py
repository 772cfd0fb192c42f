"""The wavelet method of Baker (2007): continuous wavelet transform with the Daubechies-4 wavelet,
pseudo-periods, and Baker's pulse indicator (see :mod:`isorock.pulse` for the method)."""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
import pywt
from scipy.signal import fftconvolve

__all__ = [
    "WAVELET",
    "central_frequency",
    "pseudo_period",
    "cwt_db4",
    "wavelet_at",
    "pulse_indicator",
    "time_of_fraction",
]

WAVELET = "db4"


@lru_cache(maxsize=8)
def _wavelet_table(level: int) -> tuple[np.ndarray, np.ndarray, float]:
    """Sampled db4 wavelet function: grid ``x`` on its support, ``psi(x)``, centre of the support."""
    _phi, psi, x = pywt.Wavelet(WAVELET).wavefun(level=level)
    x = np.asarray(x, dtype=float)
    psi = np.asarray(psi, dtype=float)
    return x, psi, 0.5 * (x[0] + x[-1])


@lru_cache(maxsize=8)
def central_frequency(level: int = 10) -> float:
    """Central frequency of db4 [cycles per unit of the wavelet's argument] (PyWavelets, 0.714)."""
    return float(pywt.central_frequency(WAVELET, precision=level))


def pseudo_period(scale: float | np.ndarray, dt: float, level: int = 10) -> float | np.ndarray:
    """Pseudo-period [s] of the db4 wavelet at ``scale`` [samples] for time step ``dt`` [s]."""
    return (
        np.asarray(scale, dtype=float) * dt / central_frequency(level)
        if np.ndim(scale)
        else float(scale) * dt / central_frequency(level)
    )


def _kernel(scale: float, level: int) -> tuple[np.ndarray, int, int]:
    """Wavelet samples ``psi(j / a + x_c)`` for integer offsets ``j`` in [jmin, jmax]."""
    x, psi, xc = _wavelet_table(level)
    jmin = math.ceil((x[0] - xc) * scale)
    jmax = math.floor((x[-1] - xc) * scale)
    j = np.arange(jmin, jmax + 1)
    w = np.interp(j / scale + xc, x, psi, left=0.0, right=0.0)
    return w, jmin, jmax


def cwt_db4(signal: np.ndarray, scales: np.ndarray, level: int = 10) -> np.ndarray:
    """Continuous wavelet transform with the db4 wavelet.

    Parameters
    ----------
    signal : numpy.ndarray
        Samples ``s_k`` (any unit U), zero outside the record.
    scales : numpy.ndarray
        Scales ``a`` [samples] (need not be integers).
    level : int
        Refinement level of the sampled wavelet function.

    Returns
    -------
    numpy.ndarray
        ``C[i, b] = a_i^(-1/2) sum_k s_k psi((k - b)/a_i + x_c)`` [U * samples^(1/2)], shape
        ``(len(scales), len(signal))``; a wavelet ``c psi((k - b)/a + x_c)/sqrt(a)`` has
        coefficient ``c`` at ``(a, b)`` (db4 has unit energy).
    """
    s = np.asarray(signal, dtype=float)
    n = s.size
    out = np.empty((len(scales), n))
    for i, a in enumerate(np.asarray(scales, dtype=float)):
        w, _jmin, jmax = _kernel(float(a), level)
        full = fftconvolve(s, w[::-1], mode="full")
        # full[m] = sum_j s[m - jmax + j] w[j]  ->  C(b) = full[b + jmax]
        out[i] = full[jmax : jmax + n] / math.sqrt(a)
    return out


def wavelet_at(n: int, scale: float, position: int, level: int) -> np.ndarray:
    """``psi((k - b)/a + x_c) / sqrt(a)`` for ``k = 0..n-1`` (zero outside the support)."""
    w, jmin, jmax = _kernel(scale, level)
    out = np.zeros(n)
    lo = position + jmin
    hi = position + jmax + 1
    klo, khi = max(lo, 0), min(hi, n)
    if khi > klo:
        out[klo:khi] = w[klo - lo : khi - lo]
    return out / math.sqrt(scale)


def pulse_indicator(pgv_ratio: float, energy_ratio: float) -> float:
    """Baker's (2007) pulse indicator ``1 / (1 + exp(-23.3 + 14.6 pgv_ratio + 20.5 energy_ratio))`` [-]."""
    z = -23.3 + 14.6 * pgv_ratio + 20.5 * energy_ratio
    return float(1.0 / (1.0 + math.exp(min(z, 700.0))))


def time_of_fraction(x2: np.ndarray, frac: float, dt: float) -> float:
    """Time [s] at which the cumulative sum of ``x2`` reaches ``frac`` of its total (inf if all zero)."""
    c = np.cumsum(x2)
    if c[-1] <= 0:
        return math.inf
    return float(np.searchsorted(c, frac * c[-1]) * dt)
