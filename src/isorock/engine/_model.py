"""The equations of the kernel (docs/model.md §3-§9): input segments, the Bouc-Wen closed form, the
isolator force, the equations of motion of both regimes, the exact linear SDOF in full contact, the
energy and the exact decisions of free vibration."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._layout import (
    CONTACT,
    EXC_FULLSINE,
    EXC_RECORD,
    EXC_RECT,
    ISO_FP,
    ISO_LINEAR,
    ISO_NONE,
    P_ALPHA,
    P_AMP,
    P_BWB,
    P_BWG,
    P_CB,
    P_DT,
    P_G,
    P_H,
    P_I43,
    P_ISO,
    P_KAPPA,
    P_KB,
    P_MU,
    P_R,
    P_TD,
    P_WB,
    P_XI,
    P_Y,
)


# ---------------------------------------------------------------- excitation segments
@njit(cache=True, forceinline=True)
def segment(k, ekind, acc, P):
    """Segment ``k`` of the input: (t_start, t_end, type, c0, c1).

    type 0: ``x_g'' = c0 + c1 (t - t_start)``; type 1: ``x_g'' = c0 sin(c1 t)``.
    The last segment is the zero tail, with ``t_end = inf``.
    """
    amp = P[P_AMP]
    if ekind == EXC_RECORD:
        dt = P[P_DT]
        n = acc.shape[0]
        if k < n - 1:
            a0 = amp * acc[k]
            a1 = amp * acc[k + 1]
            return k * dt, (k + 1) * dt, 0, a0, (a1 - a0) / dt
        return (n - 1) * dt, math.inf, 0, 0.0, 0.0
    td = P[P_TD]
    dur = 2.0 * td if ekind == EXC_FULLSINE else td
    if k == 0:
        if ekind == EXC_RECT:
            return 0.0, dur, 0, amp, 0.0
        return 0.0, dur, 1, amp, math.pi / td
    return dur, math.inf, 0, 0.0, 0.0


@njit(cache=True, forceinline=True)
def ground(t, typ, c0, c1, ts):
    """Ground acceleration ``x_g''(t)`` [m/s^2] on a segment described as in :func:`segment`."""
    if typ == 0:
        return c0 + c1 * (t - ts)
    return c0 * math.sin(c1 * t)


# ---------------------------------------------------------------- Bouc-Wen closed form
@njit(cache=True, forceinline=True)
def bw_phi(z0, du, P):
    """Bouc-Wen variable after a monotone base displacement increment ``du`` [m] from ``z0``."""
    if du == 0.0:
        return z0
    Y = P[P_Y]
    a = P[P_BWG] + P[P_BWB]
    c = P[P_BWG] - P[P_BWB]
    sg = 1.0 if du > 0.0 else -1.0
    z = sg * z0
    x = abs(du) / Y
    if z < 0.0:
        if c > 0.0:
            sc = math.sqrt(c)
            x0 = -math.atan(sc * z) / sc
            if x < x0:
                return sg * math.tan(sc * x + math.atan(sc * z)) / sc
        else:
            x0 = -z
            if x < x0:
                return sg * (z + x)
        x -= x0
        z = 0.0
    sa = math.sqrt(a)
    w = sa * z
    if w > 1.0 - 1e-16:
        w = 1.0 - 1e-16
    return sg * math.tanh(sa * x + math.atanh(w)) / sa


@njit(cache=True, forceinline=True)
def iso_force(u, v, z, P):
    """Isolator force per unit total mass ``f_b`` [m/s^2]."""
    iso = P[P_ISO]
    if iso == ISO_LINEAR:
        return P[P_KB] * u + P[P_CB] * v
    if iso == ISO_FP:
        return P[P_KB] * u + P[P_MU] * P[P_G] * z
    return 0.0


# ---------------------------------------------------------------- equations of motion
@njit(cache=True, forceinline=True)
def rhs(t, u, v, th, om, regime, s, zs, us, typ, c0, c1, ts, P):
    """Time derivatives of ``(u, u', theta, theta')``."""
    ag = ground(t, typ, c0, c1, ts)
    iso = P[P_ISO]
    if iso == ISO_FP:
        z = bw_phi(zs, u - us, P)
    else:
        z = 0.0
    if regime == CONTACT:
        if iso == ISO_NONE:
            return 0.0, 0.0, 0.0, 0.0
        return v, -ag - iso_force(u, v, z, P), 0.0, 0.0
    R = P[P_R]
    phi = P[P_ALPHA] - s * th
    C = R * math.cos(phi)
    S = s * R * math.sin(phi)
    I43 = P[P_I43]
    g = P[P_G]
    if iso == ISO_NONE:
        return 0.0, 0.0, om, -(C * ag + g * S) / I43
    kap = P[P_KAPPA]
    r1 = -ag - iso_force(u, v, z, P) - kap * S * om * om
    r2 = -C * ag - g * S
    D = I43 - kap * C * C
    return v, (I43 * r1 - kap * C * r2) / D, om, (r2 - C * r1) / D


# ---------------------------------------------------------------- exact linear SDOF in contact
@njit(cache=True)
def lin_exact(u0, v0, a0, slope, tau, P):
    """Exact state of ``u'' + cb u' + kb u = -(a0 + slope tau)`` after ``tau`` seconds."""
    w = P[P_WB]
    xi = P[P_XI]
    kb = P[P_KB]
    cb = P[P_CB]
    wd = w * math.sqrt(1.0 - xi * xi)
    c1p = -slope / kb
    c0p = (-a0 - cb * c1p) / kb
    C1 = u0 - c0p
    C2 = (v0 - c1p + xi * w * C1) / wd
    ex = math.exp(-xi * w * tau)
    cs = math.cos(wd * tau)
    sn = math.sin(wd * tau)
    u = c0p + c1p * tau + ex * (C1 * cs + C2 * sn)
    v = c1p + ex * ((wd * C2 - xi * w * C1) * cs - (wd * C1 + xi * w * C2) * sn)
    return u, v


