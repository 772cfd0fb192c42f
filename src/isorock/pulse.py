"""Velocity-pulse period of a near-fault record: wavelet (db4), Mavroeidis-Papageorgiou and
Bray-Rodriguez-Marek methods.

Three estimates of the pulse period ``Tp`` of a ground-velocity history, one per definition found
in the literature (a published ``Tp`` should be compared with the estimate of its own definition):

**Wavelet method** (Baker 2007; the pulse extraction of Shahi & Baker 2014).
The continuous wavelet transform (CWT) of the velocity ``v_k`` with the Daubechies-4
mother wavelet ``psi`` is, for a scale ``a`` [samples] and a position ``b`` [sample],
``C(a, b) = a^(-1/2) sum_k v_k psi((k - b)/a + x_c)``, with ``x_c = 3.5`` the middle of
the support [0, 7] of db4 (so ``b`` is where the wavelet is centred). PyWavelets'
``cwt`` only takes continuous wavelets, so the transform is built here from
``pywt.Wavelet("db4").wavefun``: the wavelet function is interpolated at each scale
and correlated with the signal by FFT. The pseudo-period of scale ``a`` is
``a dt / f_c`` with ``f_c = pywt.central_frequency("db4") = 0.714`` (MATLAB's
``scal2frq``). Steps:

1. CWT over scales whose pseudo-periods cover ``tp_min`` to ``tp_max`` (0.25-15 s),
   log-spaced; the largest ``|C|`` picks the pulse scale and position; the scale is then
   refined on a fine grid between the neighbouring scales (Shahi & Baker zoom in the
   same way), keeping the position within ``0.4 a`` samples;
2. the pulse is built from up to ``n_wavelets`` (10) wavelets at that scale: at each
   iteration the CWT of the residual (record minus pulse so far) is computed at the
   pulse scale, its largest ``|C|`` within ``0.4 a`` samples of the first position is
   taken, and ``C psi((k - b)/a + x_c) / sqrt(a)`` is added to the pulse;
3. ``Tp`` is the pseudo-period of the pulse scale;
4. classification (Baker 2007): pulse indicator
   ``PI = 1 / (1 + exp(-23.3 + 14.6 PGV_ratio + 20.5 energy_ratio))`` with
   ``PGV_ratio = PGV(residual) / PGV(record)`` and ``energy_ratio`` the same ratio of
   ``sum v^2`` (cumulative squared velocity; equal to the sum of squared DWT
   coefficients Baker uses, by Parseval); the record is pulse-like when ``PI > 0.85``,
   the pulse arrives early and ``PGV >= 0.30 m/s`` (Baker's three criteria).
   Early arrival: the pulse reaches 10 % of its cumulative squared velocity before the
   record reaches 20 % of its own, ``t10%,pulse < t20%,orig`` (a late pulse is one that
   starts after a fifth of the record's energy has passed).

**Mavroeidis-Papageorgiou (2003) model** (MP), fitted by least squares
(:func:`scipy.optimize.least_squares`, :func:`fit_mp`)::

    v(t) = A/2 [1 + cos(2 pi fp (t - t0) / gamma)] cos(2 pi fp (t - t0) + nu)
           for |t - t0| <= gamma / (2 fp), zero otherwise,

so that ``Tp_mp = 1 / fp``. MP (2003) chose the parameters so that the model matches the
recorded velocity *and displacement* waveforms of the pulse; the fit here does the same
in the least-squares sense, by these general rules (the same for every record):

* fit window: centred on the energy centroid of the extracted wavelet pulse, of total
  length ``gamma_max * Tp_wavelet`` (the support of the widest admissible MP pulse at the
  wavelet period: 3 ``Tp_wavelet`` for ``gamma_max = 3``);
* misfit: velocity residual divided by the largest ``|v|`` in the window, and displacement
  residual (record and model displacement each taken about its mean over the window, so
  that the displacement level at the window start does not matter) divided by the largest
  ``|d - mean(d)|`` in the window, both with equal weight;
* bounds: ``1 <= gamma <= 3`` (MP require ``gamma > 1``; the upper bound keeps the model
  to about one and a half cycles, the directivity pulse MP describe; with a larger
  ``gamma`` the model absorbs neighbouring cycles that are not part of it), ``nu`` free,
  ``fp`` within a factor 2 of ``1 / Tp_wavelet``, ``t0`` inside the window,
  ``0 <= A <= 3 max|v|``;
* multi-start: 672 trial pulses (8 phases, 4 values of ``gamma``, 7 frequencies from 0.6
  to 1.5 times ``1 / Tp_wavelet``, 3 times); the 2 best of each frequency are refined by
  least squares and the best fit is kept;
* fit quality: RMS of the velocity and of the displacement misfit over the RMS of the
  record, in the window (``mp_rms_ratio``, ``mp_disp_rms_ratio``).

``PulseConfig(mp_displacement=False)`` fits the velocity only. On 60 synthetic records (MP
pulses, 0.6-8 s, ``1.2 <= gamma <= 3``, plus omega-square stochastic motion of 30-90 % of
the pulse PGV, processed like real records) both criteria recover ``1 / fp`` with a median
error of 3 %; the displacement term gives a heavier tail (90th percentile of the error 22 %
against 13 %): it lengthens the period when long-period motion outside the pulse dominates
the displacement in the window (``python benchmarks/tp_table.py --synthetic 60``). The
joint fit is the default because it is what MP did.

**Bray & Rodriguez-Marek (2004) pulse period** ``Tv`` (:func:`tp_bray_rodriguez_marek`):
the period of the velocity pulse of largest amplitude, measured on the velocity history
itself: twice the time between the zero crossings that bracket the PGV (the duration of
the half-cycle holding the PGV, linearly interpolated between samples). It equals the
duration of the full cycle of largest amplitude when that cycle is symmetric; no
smoothing, so high-frequency wiggles that cross zero shorten it (that is the definition).

**Orientation**: published ``Tp`` are usually for the strike-normal (SN) or strike-parallel
(SP) component. :func:`rotate_horizontal` turns two horizontal components of known
azimuths into the component along any azimuth; :func:`fault_azimuth` gives the SN or SP
azimuth of a fault strike.

Simplifications with respect to the published methods:

* one component only: Shahi & Baker (2014) rotate two horizontal components to the
  orientation of the largest coefficient and try up to 5 candidate pulses; here the
  given component (or a rotation the caller asks for) is used and only the largest pulse
  is extracted;
* the energy ratio uses the time-domain sum of squared velocity instead of squared
  DWT coefficients (equal up to the DWT boundary treatment);
* the scale grid is log-spaced (then refined) instead of linear in samples;
* Baker's early-arrival test is read as ``t10%,pulse < t20%,orig`` (with the opposite
  reading, ``t20%,pulse < t10%,orig``, a record that is nothing but a pulse would be
  "late"); Shahi & Baker (2014) use 5 % / 17 % instead;
* MP (2003) fitted their model by trial and error, by eye (velocity and displacement
  waveforms, and response spectra of the full synthetic record); here by least squares
  on velocity and displacement in the window above, without the response spectra;
* Bray & Rodriguez-Marek (2004) read ``Tv`` off plots of the velocity history; here the
  zero crossings around the PGV are computed from the samples.

References
----------
Baker, J. W. (2007). Quantitative classification of near-fault ground motions using wavelet
analysis. BSSA 97(5), 1486-1501.
Shahi, S. K. & Baker, J. W. (2014). An efficient algorithm to identify strong-velocity pulses in
multicomponent ground motions. BSSA 104(5), 2456-2466.
Mavroeidis, G. P. & Papageorgiou, A. S. (2003). A mathematical representation of near-fault
ground motions. BSSA 93(3), 1099-1131.
Bray, J. D. & Rodriguez-Marek, A. (2004). Characterization of forward-directivity ground
motions in the near-fault region. Soil Dynamics and Earthquake Engineering 24(11), 815-828.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import numpy as np
import pywt
from obspy import Trace
from scipy.integrate import cumulative_trapezoid
from scipy.optimize import least_squares
from scipy.signal import fftconvolve

from .errors import IsorockError

__all__ = [
    "PulseConfig",
    "MPParameters",
    "PulseResult",
    "extract_pulse",
    "cwt_db4",
    "pseudo_period",
    "central_frequency",
    "pulse_indicator",
    "mp_velocity",
    "mp_acceleration",
    "mp_displacement",
    "MPFit",
    "fit_mp",
    "tp_bray_rodriguez_marek",
    "rotate_horizontal",
    "fault_azimuth",
]

WAVELET = "db4"


# ----------------------------------------------------------------------------- parameters


@dataclass(frozen=True)
class PulseConfig:
    """Settings of the pulse extraction.

    Parameters
    ----------
    tp_min, tp_max : float
        Range of pseudo-periods searched [s] (Baker: 0.25-15 s).
    n_scales : int
        Number of (log-spaced) scales of the coarse CWT [-].
    n_refine : int
        Number of scales of the refinement between the neighbours of the coarse maximum [-].
    n_wavelets : int
        Number of wavelets (all at the pulse scale) summed into the pulse [-] (Baker: 10).
    position_window : float
        Half-width of the window, in scales, where the supplementary wavelets are looked
        for around the first one [-] (Shahi & Baker: 0.4).
    wavefun_level : int
        Refinement level of ``pywt.Wavelet.wavefun`` for the wavelet function [-].
    pi_threshold : float
        Pulse-indicator threshold [-] (Baker 2007: 0.85).
    min_pgv : float
        Smallest PGV of a pulse-like record [m/s] (Baker 2007: 0.30 m/s).
    early_pulse_fraction, early_record_fraction : float
        Early arrival: the pulse reaches ``early_pulse_fraction`` of its cumulative
        squared velocity before the record reaches ``early_record_fraction`` of its own [-].
    fit_mp : bool
        Fit the Mavroeidis-Papageorgiou model.
    gamma_bounds : tuple of float
        Bounds of the MP oscillation parameter ``gamma`` [-] (default 1-3, see the module
        notes); the MP fit window is ``gamma_bounds[1] * Tp_wavelet`` long.
    mp_displacement : bool
        Fit the MP model to the displacement as well as the velocity (as MP 2003 did);
        velocity only when false.
    """

    tp_min: float = 0.25
    tp_max: float = 15.0
    n_scales: int = 60
    n_refine: int = 41
    n_wavelets: int = 10
    position_window: float = 0.4
    wavefun_level: int = 10
    pi_threshold: float = 0.85
    min_pgv: float = 0.30
    early_pulse_fraction: float = 0.10
    early_record_fraction: float = 0.20
    fit_mp: bool = True
    gamma_bounds: tuple[float, float] = (1.0, 3.0)
    mp_displacement: bool = True

    def __post_init__(self) -> None:
        if not (0 < self.tp_min < self.tp_max and math.isfinite(self.tp_max)):
            raise ValueError(f"tp_min={self.tp_min!r}, tp_max={self.tp_max!r}: valid 0 < tp_min < tp_max s")
        if self.n_scales < 2 or self.n_refine < 1 or self.n_wavelets < 1:
            raise ValueError("n_scales >= 2, n_refine >= 1 and n_wavelets >= 1 are required")
        if not (1.0 <= self.gamma_bounds[0] < self.gamma_bounds[1]):
            raise ValueError(f"gamma_bounds={self.gamma_bounds!r}: valid 1 <= low < high")


@dataclass(frozen=True)
class MPParameters:
    """Parameters of the Mavroeidis-Papageorgiou (2003) velocity pulse.

    Parameters
    ----------
    A : float
        Amplitude of the velocity envelope [m/s] (``A >= 0``; the sign is in ``nu``).
    fp : float
        Prevailing frequency [Hz]; the pulse period is ``1 / fp``.
    nu : float
        Phase angle [rad], in [0, 2 pi).
    gamma : float
        Oscillatory character (number of half-cycles, roughly) [-], > 1.
    t0 : float
        Time of the envelope peak [s] from the first sample of the record.
    """

    A: float
    fp: float
    nu: float
    gamma: float
    t0: float

    @property
    def Tp(self) -> float:
        """Pulse period ``1 / fp`` [s]."""
        return 1.0 / self.fp

    def velocity(self, t: np.ndarray) -> np.ndarray:
        """Pulse velocity [m/s] at times ``t`` [s]."""
        return mp_velocity(t, self.A, self.fp, self.nu, self.gamma, self.t0)

    def acceleration(self, t: np.ndarray) -> np.ndarray:
        """Pulse acceleration [m/s^2] at times ``t`` [s] (analytic derivative of :meth:`velocity`)."""
        return mp_acceleration(t, self.A, self.fp, self.nu, self.gamma, self.t0)

    def displacement(self, t: np.ndarray) -> np.ndarray:
        """Pulse displacement [m] at times ``t`` [s] (analytic integral of :meth:`velocity`, zero
        before the pulse)."""
        return mp_displacement(t, self.A, self.fp, self.nu, self.gamma, self.t0)


@dataclass(frozen=True)
class MPFit:
    """Result of :func:`fit_mp`.

    Parameters
    ----------
    params : MPParameters
        Best-fitting MP parameters.
    v_rms_ratio : float
        RMS of (record - model) velocity over the RMS of the record velocity, in the fit
        window [-] (0: perfect fit).
    d_rms_ratio : float
        The same for the displacement, each taken about its mean over the window [-].
    t_start, t_end : float
        Fit window [s].
    """

    params: MPParameters
    v_rms_ratio: float
    d_rms_ratio: float
    t_start: float
    t_end: float


@dataclass
class PulseResult:
    """Result of :func:`extract_pulse`.

    Attributes
    ----------
    Tp_s : float
        Pulse period of the wavelet method (pseudo-period of the pulse scale) [s].
    Tp_mp_s : float
        Pulse period of the MP fit, ``1 / fp`` [s] (NaN when not fitted).
    Tp_br_s : float
        Pulse period of Bray & Rodriguez-Marek (2004): twice the duration of the velocity
        half-cycle holding the PGV [s].
    pulse_like : bool
        Baker (2007) classification: ``PI > 0.85``, early pulse and ``PGV >= 0.30 m/s``.
    pulse_indicator : float
        Baker's pulse indicator PI [-], in (0, 1).
    pgv_ratio : float
        PGV of the residual over PGV of the record [-].
    energy_ratio : float
        Cumulative squared velocity of the residual over that of the record [-].
    early : bool
        Whether the pulse arrives early (see the module notes).
    pgv_m_s : float
        PGV of the record [m/s].
    mp : MPParameters or None
        Fitted MP parameters.
    mp_rms_ratio : float
        RMS of (record - MP pulse) velocity over RMS of the record velocity, in the MP fit
        window [-] (NaN when not fitted).
    mp_disp_rms_ratio : float
        The same for the displacement (each about its mean over the window) [-].
    mp_window_s : tuple of float
        MP fit window (start, end) [s] (NaNs when not fitted).
    br_half_cycle_s : tuple of float
        Zero crossings (start, end) [s] that bracket the PGV (Bray & Rodriguez-Marek).
    scale : float
        Pulse scale [samples].
    coefficient : float
        Largest wavelet coefficient [m/s * sqrt(samples)].
    t_pulse_s : float
        Time of the centre of the largest wavelet [s].
    dt_s : float
        Time step [s].
    velocity : numpy.ndarray
        Velocity of the record [m/s].
    pulse_velocity : numpy.ndarray
        Extracted (wavelet) pulse [m/s].
    residual_velocity : numpy.ndarray
        ``velocity - pulse_velocity`` [m/s].
    mp_velocity : numpy.ndarray
        Fitted MP pulse [m/s] (zeros when not fitted).
    """

    Tp_s: float
    Tp_mp_s: float
    Tp_br_s: float
    pulse_like: bool
    pulse_indicator: float
    pgv_ratio: float
    energy_ratio: float
    early: bool
    pgv_m_s: float
    mp: MPParameters | None
    mp_rms_ratio: float
    mp_disp_rms_ratio: float
    mp_window_s: tuple[float, float]
    br_half_cycle_s: tuple[float, float]
    scale: float
    coefficient: float
    t_pulse_s: float
    dt_s: float
    velocity: np.ndarray = field(repr=False)
    pulse_velocity: np.ndarray = field(repr=False)
    residual_velocity: np.ndarray = field(repr=False)
    mp_velocity: np.ndarray = field(repr=False)

    @property
    def time(self) -> np.ndarray:
        """Sample times [s]."""
        return np.arange(self.velocity.size) * self.dt_s

    def summary(self) -> dict[str, Any]:
        """The scalar results, JSON-ready, with the MP parameters as ``mp_A_m_s``, ``mp_fp_hz``,
        ``mp_nu_rad``, ``mp_gamma``, ``mp_t0_s`` and the fit quality and window as
        ``mp_rms_ratio``, ``mp_disp_rms_ratio``, ``mp_window_start_s``, ``mp_window_end_s``
        (None when not fitted)."""
        mp = self.mp
        return {
            "Tp_s": float(self.Tp_s),
            "Tp_mp_s": float(self.Tp_mp_s) if mp is not None else None,
            "Tp_br_s": float(self.Tp_br_s),
            "pulse_like": bool(self.pulse_like),
            "pulse_indicator": float(self.pulse_indicator),
            "pgv_ratio": float(self.pgv_ratio),
            "energy_ratio": float(self.energy_ratio),
            "early": bool(self.early),
            "pgv_m_s": float(self.pgv_m_s),
            "t_pulse_s": float(self.t_pulse_s),
            "mp_A_m_s": None if mp is None else float(mp.A),
            "mp_fp_hz": None if mp is None else float(mp.fp),
            "mp_nu_rad": None if mp is None else float(mp.nu),
            "mp_gamma": None if mp is None else float(mp.gamma),
            "mp_t0_s": None if mp is None else float(mp.t0),
            "mp_rms_ratio": None if mp is None else float(self.mp_rms_ratio),
            "mp_disp_rms_ratio": None if mp is None else float(self.mp_disp_rms_ratio),
            "mp_window_start_s": None if mp is None else float(self.mp_window_s[0]),
            "mp_window_end_s": None if mp is None else float(self.mp_window_s[1]),
            "br_half_cycle_start_s": float(self.br_half_cycle_s[0]),
            "br_half_cycle_end_s": float(self.br_half_cycle_s[1]),
        }


# ----------------------------------------------------------------------------- db4 CWT


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


def _wavelet_at(n: int, scale: float, position: int, level: int) -> np.ndarray:
    """``psi((k - b)/a + x_c) / sqrt(a)`` for ``k = 0..n-1`` (zero outside the support)."""
    w, jmin, jmax = _kernel(scale, level)
    out = np.zeros(n)
    lo = position + jmin
    hi = position + jmax + 1
    klo, khi = max(lo, 0), min(hi, n)
    if khi > klo:
        out[klo:khi] = w[klo - lo : khi - lo]
    return out / math.sqrt(scale)


# ----------------------------------------------------------------------------- classification


def pulse_indicator(pgv_ratio: float, energy_ratio: float) -> float:
    """Baker's (2007) pulse indicator ``1 / (1 + exp(-23.3 + 14.6 pgv_ratio + 20.5 energy_ratio))`` [-]."""
    z = -23.3 + 14.6 * pgv_ratio + 20.5 * energy_ratio
    return float(1.0 / (1.0 + math.exp(min(z, 700.0))))


