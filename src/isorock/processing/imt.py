"""Intensity measures named the field's way (OpenQuake's strings) and the RotD50 / RotD100 of a pair.

An intensity measure type (IMT) is written as OpenQuake writes it: ``PGA`` [g], ``PGV`` [cm/s] and
``SA(T)`` [g], the 5 %-damped pseudo-spectral acceleration at the period ``T`` [s] (``SA(1.0)``).
:func:`parse_imt` also reads the USGS hazard service's spelling (``SA1P0``, ``SA0P2``) and any case;
``str(parse_imt(s))`` is the one canonical string stored and printed. The units are those of the
hazard models (OpenQuake and the USGS give PGV in cm/s).

The *component definition* says which value of the two horizontal components of a recording the
measure is: the current ground-motion models (NGA-West2), the USGS maps and most OpenQuake GMPEs give
the median over orientations **RotD50**; ASCE/SEI 7-16's MCE_R is the maximum over orientations
**RotD100** (Boore 2010). For each angle ``theta`` in ``[0, 180)`` degrees the two horizontals are
combined into the motion along that direction, ``a1 cos(theta) + a2 sin(theta)`` (their azimuths 90
degrees apart), and the measure's peak is taken; RotD50 is the median of these peaks over the angles
and RotD100 their maximum. Every measure here is the peak of a linear functional of the acceleration,
so the oscillator's response to the rotated motion is the rotated combination of the two responses:
each component's response is computed once (:mod:`isorock.processing.intensity`'s exact recurrence)
and only the peaks are taken per angle. :data:`ANGLE_STEP_DEG` is 1 degree, as Boore (2010) uses.

``analysed`` is not a component definition of a hazard model: it is the measure of the one
component the engine analyses, which the assessment uses when asked to (``assessment.component:
analysed``) and states.

References
----------
Boore, D. M. (2010). Orientation-independent, nongeometric-mean measures of seismic intensity from
two horizontal components of motion. BSSA 100(4), 1830-1835.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from isorock.constants import G
from isorock.errors import ParameterError
from isorock.physics.excitation import GroundMotion

__all__ = [
    "IMT",
    "parse_imt",
    "COMPONENT_DEFINITIONS",
    "component_definition",
    "ANGLE_STEP_DEG",
    "imt_value",
    "rotd",
    "rotd_of_traces",
    "INFO_MEASURES",
]

#: the component definitions a hazard curve or the assessment may name (canonical spelling)
COMPONENT_DEFINITIONS: tuple[str, ...] = ("RotD50", "RotD100", "analysed")
#: the measures whose RotD ``isorock info`` shows
INFO_MEASURES: tuple[str, ...] = ("PGA", "PGV", "SA(0.2)", "SA(1.0)", "SA(3.0)")
#: the step of the orientations of RotD [deg] (Boore 2010)
ANGLE_STEP_DEG = 1.0

_SA = re.compile(r"^SA\(\s*([0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*\)$", re.IGNORECASE)
_SA_USGS = re.compile(r"^SA([0-9]+)P([0-9]+)$", re.IGNORECASE)


@dataclass(frozen=True)
class IMT:
    """An intensity measure type.

    Parameters
    ----------
    name : {"PGA", "PGV", "SA"}
        The measure.
    period_s : float or None
        The oscillator period of ``SA`` [s] (None for the others).
    """

    name: str
    period_s: float | None = None

    def __str__(self) -> str:
        return f"SA({float(self.period_s)!r})" if self.name == "SA" else self.name

    @property
    def unit(self) -> str:
        """``g`` for PGA and SA, ``cm/s`` for PGV (as OpenQuake and the USGS give them)."""
        return "cm/s" if self.name == "PGV" else "g"

    def describe(self) -> str:
        """In words: 'PGA', 'PGV', 'SA(1.0), 5 %-damped'."""
        return f"{self}, 5 %-damped" if self.name == "SA" else str(self)


def parse_imt(text: object, where: str = "imt") -> IMT:
    """An intensity measure type from its string (``PGA``, ``PGV``, ``SA(1.0)``, ``SA1P0``; any case).

    Raises
    ------
    ParameterError
        Not one of these, or a period not positive; ``where`` names the key in the message.
    """
    s = str(text).strip()
    up = s.upper()
    if up in ("PGA", "PGV"):
        return IMT(up)
    m = _SA.match(s)
    if m is None:
        u = _SA_USGS.match(s)
        period = float(f"{u.group(1)}.{u.group(2)}") if u else None
    else:
        period = float(m.group(1))
    if period is None:
        raise ParameterError(
            f"{where}: {s!r} is not an intensity measure: valid PGA, PGV, SA(T) with T the period in s "
            "(OpenQuake's strings, e.g. SA(1.0))"
        )
    if not (math.isfinite(period) and period > 0.0):
        raise ParameterError(f"{where}: {s!r}: the period of SA must be positive")
    return IMT("SA", period)


def component_definition(text: object, where: str = "component_definition") -> str:
    """The canonical spelling of a component definition (:data:`COMPONENT_DEFINITIONS`, any case).

    Raises
    ------
    ParameterError
        Another definition (a geometric mean, a larger component): named, with the valid ones.
    """
    s = str(text).strip()
    for d in COMPONENT_DEFINITIONS:
        if s.lower() == d.lower():
            return d
    raise ParameterError(
        f"{where}: {s!r} is not a component definition isorock computes: valid "
        f"{', '.join(COMPONENT_DEFINITIONS)} (the median and the maximum over orientations of the two "
        "horizontals, or the component analysed)"
    )


def imt_value(gm: GroundMotion, imt: IMT) -> float:
    """The measure of one component as it is, in :attr:`IMT.unit` (PGV in cm/s)."""
    from isorock.processing.intensity import intensity

    if imt.name == "PGA":
        return gm.pga_g
    if imt.name == "PGV":
        return 100.0 * intensity(gm, "pgv")
    return intensity(gm, "sa", period_s=imt.period_s)


def _responses(gm: GroundMotion, imt: IMT) -> tuple[np.ndarray, float, tuple[float, float, float] | None]:
    """The series whose peak is the measure, its factor to the measure's unit, and for SA the
    oscillator's end state and constants (free vibration after the record)."""
    from obspy import Trace

    from isorock.processing.intensity import DEFAULT_DAMPING, displacement_history
    from isorock.processing.metrics import velocity

    if imt.name == "PGA":
        return gm.acc, 1.0 / G, None
    if imt.name == "PGV":
        return np.asarray(velocity(Trace(gm.acc, header={"delta": gm.dt}))), 100.0, None
    assert imt.period_s is not None
    u, v_end = displacement_history(gm, imt.period_s, DEFAULT_DAMPING)
    omega = 2.0 * math.pi / imt.period_s
    return u, omega**2 / G, (v_end, omega, DEFAULT_DAMPING)


