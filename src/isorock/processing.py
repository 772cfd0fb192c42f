"""Record processing as a list of named steps (the USGS gmprocess pattern).

A processing configuration is a YAML list of steps, each a step name with keyword
parameters::

    processing:
      - detrend: {type: linear}
      - taper: {type: hann, max_percentage: 0.05}
      - bandpass_filter: {freqmin: 0.05, freqmax: 40.0, corners: 4}
      - check_tail: {duration: 5.0}

Every step is a plain function ``step(trace, **params) -> trace`` on an ObsPy
:class:`~obspy.core.trace.Trace` holding ground acceleration in m/s^2. A step works
in place, returns the trace, and appends one line describing what it did to the
trace's processing history ``trace.stats.processing`` (ObsPy's own history lines
of the methods it calls are folded into that one line).

QA steps (``check_*``) never raise on a bad record: they mark it failed with a
reason (:func:`fail`), as gmprocess does; :func:`qa_passed` and :func:`qa_reasons`
read the marks. Processing goes on after a failure so that the caller can still
look at the record; it decides what to do with failed records.

The default configuration ``processing.yaml`` ships with the package. Its steps
(order as applied):

1. ``check_pga`` on the input (plausible range 0.001 g to 5 g);
2. ``detrend`` (linear) and ``detrend`` (demean);
3. ``taper``: Hann window on 5 % of the record at each end (at most 2 s);
4. ``bandpass_filter``: acausal (zero-phase, forward and backward) Butterworth,
   4 corners, 0.05 Hz to 40 Hz (the high corner capped at 0.8 of the Nyquist
   frequency), applied to the record padded with zeros of total length
   ``1.5 * corners / freqmin`` (Converse & Brady 1992; Boore 2005), pads removed after;
5. ``baseline_polynomial``: the NGA-West2 / gmprocess baseline correction: a
   polynomial of order 6 without constant and linear terms is fitted by least squares
   to the displacement and its second derivative is removed from the acceleration;
6. ``check_tail`` (gmprocess: velocity and displacement in the last 5 s against
   PGV and PGD) and ``check_pga`` on the result;
7. ``resample``: only when a target ``dt`` is given (ObsPy Lanczos or FFT).

References
----------
Boore, D. M. (2005). On pads and filters: processing strong-motion data. BSSA 95(2), 745-750.
Ancheta, T. D. et al. (2014). NGA-West2 database. Earthquake Spectra 30(3), 989-1005.
Hearne, M. et al. (2019). gmprocess. USGS software release, doi:10.5066/P9ANQXN3.
"""

from __future__ import annotations

import inspect
import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from obspy import Stream, Trace
from obspy.core.util import AttribDict
from scipy.integrate import cumulative_trapezoid

from .errors import IsorockError
from .model import G

__all__ = [
    "STEPS",
    "ProcessingStep",
    "ProcessingConfig",
    "default_config",
    "load_config",
    "process",
    "metrics",
    "velocity",
    "displacement",
    "fail",
    "qa_passed",
    "qa_reasons",
    "detrend",
    "taper",
    "bandpass_filter",
    "baseline_polynomial",
    "resample",
    "check_pga",
    "check_tail",
]

DEFAULT_CONFIG_NAME = "processing.yaml"

StepFunction = Callable[..., Trace]


# ----------------------------------------------------------------------------- history and QA marks


def _version() -> str:
    from . import __version__

    return __version__


def _fmt(value: object) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    return repr(value)


def _record(
    tr: Trace, name: str, params: Mapping[str, object], note: str = "", n_before: int | None = None
) -> None:
    """Append one history line to ``tr.stats.processing``.

    Lines ObsPy added after index ``n_before`` (its own history of the methods a step
    called) are replaced by this line.
    """
    hist = list(tr.stats.get("processing", []))
    if n_before is not None:
        hist = hist[:n_before]
    args = ", ".join(f"{k}={_fmt(v)}" for k, v in params.items())
    line = f"isorock {_version()}: {name}({args})"
    if note:
        line += f": {note}"
    hist.append(line)
    tr.stats.processing = hist


def _n_hist(tr: Trace) -> int:
    return len(tr.stats.get("processing", []))


def _qa(tr: Trace) -> AttribDict:
    if "qa" not in tr.stats or not isinstance(tr.stats.qa, Mapping):
        tr.stats.qa = AttribDict({"passed": True, "reasons": []})
    return tr.stats.qa


def fail(tr: Trace, step: str, reason: str) -> None:
    """Mark a trace as failed by a QA check (it is not removed, nothing is raised).

    Parameters
    ----------
    tr : obspy.Trace
        The record.
    step : str
        Name of the check that failed.
    reason : str
        Why, in words with numbers.
    """
    qa = _qa(tr)
    qa.passed = False
    qa.reasons = [*qa.reasons, f"{step}: {reason}"]