def _time_of_fraction(x2: np.ndarray, frac: float, dt: float) -> float:
    c = np.cumsum(x2)
    if c[-1] <= 0:
        return math.inf
    return float(np.searchsorted(c, frac * c[-1]) * dt)


# ----------------------------------------------------------------------------- MP model


def mp_velocity(t: np.ndarray, A: float, fp: float, nu: float, gamma: float, t0: float) -> np.ndarray:
    """Mavroeidis-Papageorgiou (2003) velocity pulse [m/s].

    Parameters
    ----------
    t : numpy.ndarray
        Times [s].
    A : float
        Envelope amplitude [m/s].
    fp : float
        Prevailing frequency [Hz].
    nu : float
        Phase [rad].
    gamma : float
        Oscillatory character [-].
    t0 : float
        Time of the envelope peak [s].
    """
    tau = np.asarray(t, dtype=float) - t0
    w = 2.0 * math.pi * fp
    inside = np.abs(tau) <= gamma / (2.0 * fp)
    v = 0.5 * A * (1.0 + np.cos(w * tau / gamma)) * np.cos(w * tau + nu)
    return np.where(inside, v, 0.0)


def mp_acceleration(t: np.ndarray, A: float, fp: float, nu: float, gamma: float, t0: float) -> np.ndarray:
    """Time derivative of :func:`mp_velocity` [m/s^2] (same parameters)."""
    tau = np.asarray(t, dtype=float) - t0
    w = 2.0 * math.pi * fp
    inside = np.abs(tau) <= gamma / (2.0 * fp)
    a = (
        -0.5
        * A
        * (
            (w / gamma) * np.sin(w * tau / gamma) * np.cos(w * tau + nu)
            + (1.0 + np.cos(w * tau / gamma)) * w * np.sin(w * tau + nu)
        )
    )
    return np.where(inside, a, 0.0)


