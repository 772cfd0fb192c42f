"""Closed forms of the linear isolator in full contact (docs/model.md §14 E): the exact damped SDOF
response to the three pulses and the uplift amplitude. Plain numpy/scipy, no isorock."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from scipy.optimize import minimize_scalar

G = 9.81
"""Gravity [m/s^2] (docs/model.md §1)."""

_EPS = float(np.finfo(float).eps)


# =================================================================================================
# (E) linear isolator: exact damped SDOF response to the pulses
# =================================================================================================
def _free_sdof(u0: float, v0: float, tau: np.ndarray, w: float, xi: float) -> tuple[np.ndarray, np.ndarray]:
    """Free vibration of ``u'' + 2 xi w u' + w^2 u = 0`` from ``(u0, v0)`` after ``tau`` [s] (exact)."""
    sig = xi * w
    wd = w * math.sqrt(1.0 - xi * xi)
    ex = np.exp(-sig * tau)
    c, s = np.cos(wd * tau), np.sin(wd * tau)
    u = ex * (u0 * c + (v0 + sig * u0) / wd * s)
    v = ex * (v0 * c - (sig * v0 + w * w * u0) / wd * s)
    return u, v


def _sine_forced_from_rest(
    a0: float, om: float, t: np.ndarray, w: float, xi: float
) -> tuple[np.ndarray, np.ndarray]:
    """Response from rest at ``t = 0`` to ``x_g'' = a0 sin(om t)`` (forcing ``-a0 sin(om t)``), exact.

    Undamped: cancellation-free form valid at and near resonance,
    ``u = a0 [t cos(wbar t) S(d t/2) - sin(w t)/w] / (w + om)``,
    ``u' = -a0 om t sin(wbar t) S(d t/2) / (w + om)``, ``d = om - w``, ``wbar = (w + om)/2``,
    ``S(x) = sin(x)/x``. Damped: particular + homogeneous (relative error ~eps/xi near resonance).
    """
    if xi == 0.0:
        d = om - w
        wbar = 0.5 * (w + om)
        sc = np.sinc(d * t / (2.0 * math.pi))  # numpy sinc(x) = sin(pi x)/(pi x)
        u = a0 * (t * np.cos(wbar * t) * sc - np.sin(w * t) / w) / (w + om)
        v = -a0 * om * t * np.sin(wbar * t) * sc / (w + om)
        return u, v
    det = (w * w - om * om) ** 2 + (2.0 * xi * w * om) ** 2
    P = -a0 * (w * w - om * om) / det
    Q = a0 * 2.0 * xi * w * om / det
    up = P * np.sin(om * t) + Q * np.cos(om * t)
    vp = om * (P * np.cos(om * t) - Q * np.sin(om * t))
    uh, vh = _free_sdof(-Q, -om * P, t, w, xi)  # cancels u_p(0) = Q, u_p'(0) = om P
    return up + uh, vp + vh


