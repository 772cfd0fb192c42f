"""Orientation of horizontal components: strike-normal / strike-parallel azimuths and rotation."""

from __future__ import annotations

import math
import warnings

import numpy as np
from obspy import Trace

from isorock.errors import IsorockError

__all__ = ["fault_azimuth", "rotate_horizontal"]


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
    ``N cos(az) + E sin(az)``: ``N`` and ``E`` are solved from the two given components as ObsPy's
    :func:`obspy.signal.rotate.rotate2zne` solves them (:func:`_rotate2zne`), then projected (in closed form,
    ``c = [c1 sin(az2 - azimuth) + c2 sin(azimuth - az1)] / sin(az2 - az1)``; for orthogonal
    components, the usual rotation). The components need not be orthogonal, but not closer than
    10 deg to parallel.

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
    # north and east from the two horizontals (ObsPy's rotate2zne, a zero vertical as the third
    # component), then the projection on the wanted azimuth
    _, north, east = _rotate2zne(x1[:n], az1, 0.0, x2[:n], az2, 0.0, np.zeros(n), 0.0, -90.0)
    a = math.radians(azimuth)
    out = north * math.cos(a) + east * math.sin(a)
    if not traces:
        return out
    tr = c1.copy()
    tr.data = out
    az = azimuth % 360.0
    tr.stats.channel = f"{round(az) % 360:03d}"  # a SEED channel code has 3 characters
    if "isorock" in tr.stats:
        tr.stats.isorock.component = f"{az:05.1f}"
    hist = list(tr.stats.get("processing", []))
    hist.append(f"isorock: rotate_horizontal({az1:g}, {az2:g} -> {azimuth % 360.0:g} deg)")
    tr.stats.processing = hist
    return tr


def _zne_base_vector(dip: float, azimuth: float) -> np.ndarray:
    """Unit vector of a component of ``dip`` and ``azimuth`` [deg] in the (Z, N, E) base (SEED
    conventions; ObsPy's ``_dip_azimuth2zne_base_vector``)."""
    dip_r = np.deg2rad(dip)
    az_r = np.deg2rad(azimuth)
    return np.array([-np.sin(dip_r), np.cos(az_r) * np.cos(dip_r), np.sin(az_r) * np.cos(dip_r)])


def _rotate2zne(
    data_1: np.ndarray,
    azimuth_1: float,
    dip_1: float,
    data_2: np.ndarray,
    azimuth_2: float,
    dip_2: float,
    data_3: np.ndarray,
    azimuth_3: float,
    dip_3: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Z, N and E from three components of given azimuths and dips [deg]: the computation of ObsPy's
    :func:`obspy.signal.rotate.rotate2zne` (the same numpy operations, so the same samples bit for
    bit), here because importing :mod:`obspy.signal` loads matplotlib (about 0.5 s)."""
    if len({len(d) for d in (data_1, data_2, data_3)}) != 1:
        raise ValueError("All three data arrays must be of same length.")
    # the base vectors of the old base in terms of the new one, and the base change
    m = np.array(
        [
            _zne_base_vector(dip_1, azimuth_1),
            _zne_base_vector(dip_2, azimuth_2),
            _zne_base_vector(dip_3, azimuth_3),
        ]
    )
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", ".*invalid value encountered in det.*")
        det = np.linalg.det(m)
    if not (1e-6 < abs(det) < 1e6):
        raise ValueError(
            "The given directions are not linearly independent, at least within numerical precision. "
            f"Determinant of the base change matrix: {det:g}"
        )
    z, n, e = np.dot(np.linalg.inv(m), [data_1, data_2, data_3])
    out = []
    for c in (z, n, e):
        c = np.array(c).ravel()
        c[c == -0.0] = 0  # no negative zeros (ObsPy's rule)
        out.append(c)
    return out[0], out[1], out[2]