def mp_displacement(t: np.ndarray, A: float, fp: float, nu: float, gamma: float, t0: float) -> np.ndarray:
    """Displacement of the MP pulse [m]: the integral of :func:`mp_velocity` from the start of the pulse.

    With ``w = 2 pi fp``, ``w1 = w (1 + 1/gamma)``, ``w2 = w (1 - 1/gamma)`` and the pulse
    start ``ts = -gamma / (2 fp)`` (times ``tau = t - t0``), the velocity is
    ``A/2 cos(w tau + nu) + A/4 [cos(w1 tau + nu) + cos(w2 tau + nu)]``, so the displacement is
    ``A/(2w) [sin(w tau + nu)]_ts^tau + A/(4 w1) [sin(w1 tau + nu)]_ts^tau
    + A/(4 w2) [sin(w2 tau + nu)]_ts^tau`` (the last term is ``A/4 cos(nu) (tau - ts)`` for
    ``gamma = 1``); zero before the pulse, constant (the residual displacement) after it.

    Parameters
    ----------
    t : numpy.ndarray
        Times [s].
    A, fp, nu, gamma, t0 : float
        MP parameters, as in :func:`mp_velocity`.
    """
    tau = np.asarray(t, dtype=float) - t0
    w = 2.0 * math.pi * fp
    ts = -gamma / (2.0 * fp)
    tt = np.clip(tau, ts, -ts)

    def term(om: float) -> np.ndarray:
        if abs(om * ts) < 1e-7:  # gamma = 1 (w2 = 0): the limit, to O((om ts)^2)
            return math.cos(nu) * (tt - ts)
        return (np.sin(om * tt + nu) - math.sin(om * ts + nu)) / om

    w2 = w * (1.0 - 1.0 / gamma)
    return 0.5 * A * term(w) + 0.25 * A * term(w * (1.0 + 1.0 / gamma)) + 0.25 * A * term(w2)


