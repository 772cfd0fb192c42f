"""The processing steps: plain functions ``step(trace, **params) -> trace`` on ground acceleration
[m/s^2], each recording what it did once (:func:`isorock.processing.history.record_step`: an
:class:`~isorock.processing.history.AppliedStep` and its history line); :data:`STEPS` names them for
the YAML configuration (:mod:`isorock.processing.config`)."""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Mapping

import numpy as np
from obspy import Trace

from isorock.constants import G
from isorock.errors import IsorockError
from isorock.processing.history import record_step
from isorock.processing.metrics import cumulative_trapezoid, displacement, velocity
from isorock.processing.qa import fail

__all__ = [
    "STEPS",
    "StepFunction",
    "detrend",
    "taper",
    "bandpass_filter",
    "baseline_polynomial",
    "resample",
    "check_pga",
    "check_tail",
    "as_float",
]

StepFunction = Callable[..., Trace]


# ----------------------------------------------------------------------------- history


def _record(
    tr: Trace, name: str, params: Mapping[str, object], note: str = "", n_before: int | None = None
) -> None:
    """Record the step on ``tr`` (:func:`isorock.processing.history.record_step`): its structured
    provenance and its history line, replacing ObsPy's own lines added after index ``n_before``."""
    record_step(tr, name, params, note, n_before)


def _n_hist(tr: Trace) -> int:
    return len(tr.stats.get("processing", []))


def as_float(tr: Trace) -> None:
    """Make the samples of ``tr`` float64 (in place)."""
    if tr.data.dtype != np.float64:
        tr.data = np.asarray(tr.data, dtype=np.float64)


# ----------------------------------------------------------------------------- processing steps


def detrend(tr: Trace, type: str = "linear") -> Trace:  # noqa: A002 - ObsPy's name
    """Remove the mean (``type="demean"``) or a least-squares line (``"linear"``) from the acceleration.

    Parameters
    ----------
    tr : obspy.Trace
        Acceleration [m/s^2]; changed in place.
    type : {"linear", "demean", "constant", "simple"}
        ObsPy detrend type.
    """
    if type not in ("linear", "demean", "constant", "simple"):
        raise IsorockError(f"detrend: type={type!r} is not valid: valid linear, demean, constant, simple")
    as_float(tr)
    n0 = _n_hist(tr)
    before = float(np.mean(tr.data))
    tr.detrend(type=type)
    _record(tr, "detrend", {"type": type}, f"mean before {before:.4g} m/s^2", n0)
    return tr


def taper(
    tr: Trace,
    type: str = "hann",
    max_percentage: float = 0.05,
    max_length: float | None = None,  # noqa: A002
    side: str = "both",
) -> Trace:
    """Taper both ends (or one) of the record with a cosine-type window.

    Parameters
    ----------
    tr : obspy.Trace
        Acceleration [m/s^2]; changed in place.
    type : str
        ObsPy taper window (``hann`` is the cosine-squared, i.e. full cosine, taper).
    max_percentage : float
        Fraction of the record tapered at each end [-] (0.05 = 5 %).
    max_length : float, optional
        Longest taper at each end [s].
    side : {"both", "left", "right"}
        Which end(s).
    """
    if not (0 < max_percentage <= 0.5):
        raise IsorockError(f"taper: max_percentage={max_percentage!r} is out of range: valid 0 < p <= 0.5")
    as_float(tr)
    n0 = _n_hist(tr)
    tr.taper(max_percentage=max_percentage, type=type, max_length=max_length, side=side)
    ntap = int(min(max_percentage * tr.stats.npts, (max_length or math.inf) / tr.stats.delta))
    _record(
        tr,
        "taper",
        {"type": type, "max_percentage": max_percentage, "max_length": max_length, "side": side},
        f"{ntap * tr.stats.delta:.3g} s at each tapered end",
        n0,
    )
    return tr