@njit(cache=True)
def lin_matrix(h, P):
    """Transition matrix ``M`` (2 x 4): ``(u1, v1) = M @ (u0, v0, a0, a1)`` over a step ``h`` with a
    ground acceleration linear from ``a0`` to ``a1``."""
    M = np.empty((2, 4))
    for j in range(4):
        u0 = 1.0 if j == 0 else 0.0
        v0 = 1.0 if j == 1 else 0.0
        a0 = 1.0 if j == 2 else 0.0
        a1 = 1.0 if j == 3 else 0.0
        u, v = lin_exact(u0, v0, a0, (a1 - a0) / h, h, P)
        M[0, j] = u
        M[1, j] = v
    return M


@njit(cache=True, forceinline=True)
def contact_A(u, v, z, ag, P):
    """Total base acceleration in full contact [m/s^2]."""
    if P[P_ISO] == ISO_NONE:
        return ag
    return -iso_force(u, v, z, P)


# ---------------------------------------------------------------- energy (docs/model.md §9)
@njit(cache=True)
def energy(u, v, th, om, z, s, regime, P):
    """Mechanical energy per unit mass of docs/model.md §9 in the given regime [J/kg]."""
    iso = P[P_ISO]
    g = P[P_G]
    if iso == ISO_NONE:
        if regime == CONTACT:
            return 0.0
        return 0.5 * P[P_I43] * om * om + g * (P[P_R] * math.cos(P[P_ALPHA] - s * th) - P[P_H])
    if iso == ISO_LINEAR:
        eiso = 0.5 * P[P_KB] * u * u
    else:
        eiso = 0.5 * P[P_KB] * u * u + 0.5 * P[P_MU] * g * P[P_Y] * z * z
    if regime == CONTACT:
        return 0.5 * v * v + eiso
    kap = P[P_KAPPA]
    C = P[P_R] * math.cos(P[P_ALPHA] - s * th)
    return 0.5 * v * v + kap * C * v * om + 0.5 * kap * P[P_I43] * om * om + kap * g * (C - P[P_H]) + eiso


@njit(cache=True)
def e_alpha(P):
    """Potential energy ``E_alpha`` [J/kg] of the block at rest at ``theta = alpha``, from upright.

    Per unit mass of the block, or of block and base (factor ``kappa``) on an isolated base.
    """
    g = P[P_G]
    base = g * P[P_R] * (1.0 - math.cos(P[P_ALPHA]))
    if P[P_ISO] == ISO_NONE:
        return base
    return P[P_KAPPA] * base


@njit(cache=True)
def no_more_uplift(u, v, z, P, thr):
    """Exact bound (free vibration, full contact): True if ``|A|`` can never exceed ``thr`` again."""
    iso = P[P_ISO]
    if iso == ISO_NONE:
        return True
    e = energy(u, v, 0.0, 0.0, z, 1.0, CONTACT, P)
    if iso == ISO_LINEAR:
        xi = P[P_XI]
        return P[P_WB] * math.sqrt(1.0 + 4.0 * xi * xi) * math.sqrt(2.0 * e) < thr
    g = P[P_G]
    Rb = g / P[P_KB]
    return g * math.sqrt(2.0 * e * Rb / g) / Rb + P[P_MU] * g < thr


# ---------------------------------------------------------------- non-isolated uplift search
@njit(cache=True)
def noniso_uplift_time(t, te, typ, c0, c1, ts, thr):
    """First time >= t (and < te) at which ``|x_g''| >= thr`` on a smooth segment, or inf."""
    if typ == 0:
        a = c0 + c1 * (t - ts)
        if abs(a) > thr:
            return t
        if c1 > 0.0:
            tc = ts + (thr - c0) / c1
        elif c1 < 0.0:
            tc = ts + (-thr - c0) / c1
        else:
            return math.inf
        if tc >= t and tc < te:
            return tc
        return math.inf
    amp = abs(c0)
    if amp <= thr:
        return math.inf
    td = math.pi / c1
    t1 = td * math.asin(thr / amp) / math.pi
    k = math.floor(t / td)
    while k * td < te:
        w0 = k * td + t1
        w1 = (k + 1) * td - t1
        if t < w1:
            if t > w0:
                return t
            if w0 < te:
                return w0
            return math.inf
        k += 1
    return math.inf