def fit_mp(
    t: np.ndarray,
    v: np.ndarray,
    tp0: float,
    t_center: float,
    amp0: float | None = None,
    gamma_bounds: tuple[float, float] = (1.0, 3.0),
    n_polish: int = 2,
    *,
    displacement: bool = True,
) -> MPFit:
    """Least-squares fit of the MP pulse to the velocity (and displacement) of a record.

    Parameters
    ----------
    t : numpy.ndarray
        Times [s], uniformly spaced.
    v : numpy.ndarray
        Velocity [m/s].
    tp0 : float
        Starting pulse period [s] (the wavelet estimate); ``fp`` is bounded to
        ``[1/(2 tp0), 2/tp0]``.
    t_center : float
        Centre of the fit window [s] (the energy centroid of the wavelet pulse).
    amp0 : float, optional
        Starting amplitude [m/s] (default: the largest ``|v|`` in the window).
    gamma_bounds : tuple of float
        Bounds of ``gamma`` [-]; the window is ``t_center +- gamma_bounds[1] * tp0 / 2``
        (clipped to the record).
    n_polish : int
        Number of starts refined by least squares per trial frequency [-]: of the 672 grid
        starts (8 phases, 4 ``gamma``, 7 frequencies, 3 times), the ``n_polish`` best of each
        of the 7 frequencies (so that every period range gets its own local optimum).
    displacement : bool
        Fit the displacement too (record and model displacement taken about their means over
        the window, velocity and displacement residuals each divided by the record's largest
        absolute value in the window, equal weights); velocity only when false.

    Returns
    -------
    MPFit
        Best parameters, fit quality and window.
    """
    t = np.asarray(t, dtype=float)
    v = np.asarray(v, dtype=float)
    if t.size < 4 or v.shape != t.shape:
        raise IsorockError("fit_mp needs matching time and velocity arrays of 4 samples or more")
    dt = float(t[1] - t[0])
    fp0 = 1.0 / tp0
    glo, ghi = gamma_bounds
    half = 0.5 * ghi * tp0
    ta, tb = max(t[0], t_center - half), min(t[-1], t_center + half)
    sel = (t >= ta) & (t <= tb)
    if np.count_nonzero(sel) < 4:
        sel = np.ones(t.size, dtype=bool)
        ta, tb = float(t[0]), float(t[-1])
    d = cumulative_trapezoid(v, dx=dt, initial=0.0)
    # fit on a grid of >= 40 samples per shortest admissible period (the pulse is smooth)
    step = max(1, int(0.5 * tp0 / 40.0 / dt))
    ts, vs = t[sel][::step], v[sel][::step]
    ds = d[sel][::step]
    ds = ds - ds.mean()
    vn = float(np.max(np.abs(vs))) or 1.0
    dn = float(np.max(np.abs(ds))) or 1.0
    norm = 1.0 / math.sqrt(ts.size)
    lb = np.array([0.0, 0.5 * fp0, -2.0 * math.pi, glo, ta])
    ub = np.array([3.0 * vn, 2.0 * fp0, 4.0 * math.pi, ghi, tb])

    def resid(p: np.ndarray) -> np.ndarray:
        rv = (mp_velocity(ts, *p) - vs) / vn
        if not displacement:
            return rv * norm
        dm = mp_displacement(ts, *p)
        rd = (dm - dm.mean() - ds) / dn
        return np.concatenate([rv, rd]) * norm

    # many cheap starts (phase, oscillation, frequency, time), the best few polished by least squares
    a0 = vn if amp0 is None else float(amp0)
    gammas = glo + (ghi - glo) * np.array([0.125, 0.375, 0.625, 0.875])
    fmuls = (0.6, 0.75, 0.87, 1.0, 1.15, 1.3, 1.5)
    starts: dict[float, list[tuple[float, np.ndarray]]] = {f: [] for f in fmuls}
    for nu in np.linspace(0.0, 2.0 * math.pi, 8, endpoint=False):
        for gamma in gammas:
            for fmul in fmuls:
                for dt0 in (-0.25, 0.0, 0.25):
                    p0 = np.clip([a0, fp0 * fmul, nu, gamma, t_center + dt0 * tp0], lb, ub)
                    starts[fmul].append((float(np.sum(resid(p0) ** 2)), p0))
    chosen = [p0 for f in fmuls for _c, p0 in sorted(starts[f], key=lambda s: s[0])[:n_polish]]
    best = None
    for p0 in chosen:
        sol = least_squares(resid, p0, bounds=(lb, ub), x_scale=[vn, fp0, 1.0, 1.0, tp0], max_nfev=300)
        if best is None or sol.cost < best.cost:
            best = sol
    assert best is not None
    A, fp, nu, gamma, t0 = (float(x) for x in best.x)
    mp = MPParameters(A=A, fp=fp, nu=float(nu % (2.0 * math.pi)), gamma=gamma, t0=t0)
    tw, vw, dw = t[sel], v[sel], d[sel] - d[sel].mean()
    mv = mp.velocity(tw)
    md = mp.displacement(tw)
    md = md - md.mean()

    def ratio(x: np.ndarray, y: np.ndarray) -> float:
        den = float(np.sqrt(np.mean(y**2)))
        return float(np.sqrt(np.mean((x - y) ** 2))) / den if den > 0 else math.nan

    return MPFit(params=mp, v_rms_ratio=ratio(mv, vw), d_rms_ratio=ratio(md, dw), t_start=ta, t_end=tb)


