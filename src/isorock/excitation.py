"""Ground excitations: the paper's three pulses (Eqs. 36-38) and sampled records.

Every excitation gives the ground acceleration ``x_g''(t)`` in m/s^2, is zero for
``t < 0`` and after its end, and knows the instants where ``x_g''`` is not smooth
(the engine restarts its integrator there).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal

import numpy as np

from .errors import RecordError
from .model import G

__all__ = ["Pulse", "GroundMotion", "Excitation", "PULSE_SHAPES", "load_plain_record"]

PULSE_SHAPES = ("rect", "halfsine", "fullsine")
_SHAPE_CODE = {"rect": 0, "halfsine": 1, "fullsine": 2}


@dataclass(frozen=True)
class Pulse:
    """Acceleration pulse of the paper (Eqs. 36-38).

    Parameters
    ----------
    shape : {"rect", "halfsine", "fullsine"}
        Rectangular half-cycle, half-sine or full-sine (one full cycle) pulse.
    td : float
        Half-cycle duration [s]; ``omega_p = pi / td``. A full-sine pulse lasts ``2 td``.
    amp : float
        Amplitude ``A_g0`` in units of g [-].
    """

    shape: Literal["rect", "halfsine", "fullsine"]
    td: float
    amp: float = 1.0

    def __post_init__(self) -> None:
        if self.shape not in PULSE_SHAPES:
            raise ValueError(f"shape={self.shape!r} is not a pulse: valid {', '.join(PULSE_SHAPES)}")
        if not (math.isfinite(self.td) and self.td > 0):
            raise ValueError(f"td={self.td!r} is out of range: valid td > 0 s")
        if not (math.isfinite(self.amp) and self.amp >= 0):
            raise ValueError(f"amp={self.amp!r} is out of range: valid amp >= 0 g")

    @property
    def code(self) -> int:
        """Integer code of the shape used by the compiled engine (0 rect, 1 half-sine, 2 full-sine)."""
        return _SHAPE_CODE[self.shape]

    @property
    def duration(self) -> float:
        """Time after which the ground acceleration is zero [s]."""
        return 2.0 * self.td if self.shape == "fullsine" else self.td

    @property
    def omega_p(self) -> float:
        """Pulse circular frequency ``pi / td`` [rad/s]."""
        return math.pi / self.td

    @property
    def pga_g(self) -> float:
        """Peak ground acceleration in g [-] (equal to ``amp``)."""
        return self.amp

    def with_pga(self, pga_g: float) -> Pulse:
        """The same pulse with amplitude ``pga_g`` [g]."""
        return Pulse(self.shape, self.td, pga_g)

    def acc(self, t: np.ndarray | float) -> np.ndarray:
        """Ground acceleration ``x_g''(t)`` [m/s^2] (right-continuous at ``td``)."""
        t = np.asarray(t, dtype=float)
        a0 = self.amp * G
        inside = (t >= 0) & (t < self.duration)
        if self.shape == "rect":
            val = np.full_like(t, a0)
        else:
            val = a0 * np.sin(math.pi * t / self.td)
        return np.where(inside, val, 0.0)

    def describe(self) -> str:
        return f"{self.shape} pulse td={self.td:g} s, A={self.amp:g} g"


@dataclass(frozen=True)
class GroundMotion:
    """Sampled ground acceleration, linear between samples and zero after the last one.

    Parameters
    ----------
    dt : float
        Sampling interval [s].
    acc : numpy.ndarray
        Ground acceleration samples ``a_k`` at ``t_k = k dt`` [m/s^2].
    name : str
        Label of the record (file or catalog id).
    """

    dt: float
    acc: np.ndarray
    name: str = ""
    meta: dict = field(default_factory=dict, compare=False, repr=False)

    def __post_init__(self) -> None:
        if not (math.isfinite(self.dt) and self.dt > 0):
            raise ValueError(f"dt={self.dt!r} is out of range: valid dt > 0 s")
        a = np.ascontiguousarray(self.acc, dtype=float)
        if a.ndim != 1 or a.size < 2:
            raise ValueError(f"acc must be a 1-D array of at least 2 samples, got shape {a.shape}")
        if not np.all(np.isfinite(a)):
            bad = int(np.flatnonzero(~np.isfinite(a))[0])
            raise ValueError(f"acc has a non-finite value at sample {bad}")
        object.__setattr__(self, "acc", a)

    @property
    def npts(self) -> int:
        """Number of samples."""
        return int(self.acc.size)

    @property
    def duration(self) -> float:
        """Time of the last sample [s]; the input is zero afterwards."""
        return (self.npts - 1) * self.dt

    @property
    def pga(self) -> float:
        """Peak ground acceleration [m/s^2]."""
        return float(np.max(np.abs(self.acc)))

    @property
    def pga_g(self) -> float:
        """Peak ground acceleration in g [-]."""
        return self.pga / G

    def scaled(self, factor: float) -> GroundMotion:
        """Record multiplied by ``factor`` [-]."""
        return GroundMotion(self.dt, self.acc * factor, self.name, self.meta)

    def with_pga(self, pga_g: float) -> GroundMotion:
        """Record scaled so that its PGA is ``pga_g`` [g]."""
        if self.pga == 0:
            raise ValueError(f"record {self.name!r} is all zeros: it cannot be scaled to a PGA")
        return self.scaled(pga_g / self.pga_g)

    def acc_at(self, t: np.ndarray | float) -> np.ndarray:
        """Ground acceleration at ``t`` [m/s^2]: linear interpolation, zero outside the record."""
        t = np.asarray(t, dtype=float)
        times = np.arange(self.npts) * self.dt
        out = np.interp(t, times, self.acc)
        return np.where((t < 0) | (t > self.duration), 0.0, out)

    # same name as Pulse.acc for the engine-independent code (oracle, plots)
    def acc_fn(self, t: np.ndarray | float) -> np.ndarray:
        return self.acc_at(t)

    def describe(self) -> str:
        name = self.name or "(unnamed)"
        return f"record {name}: {self.npts} samples, dt={self.dt:g} s, PGA={self.pga_g:.4g} g"


Excitation = Pulse | GroundMotion


def ground_acc(exc: Excitation, t: np.ndarray | float) -> np.ndarray:
    """Ground acceleration of any excitation at ``t`` [m/s^2]."""
    return exc.acc(t) if isinstance(exc, Pulse) else exc.acc_at(t)


_UNIT_FACTORS = {"g": G, "m/s2": 1.0, "cm/s2": 0.01, "gal": 0.01, "mm/s2": 1e-3}


def load_plain_record(path: str | Path, dt: float | None = None, units: str = "g") -> GroundMotion:
    """Read a plain numeric record: one value per line, or time/value pairs.

    Parameters
    ----------
    path : str or Path
        Text file; blank lines and lines starting with ``#`` or ``%`` are ignored.
    dt : float, optional
        Time step [s]; required for one-column files, checked against two-column files.
    units : {"g", "m/s2", "cm/s2"}
        Units of the acceleration values.

    Raises
    ------
    RecordError
        With the file, line number and problem.
    """
    path = Path(path)
    if units not in _UNIT_FACTORS:
        raise RecordError(path, f"unknown units {units!r}: valid {', '.join(_UNIT_FACTORS)}")
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError) as exc:
        raise RecordError(path, f"cannot read file: {exc}") from None
    rows: list[list[float]] = []
    ncol = None
    for lineno, line in enumerate(text.splitlines(), start=1):
        s = line.strip()
        if not s or s[0] in "#%":
            continue
        toks = s.replace(",", " ").split()
        try:
            vals = [float(x) for x in toks]
        except ValueError:
            bad = next(x for x in toks if not _isfloat(x))
            raise RecordError(path, f"non-numeric value {bad!r}", lineno) from None
        if not all(math.isfinite(v) for v in vals):
            raise RecordError(path, "non-finite value (NaN or inf)", lineno)
        if ncol is None:
            ncol = len(vals)
            if ncol not in (1, 2):
                raise RecordError(
                    path, f"{ncol} columns; a plain record has 1 (acc) or 2 (time, acc)", lineno
                )
        elif len(vals) != ncol:
            raise RecordError(path, f"{len(vals)} columns where earlier lines have {ncol}", lineno)
        rows.append(vals)
    if len(rows) < 2:
        raise RecordError(path, "no data (fewer than 2 numeric lines)")
    arr = np.asarray(rows)
    if ncol == 2:
        t = arr[:, 0]
        steps = np.diff(t)
        step = float(np.median(steps))
        if step <= 0 or np.any(np.abs(steps - step) > 1e-3 * step + 1e-9):
            k = int(np.flatnonzero(np.abs(steps - step) > 1e-3 * step + 1e-9)[0]) if step > 0 else 0
            raise RecordError(path, f"time column is not uniformly increasing near data row {k + 2}")
        if dt is not None and abs(dt - step) > 1e-6 * step:
            raise RecordError(path, f"--dt {dt} disagrees with the time column step {step:g} s")
        dt = step
        acc = arr[:, 1]
    else:
        if dt is None:
            raise RecordError(path, "a one-column record needs its time step (dt)")
        acc = arr[:, 0]
    if not (dt > 0):
        raise RecordError(path, f"time step dt={dt} must be > 0 s")
    return GroundMotion(dt=float(dt), acc=acc * _UNIT_FACTORS[units], name=path.name)


def _isfloat(x: str) -> bool:
    try:
        float(x)
    except ValueError:
        return False
    return True
