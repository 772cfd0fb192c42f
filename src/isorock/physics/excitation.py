"""Ground excitations: the paper's three pulses (Eqs. 36-38) and sampled records.

Every excitation gives the ground acceleration ``x_g''(t)`` in m/s^2, is zero for
``t < 0`` and after its end, and knows the instants where ``x_g''`` is not smooth
(the engine restarts its integrator there). Nothing here reads files: records are read by
:func:`isorock.io.read_record` and become a :class:`GroundMotion` there.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from isorock.constants import PULSE_SHAPES, G
from isorock.errors import ParameterError

__all__ = ["Pulse", "GroundMotion", "Excitation"]

_SHAPE_CODE = {shape: code for code, shape in enumerate(PULSE_SHAPES)}


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

    Raises
    ------
    ParameterError
        An unknown shape, or ``td`` or ``amp`` out of range.
    """

    shape: Literal["rect", "halfsine", "fullsine"]
    td: float
    amp: float = 1.0

    def __post_init__(self) -> None:
        if self.shape not in PULSE_SHAPES:
            raise ParameterError(f"shape={self.shape!r} is not a pulse: valid {', '.join(PULSE_SHAPES)}")
        if not (math.isfinite(self.td) and self.td > 0):
            raise ParameterError(f"td={self.td!r} is out of range: valid td > 0 s")
        if not (math.isfinite(self.amp) and self.amp >= 0):
            raise ParameterError(f"amp={self.amp!r} is out of range: valid amp >= 0 g")

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
    meta : dict
        Free-form description (source file, processing).
    vertical : numpy.ndarray, optional
        Vertical ground acceleration at the same instants, positive upwards [m/s^2]; None: horizontal
        input only. It is scaled with the horizontal (:meth:`scaled`, :meth:`with_pga`): a record's
        components keep their ratio.

    Raises
    ------
    ParameterError
        ``dt`` out of range, fewer than two samples, a non-finite sample, or a vertical of another length.
    """

    dt: float
    acc: np.ndarray
    name: str = ""
    meta: dict = field(default_factory=dict, compare=False, repr=False)
    vertical: np.ndarray | None = field(default=None, compare=False, repr=False)

    def __post_init__(self) -> None:
        if not (math.isfinite(self.dt) and self.dt > 0):
            raise ParameterError(f"dt={self.dt!r} is out of range: valid dt > 0 s")
        a = np.ascontiguousarray(self.acc, dtype=float)
        if a.ndim != 1 or a.size < 2:
            raise ParameterError(f"acc must be a 1-D array of at least 2 samples, got shape {a.shape}")
        if not np.all(np.isfinite(a)):
            bad = int(np.flatnonzero(~np.isfinite(a))[0])
            raise ParameterError(f"acc has a non-finite value at sample {bad}")
        object.__setattr__(self, "acc", a)
        if self.vertical is not None:
            v = np.ascontiguousarray(self.vertical, dtype=float)
            if v.shape != a.shape:
                raise ParameterError(
                    f"vertical has {v.size} samples, the horizontal {a.size}: give them on the same instants"
                )
            if not np.all(np.isfinite(v)):
                bad = int(np.flatnonzero(~np.isfinite(v))[0])
                raise ParameterError(f"vertical has a non-finite value at sample {bad}")
            object.__setattr__(self, "vertical", v)

    @property
    def vertical_pga_g(self) -> float | None:
        """Peak vertical acceleration in g [-]; None without a vertical."""
        if self.vertical is None:
            return None
        return float(np.max(np.abs(self.vertical))) / G

    def horizontal_only(self) -> GroundMotion:
        """The same record without its vertical."""
        return GroundMotion(self.dt, self.acc, self.name, self.meta)

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
        vert = None if self.vertical is None else self.vertical * factor
        return GroundMotion(self.dt, self.acc * factor, self.name, self.meta, vert)

    def with_pga(self, pga_g: float) -> GroundMotion:
        """Record scaled so that its PGA is ``pga_g`` [g]."""
        if self.pga == 0:
            raise ParameterError(f"record {self.name!r} is all zeros: it cannot be scaled to a PGA")
        return self.scaled(pga_g / self.pga_g)

    def acc_at(self, t: np.ndarray | float) -> np.ndarray:
        """Ground acceleration at ``t`` [m/s^2]: linear interpolation, zero outside the record."""
        t = np.asarray(t, dtype=float)
        times = np.arange(self.npts) * self.dt
        out = np.interp(t, times, self.acc)
        return np.where((t < 0) | (t > self.duration), 0.0, out)

    def describe(self) -> str:
        name = self.name or "(unnamed)"
        text = f"record {name}: {self.npts} samples, dt={self.dt:g} s, PGA={self.pga_g:.4g} g"
        if self.vertical is not None:
            text += f", vertical peak {self.vertical_pga_g:.4g} g"
        return text


Excitation = Pulse | GroundMotion