# ----------------------------------------------------------------------------- Bray & Rodriguez-Marek


def tp_bray_rodriguez_marek(v: np.ndarray, dt: float) -> tuple[float, float, float]:
    """Pulse period of Bray & Rodriguez-Marek (2004) from a velocity history.

    The velocity pulse of largest amplitude is the half-cycle holding the PGV; its zero
    crossings (linearly interpolated between samples; the record's ends when the velocity
    does not change sign before or after the PGV) bracket it, and the period is twice their
    distance: ``Tv = 2 (t_end - t_start)``.

    Parameters
    ----------
    v : numpy.ndarray
        Velocity [m/s] (any unit).
    dt : float
        Time step [s].

    Returns
    -------
    (float, float, float)
        ``Tv`` [s], ``t_start`` [s], ``t_end`` [s] (times from the first sample).
    """
    v = np.asarray(v, dtype=float)
    if v.size < 2 or not np.any(v):
        raise IsorockError("velocity is too short or all zeros: no pulse period")
    i = int(np.argmax(np.abs(v)))
    same = np.sign(v) == np.sign(v[i])  # False at a zero or an opposite sign
    before = np.flatnonzero(~same[:i])
    after = np.flatnonzero(~same[i + 1 :])
    if before.size:
        k = int(before[-1])  # last sample that is not on the PGV side; k + 1 is
        t_start = (k + v[k] / (v[k] - v[k + 1])) * dt
    else:
        t_start = 0.0
    if after.size:
        k = i + 1 + int(after[0])  # first sample past the crossing; k - 1 is on the PGV side
        t_end = (k - 1 + v[k - 1] / (v[k - 1] - v[k])) * dt
    else:
        t_end = (v.size - 1) * dt
    return 2.0 * (t_end - t_start), float(t_start), float(t_end)


