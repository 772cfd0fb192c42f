"""Extraction of the velocity pulse of a record: the wavelet pulse and its period, the classification,
the MP fit and the Bray & Rodriguez-Marek period, in one :class:`PulseResult`."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from obspy import Trace
from scipy.integrate import cumulative_trapezoid

from isorock.errors import IsorockError
from isorock.pulse.bray import tp_bray_rodriguez_marek
from isorock.pulse.mp import MPParameters, fit_mp
from isorock.pulse.wavelet import central_frequency, cwt_db4, pulse_indicator, time_of_fraction, wavelet_at

__all__ = ["PulseConfig", "PulseResult", "extract_pulse", "TP_METHODS", "tp_method_of", "tp_by_method"]

#: the three Tp definitions: key -> (name, result attribute [s])
TP_METHODS: dict[str, tuple[str, str]] = {
    "wavelet": ("db4 wavelet, Baker (2007)", "Tp_s"),
    "mp": ("Mavroeidis & Papageorgiou (2003) fit", "Tp_mp_s"),
    "br": ("Bray & Rodriguez-Marek (2004), twice the PGV half-cycle", "Tp_br_s"),
}


def tp_method_of(source: str | None) -> str:
    """The Tp definition of a published value from its source: ``"br"`` for Bray & Rodriguez-Marek,
    ``"mp"`` for Mavroeidis & Papageorgiou, ``"wavelet"`` otherwise (Baker 2007)."""
    s = str(source or "").lower()
    if "bray" in s or "rodriguez" in s:
        return "br"
    if "mavroeidis" in s or "papageorgiou" in s:
        return "mp"
    return "wavelet"


def tp_by_method(result: PulseResult, method: str) -> float | None:
    """Tp [s] of ``result`` by one of :data:`TP_METHODS` (None: the MP fit was not run)."""
    value = getattr(result, TP_METHODS[method][1])
    if method == "mp" and result.mp is None:
        return None
    return None if value is None else float(value)


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
        pulse += coef * wavelet_at(n, scale, j, lvl)
    resid = v - pulse
    tp = scale * dt / fc

    # 3. classification (Baker 2007)
    pgv_ratio = float(np.max(np.abs(resid))) / pgv
    energy_ratio = float(np.sum(resid**2) / np.sum(v**2))
    pi = pulse_indicator(pgv_ratio, energy_ratio)
    t_pulse = time_of_fraction(pulse**2, cfg.early_pulse_fraction, dt)
    t_orig = time_of_fraction(v**2, cfg.early_record_fraction, dt)
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
