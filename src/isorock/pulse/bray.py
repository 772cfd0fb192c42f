"""The pulse period of Bray & Rodriguez-Marek (2004): twice the velocity half-cycle holding the PGV."""

from __future__ import annotations

import numpy as np

from isorock.errors import IsorockError

__all__ = ["tp_bray_rodriguez_marek"]


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