# ----------------------------------------------------------------------------- orientation


def fault_azimuth(strike_deg: float, orientation: str) -> float:
    """Azimuth [deg, clockwise from north, in [0, 360)] of the strike-normal or strike-parallel direction.

    Parameters
    ----------
    strike_deg : float
        Fault strike [deg clockwise from north].
    orientation : str
        ``"SN"`` (strike-normal, ``strike + 90``) or ``"SP"`` (strike-parallel, ``strike``);
        ``"FN"``/``"FP"`` are the same. Only the line matters for a pulse period: the
        opposite azimuth gives the same component with its sign changed.
    """
    o = orientation.strip().upper()
    if o in ("SN", "FN"):
        return float((strike_deg + 90.0) % 360.0)
    if o in ("SP", "FP"):
        return float(strike_deg % 360.0)
    raise ValueError(f"orientation {orientation!r}: valid SN, SP (or FN, FP)")


def rotate_horizontal(
    c1: np.ndarray | Trace, az1: float, c2: np.ndarray | Trace, az2: float, azimuth: float
) -> np.ndarray | Trace:
    """The horizontal component along ``azimuth`` from two components of known azimuths.

    A component along azimuth ``az`` (deg clockwise from north, positive towards ``az``) is
    ``N cos(az) + E sin(az)``; solving for ``N`` and ``E`` from the two given components and
    projecting gives ``c = [c1 sin(az2 - azimuth) + c2 sin(azimuth - az1)] / sin(az2 - az1)``
    (for orthogonal components, the usual rotation). The components need not be orthogonal,
    but not closer than 10 deg to parallel.

    Parameters
    ----------
    c1, c2 : numpy.ndarray or obspy.Trace
        The two components (same time step and start; the longer is cut to the shorter).
    az1, az2 : float
        Their azimuths [deg].
    azimuth : float
        Azimuth of the wanted component [deg].

    Returns
    -------
    numpy.ndarray or obspy.Trace
        The rotated component; a Trace (a copy of ``c1``'s header, channel set to the azimuth,
        one processing-history line added) when ``c1`` and ``c2`` are Traces.
    """
    s12 = math.sin(math.radians(az2 - az1))
    if abs(s12) < math.sin(math.radians(10.0)):
        raise IsorockError(f"components at {az1:g} and {az2:g} deg are too close to parallel to rotate")
    traces = isinstance(c1, Trace) and isinstance(c2, Trace)
    if isinstance(c1, Trace) != isinstance(c2, Trace):
        raise IsorockError("rotate_horizontal needs two Traces or two arrays")
    if traces:
        if not math.isclose(c1.stats.delta, c2.stats.delta, rel_tol=1e-6):
            raise IsorockError(f"components have time steps {c1.stats.delta:g} and {c2.stats.delta:g} s")
        x1, x2 = np.asarray(c1.data, dtype=float), np.asarray(c2.data, dtype=float)
    else:
        x1, x2 = np.asarray(c1, dtype=float), np.asarray(c2, dtype=float)
    n = min(x1.size, x2.size)
    w1 = math.sin(math.radians(az2 - azimuth)) / s12
    w2 = math.sin(math.radians(azimuth - az1)) / s12
    out = w1 * x1[:n] + w2 * x2[:n]
    if not traces:
        return out
    tr = c1.copy()
    tr.data = out
    tr.stats.channel = f"{azimuth % 360.0:05.1f}"
    hist = list(tr.stats.get("processing", []))
    hist.append(f"isorock: rotate_horizontal({az1:g}, {az2:g} -> {azimuth % 360.0:g} deg)")
    tr.stats.processing = hist
    return tr