def sdof_pulse_response(
    shape: str, td: float, a0: float, Tb: float, xi: float, t: np.ndarray | float
) -> tuple[np.ndarray, np.ndarray]:
    """Exact response of ``u'' + 2 xi w u' + w^2 u = -x_g''(t)`` to a pulse, from rest.

    Parameters
    ----------
    shape : {"rect", "halfsine", "fullsine"}
        Pulse shape (docs/model.md §11).
    td : float
        Half-cycle duration [s].
    a0 : float
        Pulse amplitude [m/s^2].
    Tb : float
        SDOF period ``2 pi / w`` [s].
    xi : float
        Damping ratio, ``0 <= xi < 1`` [-].
    t : array_like
        Instants [s] (``t < 0`` gives rest).

    Returns
    -------
    u, v : numpy.ndarray
        Displacement [m] and velocity [m/s] relative to the ground.
        Closed form (Duhamel / particular solutions): round-off accuracy (~1e-15 relative to the peak),
        except ``~eps/xi`` relative for lightly damped systems at resonance.
    """
    t = np.atleast_1d(np.asarray(t, dtype=float))
    w = 2.0 * math.pi / Tb
    om = math.pi / td
    T = 2.0 * td if shape == "fullsine" else td
    u = np.zeros_like(t)
    v = np.zeros_like(t)
    inside = (t >= 0) & (t <= T)
    after = t > T

    def forced(tt: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        if shape == "rect":
            us = -a0 / (w * w)
            uh, vh = _free_sdof(-us, 0.0, tt, w, xi)
            return us + uh, vh
        if shape in ("halfsine", "fullsine"):
            return _sine_forced_from_rest(a0, om, tt, w, xi)
        raise ValueError(f"unknown pulse shape {shape!r}")

    if np.any(inside):
        u[inside], v[inside] = forced(t[inside])
    if np.any(after):
        uT, vT = forced(np.array([T]))
        u[after], v[after] = _free_sdof(float(uT[0]), float(vT[0]), t[after] - T, w, xi)
    return u, v


def sdof_total_acc(
    shape: str, td: float, a0: float, Tb: float, xi: float, t: np.ndarray | float
) -> np.ndarray:
    """Total base acceleration ``A = -(w^2 u + 2 xi w u')`` [m/s^2] of the exact SDOF response.

    Same accuracy as :func:`sdof_pulse_response`.
    """
    w = 2.0 * math.pi / Tb
    u, v = sdof_pulse_response(shape, td, a0, Tb, xi, t)
    return -(w * w * u + 2.0 * xi * w * v)


def _max_abs(f: Callable[[np.ndarray], np.ndarray], t0: float, t1: float, n: int = 4001) -> float:
    """``max |f|`` on ``[t0, t1]`` by sampling then bounded Brent refinement of each sampled peak.

    Accuracy: relative ~1e-15 for a smooth ``f`` whose peaks are separated by more than the sampling step.
    """
    ts = np.linspace(t0, t1, n)
    fs = np.abs(f(ts))
    best = float(max(fs[0], fs[-1]))
    for i in range(1, n - 1):
        if fs[i] >= fs[i - 1] and fs[i] >= fs[i + 1]:
            r = minimize_scalar(
                lambda x: -abs(float(f(np.array([x]))[0])),
                bounds=(ts[i - 1], ts[i + 1]),
                method="bounded",
                options={"xatol": 1e-13 * max(1.0, abs(t1))},
            )
            best = max(best, -float(r.fun), float(fs[i]))
    return best


def _free_peak_abs(A0: float, dA0: float, w: float, xi: float) -> float:
    """Largest ``|A|`` in free vibration starting from ``A(0) = A0``, ``A'(0+) = dA0`` (exact).

    ``A`` obeys the same ODE as ``u``, so ``A = e^{-sig tau} (P cos wd tau + Q sin wd tau)``; its extremes
    decay, hence the maximum is ``|A0|`` or the first extremum.
    """
    sig = xi * w
    wd = w * math.sqrt(1.0 - xi * xi)
    P = A0
    Q = (dA0 + sig * P) / wd
    if xi == 0.0:
        return math.hypot(P, Q)
    # A'(tau) = e^{-sig tau}[(wd Q - sig P) cos + (-sig Q - wd P) sin] = 0
    phi = math.atan2(wd * Q - sig * P, sig * Q + wd * P)  # tan(wd tau) = (wd Q - sig P)/(sig Q + wd P)
    tau = phi / wd
    while tau <= 0.0:
        tau += math.pi / wd
    val = math.exp(-sig * tau) * (P * math.cos(wd * tau) + Q * math.sin(wd * tau))
    return max(abs(P), abs(val))


def linear_max_A1(shape: str, td: float, Tb: float, xi: float) -> float:
    """``max_t |A1(t)|`` for unit input amplitude (linear isolator in full contact) [-].

    Maximum over the pulse (sampling of the exact response plus Brent refinement) and over the whole
    free vibration after it (exact: first extremum). Accuracy ~1e-13 relative.
    """
    w = 2.0 * math.pi / Tb
    T = 2.0 * td if shape == "fullsine" else td
    a_in = max(_max_abs(lambda tt: sdof_total_acc(shape, td, 1.0, Tb, xi, tt), 0.0, T), 0.0)
    uT, vT = sdof_pulse_response(shape, td, 1.0, Tb, xi, T)
    uT, vT = float(uT[0]), float(vT[0])
    A_T = -(w * w * uT + 2.0 * xi * w * vT)
    acc_after = -w * w * uT - 2.0 * xi * w * vT  # u'' after the pulse (x_g'' = 0)
    dA_T = -(w * w * vT + 2.0 * xi * w * acc_after)
    return max(a_in, _free_peak_abs(A_T, dA_T, w, xi))


def linear_uplift_ratio(shape: str, td: float, Tb: float, xi: float) -> float:
    """Uplift amplitude on a linear isolator, ``A_up/(g tan alpha) = 1/max|A1|`` [-] (numeric, ~1e-13)."""
    return 1.0 / linear_max_A1(shape, td, Tb, xi)


def linear_uplift_ratio_undamped(shape: str, td: float, Tb: float) -> float:
    """Undamped closed forms of ``A_up/(g tan alpha)`` (§14 E), ``tau = td/Tb``. Round-off accuracy.

    * rect: ``1/(2 sin(pi tau))`` for ``tau <= 1/2``, ``1/2`` otherwise;
    * half-sine, ``tau < 1/2``: ``(1 - 4 tau^2)/(4 tau cos(pi tau))``;
    * full-sine at resonance (``2 td = Tb``): ``1/pi``.

    Raises
    ------
    ValueError
        Outside the validity of these closed forms.
    """
    tau = td / Tb
    if shape == "rect":
        return 1.0 / (2.0 * math.sin(math.pi * tau)) if tau <= 0.5 else 0.5
    if shape == "halfsine":
        if not tau < 0.5:
            raise ValueError("half-sine closed form needs td/Tb < 1/2")
        return (1.0 - 4.0 * tau * tau) / (4.0 * tau * math.cos(math.pi * tau))
    if shape == "fullsine":
        if abs(2.0 * td - Tb) > 1e-12 * Tb:
            raise ValueError("full-sine closed form only at resonance 2 td = Tb")
        return 1.0 / math.pi
    raise ValueError(f"unknown pulse shape {shape!r}")


def sdof_max_abs_u(shape: str, td: float, a0: float, Tb: float, xi: float, t_end: float) -> float:
    """``max |u|`` over ``[0, t_end]`` of the exact SDOF response [m] (sampling + Brent, ~1e-13 relative)."""
    n = int(max(4001, 200 * t_end / min(Tb, td)))
    return _max_abs(lambda tt: sdof_pulse_response(shape, td, a0, Tb, xi, tt)[0], 0.0, t_end, n)