def _butterworth(
    data: np.ndarray, df: float, kind: str, freqs: tuple[float, ...], corners: int, zerophase: bool
) -> np.ndarray:
    """ObsPy's Butterworth filters (``Trace.filter("bandpass" | "highpass" | "lowpass")``,
    :mod:`obspy.signal.filter`), computed as ObsPy computes them (the same corner checks and the same
    scipy calls: :func:`scipy.signal.iirfilter` in second-order sections, :func:`scipy.signal.sosfilt`
    forwards and, when ``zerophase``, backwards), so the samples are the same bit for bit; without
    importing :mod:`obspy.signal`, whose package loads matplotlib. scipy.signal is imported here, the
    only processing step that needs it besides ObsPy's detrend and taper."""
    from scipy.signal import iirfilter, sosfilt

    fe = 0.5 * df
    btype = {"bandpass": "band", "highpass": "highpass", "lowpass": "lowpass"}[kind]
    if kind == "bandpass":
        if freqs[1] / fe - 1.0 > -1e-6:
            warnings.warn(
                f"Selected high corner frequency ({freqs[1]}) of bandpass is at or above Nyquist ({fe}). "
                "Applying a high-pass instead.",
                stacklevel=3,
            )
            return _butterworth(data, df, "highpass", freqs[:1], corners, zerophase)
        if freqs[0] / fe > 1:
            raise ValueError("Selected low corner frequency is above Nyquist.")
    elif freqs[0] / fe > 1:
        if kind == "highpass":
            raise ValueError("Selected corner frequency is above Nyquist.")
        # ObsPy's lowpass warns and goes on with the frequency given, which scipy then refuses
        warnings.warn(
            "Selected corner frequency is above Nyquist. Setting Nyquist as high corner.", stacklevel=3
        )
    wn = [f / fe for f in freqs]
    sos = iirfilter(corners, wn[0] if len(wn) == 1 else wn, btype=btype, ftype="butter", output="sos")
    if zerophase:
        first = np.flip(sosfilt(sos, data, axis=-1), axis=-1)
        return np.flip(sosfilt(sos, first, axis=-1), axis=-1)
    return sosfilt(sos, data, axis=-1)