def qa_passed(tr: Trace) -> bool:
    """Whether no QA check has marked ``tr`` failed."""
    qa = tr.stats.get("qa")
    return True if qa is None else bool(qa.get("passed", True))


def qa_reasons(tr: Trace) -> list[str]:
    """Reasons given by the QA checks that failed ``tr`` (empty when it passed)."""
    qa = tr.stats.get("qa")
    return [] if qa is None else list(qa.get("reasons", []))


# ----------------------------------------------------------------------------- integrals


def velocity(tr: Trace) -> np.ndarray:
    """Ground velocity [m/s]: trapezoidal integral of the acceleration [m/s^2], zero at the first sample."""
    return cumulative_trapezoid(np.asarray(tr.data, dtype=float), dx=tr.stats.delta, initial=0.0)


def displacement(tr: Trace) -> np.ndarray:
    """Ground displacement [m]: double trapezoidal integral of the acceleration, zero at the first sample."""
    v = velocity(tr)
    return cumulative_trapezoid(v, dx=tr.stats.delta, initial=0.0)


def _as_float(tr: Trace) -> None:
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
    _as_float(tr)
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
    _as_float(tr)
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


def bandpass_filter(
    tr: Trace,
    freqmin: float | None = 0.05,
    freqmax: float | None = 40.0,
    corners: int = 4,
    zerophase: bool = True,
    pad: bool = True,
    max_nyquist_fraction: float = 0.8,
) -> Trace:
    """Butterworth band-pass (or high-pass / low-pass) filter, acausal by default, with zero pads.

    The record is padded with zeros of total length ``1.5 * corners / freqmin`` seconds
    (half at each end; Boore 2005 for acausal filters), filtered with ObsPy
    (``zerophase=True`` runs the filter forwards and backwards: no phase shift, squared
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
    """
    if freqmin is None and freqmax is None:
        raise IsorockError("bandpass_filter: give freqmin, freqmax or both")
    if freqmin is not None and not freqmin > 0:
        raise IsorockError(f"bandpass_filter: freqmin={freqmin!r} is out of range: valid > 0 Hz")
    if not (isinstance(corners, int) and corners >= 1):
        raise IsorockError(f"bandpass_filter: corners={corners!r} is out of range: valid integer >= 1")
    _as_float(tr)
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
    if freqmin is not None and fmax is not None:
        work.filter("bandpass", freqmin=freqmin, freqmax=fmax, corners=corners, zerophase=zerophase)
        kind = "band-pass"
    elif freqmin is not None:
        work.filter("highpass", freq=freqmin, corners=corners, zerophase=zerophase)
        kind = "high-pass"
    else:
        work.filter("lowpass", freq=fmax, corners=corners, zerophase=zerophase)
        kind = "low-pass"
    tr.data = work.data[npad : npad + tr.stats.npts].copy() if npad else work.data
    _record(
        tr,
        "bandpass_filter",
        {"freqmin": freqmin, "freqmax": fmax, "corners": corners, "zerophase": zerophase, "pad": pad},
        f"{'acausal' if zerophase else 'causal'} Butterworth {kind} (obspy), "
        f"zero pads {npad * tr.stats.delta:.4g} s at each end removed after",
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
    _as_float(tr)
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
    _as_float(tr)
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


# ----------------------------------------------------------------------------- configuration


@dataclass(frozen=True)
class ProcessingStep:
    """One named step with its keyword parameters.

    Parameters
    ----------
    name : str
        A key of :data:`STEPS`.
    params : dict
        Keyword parameters of the step function (units as documented there).
    """

    name: str
    params: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.name not in STEPS:
            raise IsorockError(f"processing step {self.name!r} is unknown: valid {', '.join(STEPS)}")
        if not isinstance(self.params, Mapping):
            raise IsorockError(
                f"processing step {self.name!r}: parameters must be a mapping, got "
                f"{type(self.params).__name__}"
            )
        sig = inspect.signature(STEPS[self.name])
        valid = [p for p in sig.parameters if p != "tr"]
        bad = [k for k in self.params if k not in valid]
        if bad:
            raise IsorockError(
                f"processing step {self.name!r}: unknown parameter(s) {', '.join(bad)}: "
                f"valid {', '.join(valid)}"
            )
        object.__setattr__(self, "params", dict(self.params))

    def __call__(self, tr: Trace) -> Trace:
        return STEPS[self.name](tr, **self.params)


@dataclass(frozen=True)
class ProcessingConfig:
    """An ordered list of processing steps.

    Parameters
    ----------
    steps : tuple of ProcessingStep
        Applied in order.
    """

    steps: tuple[ProcessingStep, ...]

    @classmethod
    def from_obj(cls, obj: object, source: str = "configuration") -> ProcessingConfig:
        """Build from parsed YAML: ``{"processing": [...]}`` or the list itself.

        Each list item is ``{name: {param: value}}`` (or ``{name: null}``, or a bare name).
        """
        if isinstance(obj, ProcessingConfig):
            return obj
        if isinstance(obj, Mapping):
            if "processing" not in obj:
                raise IsorockError(f"{source}: no 'processing' list")
            obj = obj["processing"]
        if not isinstance(obj, Iterable) or isinstance(obj, (str, bytes)):
            raise IsorockError(f"{source}: 'processing' must be a list of steps")
        steps = []
        for i, item in enumerate(obj, start=1):
            if isinstance(item, ProcessingStep):
                steps.append(item)
                continue
            if isinstance(item, str):
                name, params = item, {}
            elif isinstance(item, Mapping) and len(item) == 1:
                ((name, params),) = item.items()
                params = params or {}
            else:
                raise IsorockError(
                    f"{source}: step {i} must be a name or a one-key mapping {{name: {{params}}}}"
                )
            try:
                steps.append(ProcessingStep(str(name), params))
            except IsorockError as exc:
                raise IsorockError(f"{source}: step {i}: {exc}") from None
        return cls(tuple(steps))

    def with_step(self, name: str, **params: Any) -> ProcessingConfig:
        """A copy where the parameters of every step ``name`` are updated (the step is appended if absent)."""
        steps = list(self.steps)
        found = False
        for i, s in enumerate(steps):
            if s.name == name:
                steps[i] = ProcessingStep(name, {**s.params, **params})
                found = True
        if not found:
            steps.append(ProcessingStep(name, params))
        return ProcessingConfig(tuple(steps))

    def to_obj(self) -> dict:
        """The YAML-ready form ``{"processing": [{name: params}, ...]}``."""
        return {"processing": [{s.name: dict(s.params)} for s in self.steps]}


def load_config(path: str | Path) -> ProcessingConfig:
    """Read a processing configuration from a YAML file."""
    path = Path(path)
    try:
        obj = yaml.safe_load(path.read_text())
    except OSError as exc:
        raise IsorockError(f"{path}: cannot read processing configuration: {exc.strerror or exc}") from None
    except yaml.YAMLError as exc:
        raise IsorockError(f"{path}: not valid YAML: {str(exc).splitlines()[0]}") from None
    return ProcessingConfig.from_obj(obj, source=str(path))


def default_config() -> ProcessingConfig:
    """The configuration shipped as ``isorock/processing.yaml``."""
    text = resources.files("isorock").joinpath(DEFAULT_CONFIG_NAME).read_text()
    return ProcessingConfig.from_obj(yaml.safe_load(text), source=DEFAULT_CONFIG_NAME)


def _config(config: object) -> ProcessingConfig:
    if config is None:
        return default_config()
    if isinstance(config, (str, Path)):
        return load_config(config)
    return ProcessingConfig.from_obj(config)


def process(
    record: Trace | Stream, config: ProcessingConfig | Mapping | list | str | Path | None = None
) -> Trace | Stream:
    """Apply the processing steps to a copy of a trace or of every trace of a stream.

    Parameters
    ----------
    record : obspy.Trace or obspy.Stream
        Ground acceleration [m/s^2]; not changed.
    config : ProcessingConfig, mapping, list, path or None
        The steps: a :class:`ProcessingConfig`, parsed YAML (``{"processing": [...]}``
        or the list), a YAML file, or None for the packaged default.

    Returns
    -------
    obspy.Trace or obspy.Stream
        The processed copy (same type as ``record``), with the history in
        ``stats.processing`` and the QA marks in ``stats.qa`` (see :func:`qa_passed`).
    """
    cfg = _config(config)
    if isinstance(record, Stream):
        return Stream([_process_trace(tr, cfg) for tr in record])
    if not isinstance(record, Trace):
        raise IsorockError(f"process needs an obspy Trace or Stream, got {type(record).__name__}")
    return _process_trace(record, cfg)


def _process_trace(tr: Trace, cfg: ProcessingConfig) -> Trace:
    out = tr.copy()
    _as_float(out)
    if out.stats.npts < 2:
        raise IsorockError(
            f"record {out.id or '(unnamed)'} has {out.stats.npts} samples: too short to process"
        )
    if not np.all(np.isfinite(out.data)):
        raise IsorockError(f"record {out.id or '(unnamed)'} has non-finite samples")
    _qa(out)
    for step in cfg.steps:
        step(out)
    return out


# ----------------------------------------------------------------------------- metrics


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
