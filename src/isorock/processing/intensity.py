"""Intensity measures of a ground motion for the assessment's stripes: PGA, PGV and Sa(T).

The assessment scales every record to stripes of one intensity measure (:data:`MEASURES`):

* ``pga``: peak ground acceleration [g], ``max |a(t)| / G``;
* ``pgv``: peak ground velocity [m/s], the peak of the trapezoidal integral of the acceleration from
  rest at the first sample (:func:`isorock.processing.metrics.velocity`, as in the records' metrics);
* ``sa``: 5 %-damped pseudo-spectral acceleration at a period ``T`` [g] (for an isolated base, the
  isolation period), ``Sa = omega_n^2 max |u(t)| / G`` with ``u`` the relative displacement of the
  linear oscillator ``u'' + 2 xi omega_n u' + omega_n^2 u = -a(t)``, ``omega_n = 2 pi / T``.

Every measure is computed for the record as it is (normally processed, :func:`isorock.processing.process`).

Linearity in the scale factor
-----------------------------
Each measure is the peak of the absolute value of a linear functional of the acceleration (the
acceleration itself, its integral, the response of a linear oscillator from rest), hence positively
homogeneous of degree one: ``IM(gm.scaled(c)) == |c| IM(gm)`` for every factor ``c`` (to round-off).
The assessment therefore computes the measure once per record and scales the record to the level
``x`` of a stripe with the factor ``x / IM(gm)``.

Method of Sa (why not pyrotd)
-----------------------------
Sa is computed here with the piecewise-exact recurrence of Nigam & Jennings (1969): the ground
acceleration of a :class:`~isorock.physics.excitation.GroundMotion` is linear between its samples (the
definition the engine integrates), and over one step ``h`` the oscillator state ``x = (u, u')`` then
obeys exactly ``x[k+1] = Phi x[k] + Gamma0 a[k] + Gamma1 a[k+1]``. The coefficients are the blocks of
the matrix exponential of the augmented system (Van Loan 1978), which keeps them accurate when
``omega_n h << 1``, where the closed-form coefficients (Chopra 2012, Sec. 5.2) lose digits by
cancellation. The recurrence runs as a second-order recursive filter (the arithmetic of
:func:`scipy.signal.lfilter`, compiled with the engine: :func:`isorock.physics.engine.recursive_filter`)
from rest: ``u = u' = 0`` at the first sample. The step is the record's ``dt``, subdivided (exactly:
the input is linear between samples) so that a period holds at least :data:`POINTS_PER_PERIOD` steps:
the peak taken at the steps then underestimates the continuous one by at most about
``1 - cos(pi / POINTS_PER_PERIOD)`` = 8e-5. After the last sample the ground is at rest (as
:class:`~isorock.physics.excitation.GroundMotion` defines it) and the free vibration is part of the response:
its largest value (the first extremum after the end) is added in closed form.

The library pyrotd (Kottke; ``calc_spec_accels``) was considered and is not used at run time:
its latest release (0.6.1) imports ``pkg_resources``, which setuptools removed in version 82, so
``import pyrotd`` fails in a fresh environment; it computes the response by one FFT of the record
without padding (a circular response: the oscillator does not start at rest and the free vibration
after the end wraps onto the start), builds its frequency grid with ``linspace`` (wrong for an odd
number of samples), starts a process pool per call when more than two cores are seen, and treats the
samples as band-limited rather than linear between samples. The tests compare this module with
pyrotd (zero-padded record) where it imports, with :func:`scipy.signal.lsim` and with closed forms.

Limits of the period
--------------------
``2 dt <= T <= duration`` (:class:`~isorock.errors.ParameterError` otherwise). Below the Nyquist
period ``2 dt`` the record holds no motion at the oscillator frequency (Sa tends to PGA as ``T`` goes
to 0: use ``pga``). Above the record's duration the oscillator does not complete one cycle within the
record and Sa measures the record's long-period content, which the processing's high-pass filter has
removed. Between ``2 dt`` and about ``20 dt`` the value depends on what is assumed between the samples
(linear here, band-limited in an FFT method) by up to about ``(pi dt / T)^2 / 3`` (3 % at ``T = 10 dt``).

References
----------
Nigam, N. C. & Jennings, P. C. (1969). Calculation of response spectra from strong-motion earthquake
records. BSSA 59(2), 909-922.
Van Loan, C. F. (1978). Computing integrals involving the matrix exponential. IEEE Trans. Automatic
Control 23(3), 395-404.
Chopra, A. K. (2012). Dynamics of Structures, 4th ed. Prentice Hall. Sec. 5.2.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TypedDict

import numpy as np
from obspy import Trace

from isorock.constants import G
from isorock.errors import ParameterError
from isorock.physics.excitation import GroundMotion
from isorock.processing.metrics import velocity

__all__ = [
    "MEASURES",
    "MEASURE_UNITS",
    "MEASURE_DESCRIPTIONS",
    "POINTS_PER_PERIOD",
    "Intensities",
    "intensity",
    "intensities",
    "pseudo_spectral_acceleration",
]

MEASURES: tuple[str, ...] = ("pga", "pgv", "sa")
"""The intensity measures a stripe can be set on."""

MEASURE_UNITS: dict[str, str] = {"pga": "g", "pgv": "m/s", "sa": "g"}
"""Unit of each measure."""

MEASURE_DESCRIPTIONS: dict[str, str] = {
    "pga": "peak ground acceleration",
    "pgv": "peak ground velocity (trapezoidal integral of the acceleration from rest)",
    "sa": "pseudo-spectral acceleration omega_n^2 max|u| of a damped linear oscillator at period T",
}
"""Short description of each measure."""

POINTS_PER_PERIOD = 256
"""Least number of integration steps per oscillator period [-] (the record's step is subdivided)."""

DEFAULT_DAMPING = 0.05
"""Damping ratio of the oscillator of Sa [-]."""


class Intensities(TypedDict):
    """All the measures of one record (:func:`intensities`)."""

    pga_g: float
    """Peak ground acceleration [g]."""
    pgv_m_s: float
    """Peak ground velocity [m/s]."""
    sa_g: dict[float, float]
    """Pseudo-spectral acceleration [g] at each period [s] asked for (keys: the periods)."""


def _as_float(name: str, value: object) -> float:
    try:
        return float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ParameterError(f"{name}={value!r} is not a number") from None


def _check_damping(damping: float) -> float:
    xi = _as_float("damping", damping)
    if not (math.isfinite(xi) and 0.0 <= xi < 1.0):
        raise ParameterError(f"damping={damping!r} is out of range: valid 0 <= damping < 1")
    return xi


def _check_period(gm: GroundMotion, period_s: float | None) -> float:
    if period_s is None:
        raise ParameterError("period_s is missing: measure 'sa' needs the oscillator period [s]")
    T = _as_float("period_s", period_s)
    lo, hi = 2.0 * gm.dt, gm.duration
    if not math.isfinite(T) or T < lo * (1.0 - 1e-12):
        raise ParameterError(
            f"period_s={period_s!r} is out of range: below the Nyquist period 2 dt = {lo:g} s of record "
            f"{gm.name!r} the record holds no motion at the oscillator frequency "
            "(Sa tends to PGA: use 'pga'); "
            f"valid {lo:g} s <= period_s <= {hi:g} s"
        )
    if T > hi * (1.0 + 1e-12):
        raise ParameterError(
            f"period_s={period_s!r} is out of range: longer than the duration {hi:g} s of record {gm.name!r} "
            f"(the oscillator would not complete one cycle); valid {lo:g} s <= period_s <= {hi:g} s"
        )
    return T


def _step_matrices(omega: float, xi: float, h: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Exact one-step matrices of the oscillator for an input linear over the step.

    Parameters
    ----------
    omega : float
        Natural circular frequency [rad/s].
    xi : float
        Damping ratio [-].
    h : float
        Step [s].

    Returns
    -------
    phi : numpy.ndarray
        2x2 state transition ``expm(F h)`` of ``x = (u [m], u' [m/s])``.
    gamma0, gamma1 : numpy.ndarray
        Responses of the state to the ground acceleration [m/s^2] at the start and at the end of the
        step: ``x[k+1] = phi x[k] + gamma0 a[k] + gamma1 a[k+1]``.
    """
    from scipy.linalg import expm  # scipy on first use: ``import isorock.processing`` stays light

    # augmented state (u, u', a, a') with a' constant over the step (first-order hold, Van Loan 1978)
    m = np.zeros((4, 4))
    m[0, 1] = 1.0
    m[1, 0] = -(omega**2)
    m[1, 1] = -2.0 * xi * omega
    m[1, 2] = -1.0  # the load is -a
    m[2, 3] = 1.0
    e = expm(m * h)
    phi = e[:2, :2]
    gamma1 = e[:2, 3] / h
    gamma0 = e[:2, 2] - gamma1
    return phi, gamma0, gamma1


def _free_vibration_peak(u0: float, v0: float, omega: float, xi: float) -> float:
    """Largest ``|u|`` [m] of the free vibration from ``u(0) = u0`` [m], ``u'(0) = v0`` [m/s], ``t >= 0``.

    ``u(t) = R exp(-xi omega t) cos(omega_d t - theta)``; the extrema are where
    ``omega_d t - theta = -asin(xi) + k pi`` and decrease in size, so the answer is the larger of
    ``|u0|`` and the first extremum at ``t >= 0``, ``R exp(-xi omega t) sqrt(1 - xi^2)``.
    """
    sigma = xi * omega
    wd = omega * math.sqrt(1.0 - xi * xi)
    s = (v0 + sigma * u0) / wd
    r = math.hypot(u0, s)
    if r == 0.0:
        return 0.0
    theta = math.atan2(s, u0)
    beta = math.asin(xi)
    k = math.ceil((beta - theta) / math.pi)
    t = (k * math.pi - beta + theta) / wd
    return max(abs(u0), r * math.exp(-sigma * max(t, 0.0)) * math.sqrt(1.0 - xi * xi))


def _initial_state(
    b: np.ndarray, a: np.ndarray, y: tuple[float, float], x: tuple[float, float]
) -> np.ndarray:
    """The filter's delays after the outputs ``y`` and inputs ``x`` (latest first): the arithmetic of
    :func:`scipy.signal.lfiltic` for three coefficients (the same sums in the same order)."""
    yy, xx = np.asarray(y, dtype=float), np.asarray(x, dtype=float)
    zi = np.zeros(2)
    for m in range(2):
        zi[m] = np.sum(b[m + 1 :] * xx[: 2 - m], axis=0)
    for m in range(2):
        zi[m] -= np.sum(a[m + 1 :] * yy[: 2 - m], axis=0)
    return zi


def _recurrence(
    gm: GroundMotion, period_s: float, xi: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The input on the subdivided step and the recurrence's coefficients: ``(a, phi, g0, g1, num,
    den)``, ``num`` and ``den`` those of the second-order recursive filter
    ``u[k] + den1 u[k-1] + den2 u[k-2] = num . a[k..k-2]``."""
    acc, dt = gm.acc, gm.dt
    sub = max(1, math.ceil(POINTS_PER_PERIOD * dt / period_s))
    if sub > 1:  # exact: the ground acceleration is linear between the samples
        frac = np.arange(sub) / sub
        a = np.empty((acc.size - 1) * sub + 1)
        a[:-1] = (acc[:-1, None] + np.diff(acc)[:, None] * frac[None, :]).ravel()
        a[-1] = acc[-1]
    else:
        a = acc
    phi, g0, g1 = _step_matrices(2.0 * math.pi / period_s, xi, dt / sub)
    den = np.array([1.0, -(phi[0, 0] + phi[1, 1]), phi[0, 0] * phi[1, 1] - phi[0, 1] * phi[1, 0]])
    num = np.array(
        [
            g1[0],
            g0[0] - phi[1, 1] * g1[0] + phi[0, 1] * g1[1],
            -phi[1, 1] * g0[0] + phi[0, 1] * g0[1],
        ]
    )
    return a, phi, g0, g1, num, den


def displacement_history(gm: GroundMotion, period_s: float, xi: float) -> tuple[np.ndarray, float]:
    """Relative displacement ``u`` [m] of the oscillator from rest under the record, on the record's
    step subdivided (module docstring), and its velocity at the last sample [m/s].

    The period must lie in ``[2 dt, duration]`` (:func:`pseudo_spectral_acceleration` checks it)."""
    # the filter compiled with the engine: scipy.signal's arithmetic without its import (about 0.5 s)
    from isorock.physics.engine import recursive_filter

    a, phi, g0, g1, num, den = _recurrence(gm, period_s, xi)
    u = np.empty(a.size)
    u[0] = 0.0  # at rest at the first sample
    u[1] = g0[0] * a[0] + g1[0] * a[1]
    if a.size > 2:
        u[2:] = recursive_filter(num, den, a[2:], _initial_state(num, den, (u[1], u[0]), (a[1], a[0])))
    # velocity at the last sample from the last two displacements (first row of the recurrence)
    v_prev = (u[-1] - phi[0, 0] * u[-2] - g0[0] * a[-2] - g1[0] * a[-1]) / phi[0, 1]
    v_end = phi[1, 0] * u[-2] + phi[1, 1] * v_prev + g0[1] * a[-2] + g1[1] * a[-1]
    return u, float(v_end)


def _peak_displacement(gm: GroundMotion, period_s: float, xi: float) -> float:
    """Peak relative displacement [m] from rest under the record, free vibration after it included."""
    u, v_end = displacement_history(gm, period_s, xi)
    omega = 2.0 * math.pi / period_s
    return max(float(np.max(np.abs(u))), _free_vibration_peak(float(u[-1]), v_end, omega, xi))


def pseudo_spectral_acceleration(
    gm: GroundMotion, periods_s: Sequence[float] | np.ndarray, damping: float = DEFAULT_DAMPING
) -> np.ndarray:
    """Pseudo-spectral acceleration of a ground motion at several periods.

    Parameters
    ----------
    gm : GroundMotion
        Ground acceleration [m/s^2], linear between samples, zero after the last.
    periods_s : sequence of float
        Oscillator periods ``T`` [s], each in ``[2 dt, duration]``.
    damping : float, optional
        Damping ratio ``xi`` of the oscillator [-], ``0 <= xi < 1`` (default 0.05).

    Returns
    -------
    numpy.ndarray
        ``Sa(T) = (2 pi / T)^2 max |u(t)| / G`` [g] per period, the oscillator at rest at the first sample
        and its free vibration after the last included.

    Raises
    ------
    ParameterError
        A period or the damping out of range.
    """
    xi = _check_damping(damping)
    periods = [_check_period(gm, T) for T in np.atleast_1d(np.asarray(periods_s, dtype=float))]
    out = np.empty(len(periods))
    for i, T in enumerate(periods):
        out[i] = (2.0 * math.pi / T) ** 2 * _peak_displacement(gm, T, xi) / G
    return out


def _pgv(gm: GroundMotion) -> float:
    return float(np.max(np.abs(velocity(Trace(gm.acc, header={"delta": gm.dt})))))


def intensity(
    gm: GroundMotion, measure: str, period_s: float | None = None, damping: float = DEFAULT_DAMPING
) -> float:
    """The value of one intensity measure of a ground motion as it is.

    Parameters
    ----------
    gm : GroundMotion
        Ground acceleration [m/s^2] (normally processed).
    measure : {"pga", "pgv", "sa"}
        The measure (:data:`MEASURES`).
    period_s : float, optional
        Oscillator period ``T`` [s] for ``sa`` (required there, refused for the others);
        ``2 dt <= T <= duration``.
    damping : float, optional
        Damping ratio of the oscillator of ``sa`` [-] (default 0.05); not used by the others.

    Returns
    -------
    float
        PGA [g], PGV [m/s] or Sa(T) [g] (:data:`MEASURE_UNITS`). Linear in the record's scale:
        ``intensity(gm.scaled(c), ...) == abs(c) * intensity(gm, ...)``.

    Raises
    ------
    ParameterError
        An unknown measure, a period missing for ``sa`` or given for another measure, a period or the
        damping out of range.
    """
    if measure not in MEASURES:
        raise ParameterError(f"measure={measure!r} is not an intensity measure: valid {', '.join(MEASURES)}")
    if measure != "sa" and period_s is not None:
        raise ParameterError(f"period_s={period_s!r} is only for measure 'sa', not {measure!r}")
    if measure == "pga":
        return gm.pga_g
    if measure == "pgv":
        return _pgv(gm)
    return float(pseudo_spectral_acceleration(gm, [_check_period(gm, period_s)], damping)[0])


def intensities(
    gm: GroundMotion, periods_s: Sequence[float] = (), damping: float = DEFAULT_DAMPING
) -> Intensities:
    """All the intensity measures of one ground motion at once.

    Parameters
    ----------
    gm : GroundMotion
        Ground acceleration [m/s^2] (normally processed).
    periods_s : sequence of float, optional
        Oscillator periods [s] of Sa, each in ``[2 dt, duration]`` (default none).
    damping : float, optional
        Damping ratio of the oscillator [-] (default 0.05).

    Returns
    -------
    Intensities
        ``{"pga_g": PGA [g], "pgv_m_s": PGV [m/s], "sa_g": {T: Sa(T) [g] for T in periods_s}}``;
        each value is linear in the record's scale factor (module docstring).

    Raises
    ------
    ParameterError
        A period or the damping out of range.
    """
    periods = [float(T) for T in periods_s]
    sa = pseudo_spectral_acceleration(gm, periods, damping)
    return {
        "pga_g": gm.pga_g,
        "pgv_m_s": _pgv(gm),
        "sa_g": {T: float(v) for T, v in zip(periods, sa, strict=True)},
    }