def bandpass_filter(
    tr: Trace,
    freqmin: float | None = 0.05,
    freqmax: float | None = 40.0,
    corners: int = 4,
    zerophase: bool = True,
    pad: bool = True,
    max_nyquist_fraction: float = 0.8,
    luf_hz: float | None = None,
) -> Trace:
    """Butterworth band-pass (or high-pass / low-pass) filter, acausal by default, with zero pads.

    The record is padded with zeros of total length ``1.5 * corners / freqmin`` seconds
    (half at each end; Boore 2005 for acausal filters), filtered as ObsPy filters (:func:`_butterworth`;
    ``zerophase=True`` runs the filter forwards and backwards: no phase shift, squared
    amplitude response), and the pads are cut off again so that the record keeps its
    samples and start time.

    Parameters
    ----------
    tr : obspy.Trace
        Acceleration [m/s^2]; changed in place.
    freqmin : float or None
        High-pass corner [Hz]; None for a low-pass only.
    freqmax : float or None
        Low-pass corner [Hz], lowered to ``max_nyquist_fraction`` of the Nyquist
        frequency when above it; None for a high-pass only.
    corners : int
        Butterworth order of one pass [-].
    zerophase : bool
        Acausal (zero-phase) filter when True.
    pad : bool
        Zero-pad before filtering when True.
    max_nyquist_fraction : float
        Cap on ``freqmax`` as a fraction of the Nyquist frequency [-].
    luf_hz : float or None
        The record's lowest usable frequency [Hz] (PEER's, ``records add --peer-search``): the
        high-pass corner ``freqmin`` is raised to it when it is higher, and the history says so
        (:func:`isorock.processing.with_lowest_usable_frequency` sets it for a record).
    """
    if luf_hz is not None and not (math.isfinite(luf_hz) and luf_hz > 0):
        raise IsorockError(f"bandpass_filter: luf_hz={luf_hz!r} is out of range: valid > 0 Hz")
    luf_note = ""
    if luf_hz is not None and freqmin is not None:
        if luf_hz > freqmin:
            luf_note = (
                f"; high-pass corner raised from {freqmin:g} Hz to the record's lowest usable frequency "
                f"{luf_hz:g} Hz"
            )
            freqmin = float(luf_hz)
        else:
            luf_note = f"; the record's lowest usable frequency {luf_hz:g} Hz is not above freqmin: kept"
    if freqmin is None and freqmax is None:
        raise IsorockError("bandpass_filter: give freqmin, freqmax or both")
    if freqmin is not None and not freqmin > 0:
        raise IsorockError(f"bandpass_filter: freqmin={freqmin!r} is out of range: valid > 0 Hz")
    if not (isinstance(corners, int) and corners >= 1):
        raise IsorockError(f"bandpass_filter: corners={corners!r} is out of range: valid integer >= 1")
    as_float(tr)
    n0 = _n_hist(tr)
    nyq = 0.5 / tr.stats.delta
    fmax = None if freqmax is None else min(float(freqmax), max_nyquist_fraction * nyq)
    if freqmin is not None and fmax is not None and fmax <= freqmin:
        raise IsorockError(
            f"bandpass_filter: freqmax {fmax:g} Hz (after the Nyquist cap) is not above "
            f"freqmin {freqmin:g} Hz"
        )
    npad = 0
    if pad and freqmin is not None:
        npad = int(math.ceil(0.5 * 1.5 * corners / freqmin / tr.stats.delta))
    data = np.concatenate([np.zeros(npad), tr.data, np.zeros(npad)]) if npad else tr.data.copy()
    work = Trace(data=data, header={"delta": tr.stats.delta})
    df = work.stats.sampling_rate
    if freqmin is not None and fmax is not None:
        work.data = _butterworth(work.data, df, "bandpass", (freqmin, fmax), corners, zerophase)
        kind = "band-pass"
    elif freqmin is not None:
        work.data = _butterworth(work.data, df, "highpass", (freqmin,), corners, zerophase)
        kind = "high-pass"
    else:
        assert fmax is not None  # freqmin and freqmax both None is refused above
        work.data = _butterworth(work.data, df, "lowpass", (fmax,), corners, zerophase)
        kind = "low-pass"
    tr.data = work.data[npad : npad + tr.stats.npts].copy() if npad else work.data
    params: dict[str, object] = {
        "freqmin": freqmin, "freqmax": fmax, "corners": corners, "zerophase": zerophase, "pad": pad
    }  # fmt: skip
    if luf_hz is not None:
        params["luf_hz"] = float(luf_hz)
    _record(
        tr,
        "bandpass_filter",
        params,
        f"{'acausal' if zerophase else 'causal'} Butterworth {kind} (obspy), "
        f"zero pads {npad * tr.stats.delta:.4g} s at each end removed after{luf_note}",
        n0,
    )
    return tr