# ----------------------------------------------------------------------------- extraction


def _as_dt_acc(record: object) -> tuple[float, np.ndarray]:
    if isinstance(record, Trace):
        return float(record.stats.delta), np.asarray(record.data, dtype=float)
    if hasattr(record, "dt") and hasattr(record, "acc"):  # isorock.GroundMotion
        return float(record.dt), np.asarray(record.acc, dtype=float)
    if isinstance(record, tuple) and len(record) == 2:
        dt, acc = record
        return float(dt), np.asarray(acc, dtype=float)
    raise IsorockError(
        f"extract_pulse needs an obspy Trace, a GroundMotion or (dt, acc), got {type(record).__name__}"
    )


def extract_pulse(
    record: Trace | tuple[float, np.ndarray] | Any, config: PulseConfig | None = None
) -> PulseResult:
    """Extract the velocity pulse of a record and its period.

    Parameters
    ----------
    record : obspy.Trace, GroundMotion or (dt, acc)
        Ground acceleration [m/s^2] with time step dt [s], normally processed (see
        :func:`isorock.processing.process`): the velocity is its trapezoidal integral.
    config : PulseConfig, optional
        Settings; the defaults follow Baker (2007) for the wavelet method and the module
        notes for the MP fit.

    Returns
    -------
    PulseResult
        Periods (wavelet, MP fit, Bray & Rodriguez-Marek), classification, MP parameters and
        fit quality, and the velocity histories. The record is analysed in the orientation it
        is given; rotate it first (:func:`rotate_horizontal`) to compare with a published
        strike-normal or strike-parallel ``Tp``.
    """
    cfg = config or PulseConfig()
    dt, acc = _as_dt_acc(record)
    if not (math.isfinite(dt) and dt > 0):
        raise IsorockError(f"time step dt={dt!r} is out of range: valid dt > 0 s")
    if acc.ndim != 1 or acc.size < 16:
        raise IsorockError(f"record has {acc.size} samples: too short for a pulse analysis")
    if not np.all(np.isfinite(acc)):
        raise IsorockError("record has non-finite samples")
    v = cumulative_trapezoid(acc, dx=dt, initial=0.0)
    n = v.size
    pgv = float(np.max(np.abs(v)))
    if pgv == 0:
        raise IsorockError("record is all zeros: no velocity pulse")
    fc = central_frequency(cfg.wavefun_level)
    lvl = cfg.wavefun_level

    # 1. coarse CWT over the period range, then refine the scale near the maximum
    a_min = max(cfg.tp_min * fc / dt, 1.0)
    a_max = max(cfg.tp_max * fc / dt, a_min * 1.01)
    scales = np.geomspace(a_min, a_max, cfg.n_scales)
    coefs = cwt_db4(v, scales, lvl)
    i, b0 = np.unravel_index(int(np.argmax(np.abs(coefs))), coefs.shape)
    lo = scales[max(i - 1, 0)]
    hi = scales[min(i + 1, scales.size - 1)]
    fine = np.geomspace(lo, hi, cfg.n_refine)
    fcoefs = cwt_db4(v, fine, lvl)
    best_val, best_scale, best_pos = -1.0, float(scales[i]), int(b0)
    for k, a in enumerate(fine):
        half = int(math.ceil(cfg.position_window * a))
        w0, w1 = max(0, b0 - half), min(n, b0 + half + 1)
        j = w0 + int(np.argmax(np.abs(fcoefs[k, w0:w1])))
        if abs(fcoefs[k, j]) > best_val:
            best_val, best_scale, best_pos = abs(fcoefs[k, j]), float(a), j
    scale, b0 = best_scale, best_pos

    # 2. pulse from up to n_wavelets wavelets at the pulse scale near the first position
    pulse = np.zeros(n)
    half = int(math.ceil(cfg.position_window * scale))
    w0, w1 = max(0, b0 - half), min(n, b0 + half + 1)
    first_coef = None
    for _ in range(cfg.n_wavelets):
        c = cwt_db4(v - pulse, np.array([scale]), lvl)[0]
        j = w0 + int(np.argmax(np.abs(c[w0:w1])))
        coef = float(c[j])
        if first_coef is None:
            first_coef = coef
        if coef == 0.0:
            break
        pulse += coef * _wavelet_at(n, scale, j, lvl)
    resid = v - pulse
    tp = scale * dt / fc

    # 3. classification (Baker 2007)
    pgv_ratio = float(np.max(np.abs(resid))) / pgv
    energy_ratio = float(np.sum(resid**2) / np.sum(v**2))
    pi = pulse_indicator(pgv_ratio, energy_ratio)
    t_pulse = _time_of_fraction(pulse**2, cfg.early_pulse_fraction, dt)
    t_orig = _time_of_fraction(v**2, cfg.early_record_fraction, dt)
    early = bool(t_pulse < t_orig)
    pulse_like = bool(pi > cfg.pi_threshold and early and pgv >= cfg.min_pgv)

    # 4. MP fit
    t = np.arange(n) * dt
    mp = None
    mp_v = np.zeros(n)
    rms_ratio = d_rms_ratio = tp_mp = math.nan
    window = (math.nan, math.nan)
    if cfg.fit_mp:
        p2 = pulse**2
        t_center = float(np.sum(t * p2) / np.sum(p2)) if np.sum(p2) > 0 else b0 * dt
        fit = fit_mp(t, v, tp, t_center, None, cfg.gamma_bounds, displacement=cfg.mp_displacement)
        mp = fit.params
        rms_ratio, d_rms_ratio, window = fit.v_rms_ratio, fit.d_rms_ratio, (fit.t_start, fit.t_end)
        mp_v = mp.velocity(t)
        tp_mp = mp.Tp

    # 5. Bray & Rodriguez-Marek (2004)
    tp_br, br0, br1 = tp_bray_rodriguez_marek(v, dt)

    return PulseResult(
        Tp_s=float(tp),
        Tp_mp_s=float(tp_mp),
        Tp_br_s=float(tp_br),
        pulse_like=pulse_like,
        pulse_indicator=pi,
        pgv_ratio=pgv_ratio,
        energy_ratio=energy_ratio,
        early=early,
        pgv_m_s=pgv,
        mp=mp,
        mp_rms_ratio=float(rms_ratio),
        mp_disp_rms_ratio=float(d_rms_ratio),
        mp_window_s=(float(window[0]), float(window[1])),
        br_half_cycle_s=(br0, br1),
        scale=float(scale),
        coefficient=float(first_coef or 0.0),
        t_pulse_s=float(b0 * dt),
        dt_s=dt,
        velocity=v,
        pulse_velocity=pulse,
        residual_velocity=resid,
        mp_velocity=mp_v,
    )