def rotd(h1: GroundMotion, h2: GroundMotion, imts: list[IMT]) -> dict[str, dict[str, float]]:
    """RotD50 and RotD100 of two orthogonal horizontal components for several measures.

    Parameters
    ----------
    h1, h2 : GroundMotion
        The two processed horizontals of one recording [m/s^2], azimuths 90 degrees apart, on the same
        step (the longer is cut to the shorter's length).
    imts : list of IMT
        The measures (a period of SA must lie in ``[2 dt, duration]``).

    Returns
    -------
    dict
        ``{"rotd50": {str(imt): value}, "rotd100": {str(imt): value}}`` in each measure's unit.

    Raises
    ------
    ParameterError
        Different steps, or a period out of range.
    """
    from isorock.processing.intensity import _free_vibration_peak

    if not math.isclose(h1.dt, h2.dt, rel_tol=1e-9):
        raise ParameterError(f"rotd: the two horizontals have different steps ({h1.dt:g} s, {h2.dt:g} s)")
    n = min(h1.acc.size, h2.acc.size)
    g1 = GroundMotion(dt=h1.dt, acc=h1.acc[:n], name=h1.name)
    g2 = GroundMotion(dt=h1.dt, acc=h2.acc[:n], name=h2.name)
    theta = np.deg2rad(np.arange(0.0, 180.0, ANGLE_STEP_DEG))
    c, s = np.cos(theta), np.sin(theta)
    out: dict[str, dict[str, float]] = {"rotd50": {}, "rotd100": {}}
    for imt in imts:
        x1, f, end1 = _responses(g1, imt)
        x2, _, end2 = _responses(g2, imt)
        peaks = np.zeros(theta.size)
        chunk = max(1, 4_000_000 // max(x1.size, 1))
        for k in range(0, theta.size, chunk):
            sl = slice(k, k + chunk)
            peaks[sl] = np.max(np.abs(np.outer(c[sl], x1) + np.outer(s[sl], x2)), axis=1)
        if end1 is not None and end2 is not None:  # SA: the free vibration after the record
            (v1, omega, xi), (v2, _, _) = end1, end2
            u1, u2 = float(x1[-1]), float(x2[-1])
            for k in range(theta.size):
                free = _free_vibration_peak(c[k] * u1 + s[k] * u2, c[k] * v1 + s[k] * v2, omega, xi)
                peaks[k] = max(peaks[k], free)
        peaks *= f
        out["rotd50"][str(imt)] = float(np.median(peaks))
        out["rotd100"][str(imt)] = float(np.max(peaks))
    return out


def rotd_of_traces(
    pair: tuple[Any, Any], imts: Sequence[str]
) -> tuple[dict[str, dict[str, float]], list[str]]:
    """RotD50 and RotD100 of two processed horizontal traces (ObsPy, m/s^2) for the measures ``imts``
    (strings); a measure a record cannot support (a period beyond its duration) is left out with a line.

    Returns
    -------
    values : dict
        ``{"rotd50": {imt: value}, "rotd100": {imt: value}}``.
    lines : list of str
        What was left out, and why.
    """
    t1, t2 = pair
    g1 = GroundMotion(dt=float(t1.stats.delta), acc=np.asarray(t1.data, dtype=float), name="h1")
    g2 = GroundMotion(dt=float(t2.stats.delta), acc=np.asarray(t2.data, dtype=float), name="h2")
    vals: dict[str, dict[str, float]] = {"rotd50": {}, "rotd100": {}}
    lines = []
    for s in imts:
        try:
            v = rotd(g1, g2, [parse_imt(s)])
        except ParameterError as exc:
            lines.append(f"no RotD of {s}: {exc}")
            continue
        for k in vals:
            vals[k].update(v[k])
    return vals, lines