def baseline_polynomial(tr: Trace, order: int = 6, end_constraints: bool = True) -> Trace:
    """Baseline correction by a polynomial fitted to the displacement (NGA-West2, gmprocess).

    The acceleration is integrated twice; a polynomial ``p(t) = sum_{k=2}^{order} c_k t^k``
    (no constant and linear terms, so that displacement and velocity stay zero at the
    start) is fitted to the displacement by least squares, and ``p''(t)`` is subtracted
    from the acceleration.

    With ``end_constraints`` (the default) the least-squares fit is constrained to pass
    through the displacement and velocity of the last sample (``p(T) = d(T)``,
    ``p'(T) = v(T)``, solved with Lagrange multipliers), so that the corrected record
    ends at rest: zero velocity and zero displacement. Without it, this is the plain
    gmprocess fit, which leaves whatever the fit misses at the end of the record (after
    a band-pass filter whose pads are cut off, often a sizeable part of the PGD).

    Parameters
    ----------
    tr : obspy.Trace
        Acceleration [m/s^2]; changed in place.
    order : int
        Highest power of the polynomial [-], at least 3 with ``end_constraints``, else at least 2.
    end_constraints : bool
        Force zero velocity and displacement at the last sample.
    """
    lowest = 3 if end_constraints else 2
    if not (isinstance(order, int) and order >= lowest):
        raise IsorockError(f"baseline_polynomial: order={order!r} is out of range: valid integer >= {lowest}")
    as_float(tr)
    n0 = _n_hist(tr)
    dt = tr.stats.delta
    n = tr.stats.npts
    T = (n - 1) * dt
    v = velocity(tr)
    d = cumulative_trapezoid(v, dx=dt, initial=0.0)
    x = np.arange(n) * dt / T  # scaled time in [0, 1] for a well-conditioned fit
    powers = np.arange(2, order + 1)
    X = x[:, None] ** powers[None, :]
    if end_constraints:
        # minimise |X c - d|^2 subject to C c = e: p(T) = d(T), T p'(T) = T v(T) (in scaled time)
        C = np.vstack([np.ones(powers.size), powers.astype(float)])
        e = np.array([d[-1], v[-1] * T])
        m = powers.size
        kkt = np.zeros((m + 2, m + 2))
        kkt[:m, :m] = 2.0 * X.T @ X
        kkt[:m, m:] = C.T
        kkt[m:, :m] = C
        rhs = np.concatenate([2.0 * X.T @ d, e])
        coef = np.linalg.solve(kkt, rhs)[:m]
    else:
        coef, *_ = np.linalg.lstsq(X, d, rcond=None)
    # second derivative of p with respect to t = T x
    acc_corr = np.zeros(n)
    for c, k in zip(coef, powers, strict=True):
        acc_corr += c * k * (k - 1) * x ** (k - 2) / T**2
    tr.data = tr.data - acc_corr
    _record(
        tr,
        "baseline_polynomial",
        {"order": order, "end_constraints": end_constraints},
        f"removed the second derivative of the fitted displacement polynomial, "
        f"max {np.max(np.abs(acc_corr)):.3g} m/s^2",
        n0,
    )
    return tr


def resample(
    tr: Trace, dt: float | None = None, method: str = "lanczos", a: int = 20, window: str = "hann"
) -> Trace:
    """Resample the record to the analysis time step ``dt`` (does nothing when ``dt`` is None).

    Parameters
    ----------
    tr : obspy.Trace
        Acceleration [m/s^2]; changed in place.
    dt : float or None
        Target time step [s]; None or equal to the current one: no change (the history says so).
    method : {"lanczos", "fft"}
        ``lanczos``: ObsPy ``Trace.interpolate`` with a Lanczos (windowed sinc) kernel of
        half-width ``a`` samples, preceded, when down-sampling, by an acausal low-pass
        at 0.8 of the new Nyquist frequency; ``fft``: ObsPy ``Trace.resample`` (Fourier
        method: the spectrum is cut or zero-extended at the new Nyquist frequency).
    a : int
        Lanczos kernel half-width [samples].
    window : str
        Window of the FFT method.
    """
    if dt is None:
        _record(tr, "resample", {"dt": None}, "not resampled (no target dt)")
        return tr
    if not (dt > 0):
        raise IsorockError(f"resample: dt={dt!r} is out of range: valid > 0 s")
    if method not in ("lanczos", "fft"):
        raise IsorockError(f"resample: method={method!r} is not valid: valid lanczos, fft")
    as_float(tr)
    old = tr.stats.delta
    if math.isclose(dt, old, rel_tol=1e-9):
        _record(tr, "resample", {"dt": dt}, "not resampled (dt unchanged)")
        return tr
    n0 = _n_hist(tr)
    if method == "lanczos":
        if dt > old:  # down-sampling: anti-alias first
            tr.filter("lowpass", freq=0.8 * 0.5 / dt, corners=8, zerophase=True)
        tr.interpolate(sampling_rate=1.0 / dt, method="lanczos", a=a, window="lanczos")
    else:
        tr.resample(sampling_rate=1.0 / dt, window=window)
    tr.stats.delta = dt  # exact value (ObsPy stores the sampling rate)
    _record(
        tr, "resample", {"dt": dt, "method": method}, f"dt {old:g} s -> {dt:g} s, {tr.stats.npts} samples", n0
    )
    return tr


# ----------------------------------------------------------------------------- QA checks


def check_pga(tr: Trace, min_g: float = 0.001, max_g: float = 5.0) -> Trace:
    """Fail the record when its PGA is outside a plausible range.

    Parameters
    ----------
    tr : obspy.Trace
        Acceleration [m/s^2]; not changed.
    min_g, max_g : float
        Plausible PGA range [g]. A PGA outside it usually means wrong units
        (cm/s^2 read as m/s^2 or as g) or a record of noise.
    """
    pga_g = float(np.max(np.abs(tr.data))) / G if tr.stats.npts else 0.0
    ok = min_g <= pga_g <= max_g and math.isfinite(pga_g)
    if not ok:
        fail(
            tr,
            "check_pga",
            f"PGA {pga_g:.4g} g is outside the plausible range [{min_g:g}, {max_g:g}] g (wrong units?)",
        )
    _record(
        tr, "check_pga", {"min_g": min_g, "max_g": max_g}, f"PGA {pga_g:.4g} g {'passed' if ok else 'FAILED'}"
    )
    return tr


def check_tail(
    tr: Trace, duration: float = 5.0, max_vel_ratio: float = 0.3, max_dis_ratio: float = 0.9
) -> Trace:
    """Fail the record when velocity or displacement stay large at its end (gmprocess ``check_tail``).

    Parameters
    ----------
    tr : obspy.Trace
        Acceleration [m/s^2]; not changed.
    duration : float
        Length of the tail [s].
    max_vel_ratio : float
        Largest allowed ratio of the peak velocity in the tail to the PGV [-].
    max_dis_ratio : float
        Largest allowed ratio of the peak displacement in the tail to the PGD [-].
    """
    v = velocity(tr)
    d = displacement(tr)
    ntail = max(1, min(tr.stats.npts, int(round(duration / tr.stats.delta)) + 1))
    pgv = float(np.max(np.abs(v)))
    pgd = float(np.max(np.abs(d)))
    vr = float(np.max(np.abs(v[-ntail:]))) / pgv if pgv > 0 else 0.0
    dr = float(np.max(np.abs(d[-ntail:]))) / pgd if pgd > 0 else 0.0
    reasons = []
    if vr > max_vel_ratio:
        reasons.append(f"velocity in the last {duration:g} s reaches {vr:.3g} of PGV (> {max_vel_ratio:g})")
    if dr > max_dis_ratio:
        reasons.append(
            f"displacement in the last {duration:g} s reaches {dr:.3g} of PGD (> {max_dis_ratio:g})"
        )
    for r in reasons:
        fail(tr, "check_tail", r)
    _record(
        tr,
        "check_tail",
        {"duration": duration, "max_vel_ratio": max_vel_ratio, "max_dis_ratio": max_dis_ratio},
        f"tail ratios velocity {vr:.3g}, displacement {dr:.3g} {'FAILED' if reasons else 'passed'}",
    )
    return tr


STEPS: dict[str, StepFunction] = {
    "detrend": detrend,
    "taper": taper,
    "bandpass_filter": bandpass_filter,
    "baseline_polynomial": baseline_polynomial,
    "resample": resample,
    "check_pga": check_pga,
    "check_tail": check_tail,
}
"""Processing steps by the names used in the YAML configuration."""
