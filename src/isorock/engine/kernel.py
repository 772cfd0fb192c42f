"""Compiled time-stepping kernel of the rocking engine (numba, no Python in the time loop).

The model is that of ``docs/model.md``: two regimes (full contact, rocking), the
uplift rule, the impact map with base-block interaction, the cease-rocking rule,
overturning at ``|theta| = pi/2`` and a free-vibration tail with the exact energy
decisions of §9.

Numerical method
----------------
* The time axis is cut into *segments* on which the ground acceleration is smooth:
  the pulse and the zero tail after it, or one sample interval of a record (linear
  interpolation).  The integrator always stops at segment ends.
* Full contact, linear isolator, linear-in-time input (records, rectangular pulse,
  tail): exact update of the SDOF (closed form; a precomputed transition matrix for
  the record's sample interval).  The uplift instant is found by bisection on the
  closed form, interior peaks of ``|A|`` inside a step included.
* Everything else: adaptive Dormand-Prince 5(4) with FSAL on ``(u, u', theta, theta')``,
  cubic Hermite dense output to locate impacts, overturning, the uplift instant and
  the peaks of ``|theta|`` and ``|u|``; an impact instant is then refined by Newton on
  ``theta`` of the continuous extension of the step.
* Bouc-Wen: for a monotone base motion ``dZ/du = (1 - gamma Z|Z| - beta Z^2)/Y`` has a
  closed-form solution, so ``Z`` is an exact algebraic function of the base
  displacement within a step (``bw_phi``); steps end at every reversal of ``u'``.
  The stiff variable never enters the Runge-Kutta error control.

Code layout
-----------
:func:`run` sets an analysis up (:func:`_setup`), then alternates the two regime loops
:func:`_contact_phase` and :func:`_rocking_phase` until it ends, and assembles the result
(:func:`_finish`). Between the loops the state travels in two small arrays; inside a loop it is
held in scalars and advanced by the step functions (``_contact_*``, ``_rocking_*``), which are
inlined into the loops: called once per step with the 36-float parameter tuple they would cost
5-15 % of the run time.

All state is per unit mass; see ``docs/model.md`` for the equations.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

# ---------------------------------------------------------------- parameter vector layout
P_B, P_H, P_R, P_ALPHA, P_P, P_G, P_KAPPA, P_I43 = 0, 1, 2, 3, 4, 5, 6, 7
P_EPS, P_BETA1, P_BETA2, P_ISO, P_KB, P_CB, P_MU, P_Y = 8, 9, 10, 11, 12, 13, 14, 15
P_BWB, P_BWG, P_THR, P_ETA, P_RTOL, P_ATOL, P_TAIL, P_MAXEXTRA = 16, 17, 18, 19, 20, 21, 22, 23
P_EARLY, P_STOPUP, P_XI, P_WB, P_AMP, P_TD, P_DT, P_HMAX = 24, 25, 26, 27, 28, 29, 30, 31
P_NOUPLIFT, P_TB, P_TH0, P_OM0 = 32, 33, 34, 35
NPAR = 36

ISO_NONE, ISO_LINEAR, ISO_FP = 0, 1, 2
EXC_RECT, EXC_HALFSINE, EXC_FULLSINE, EXC_RECORD = 0, 1, 2, 3
CONTACT, ROCKING = 0, 1

# result vector layout
R_OUTCOME, R_MAXTH, R_NIMP, R_MAXU, R_TUP, R_TOV, R_TEND, R_DECIDED, R_NSTEPS, R_MAXA = range(10)
NRES = 10

HALF_PI = 0.5 * math.pi

# Dormand-Prince 5(4) tableau
A21 = 1.0 / 5.0
A31, A32 = 3.0 / 40.0, 9.0 / 40.0
A41, A42, A43 = 44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0
A51, A52, A53, A54 = 19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0
A61, A62, A63, A64, A65 = 9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0
B1, B3, B4, B5, B6 = 35.0 / 384.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0
E1, E3, E4, E5, E6, E7 = (
    71.0 / 57600.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
)
C2, C3, C4, C5 = 0.2, 0.3, 0.8, 8.0 / 9.0
# continuous extension of Dormand-Prince (Hairer, Norsett & Wanner, DOPRI5 dense output), order 4
D1, D3, D4 = -12715105075.0 / 11282082432.0, 87487479700.0 / 32700410799.0, -10690763975.0 / 1880347072.0
D5, D6, D7 = 701980252875.0 / 199316789632.0, -1453857185.0 / 822651844.0, 69997945.0 / 29380423.0


# ---------------------------------------------------------------- excitation segments
@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
def ground(t, typ, c0, c1, ts):
    """Ground acceleration ``x_g''(t)`` [m/s^2] on a segment described as in :func:`segment`."""
    if typ == 0:
        return c0 + c1 * (t - ts)
    return c0 * math.sin(c1 * t)


# ---------------------------------------------------------------- Bouc-Wen closed form
@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
def iso_force(u, v, z, P):
    """Isolator force per unit total mass ``f_b`` [m/s^2]."""
    iso = P[P_ISO]
    if iso == ISO_LINEAR:
        return P[P_KB] * u + P[P_CB] * v
    if iso == ISO_FP:
        return P[P_KB] * u + P[P_MU] * P[P_G] * z
    return 0.0


# ---------------------------------------------------------------- equations of motion
@njit(cache=True, inline="always")
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


@njit(cache=True)
def dp5_step(t, y0, y1, y2, y3, k1, h, regime, s, zs, us, typ, c0, c1, ts, P):
    """One Dormand-Prince step: the new state, its derivative (FSAL), the error norm and the last
    coefficient of the continuous extension (see :func:`dense`)."""
    a0, a1, a2, a3 = k1
    b = rhs(
        t + C2 * h,
        y0 + h * A21 * a0,
        y1 + h * A21 * a1,
        y2 + h * A21 * a2,
        y3 + h * A21 * a3,
        regime,
        s,
        zs,
        us,
        typ,
        c0,
        c1,
        ts,
        P,
    )
    c = rhs(
        t + C3 * h,
        y0 + h * (A31 * a0 + A32 * b[0]),
        y1 + h * (A31 * a1 + A32 * b[1]),
        y2 + h * (A31 * a2 + A32 * b[2]),
        y3 + h * (A31 * a3 + A32 * b[3]),
        regime,
        s,
        zs,
        us,
        typ,
        c0,
        c1,
        ts,
        P,
    )
    d = rhs(
        t + C4 * h,
        y0 + h * (A41 * a0 + A42 * b[0] + A43 * c[0]),
        y1 + h * (A41 * a1 + A42 * b[1] + A43 * c[1]),
        y2 + h * (A41 * a2 + A42 * b[2] + A43 * c[2]),
        y3 + h * (A41 * a3 + A42 * b[3] + A43 * c[3]),
        regime,
        s,
        zs,
        us,
        typ,
        c0,
        c1,
        ts,
        P,
    )
    e = rhs(
        t + C5 * h,
        y0 + h * (A51 * a0 + A52 * b[0] + A53 * c[0] + A54 * d[0]),
        y1 + h * (A51 * a1 + A52 * b[1] + A53 * c[1] + A54 * d[1]),
        y2 + h * (A51 * a2 + A52 * b[2] + A53 * c[2] + A54 * d[2]),
        y3 + h * (A51 * a3 + A52 * b[3] + A53 * c[3] + A54 * d[3]),
        regime,
        s,
        zs,
        us,
        typ,
        c0,
        c1,
        ts,
        P,
    )
    f = rhs(
        t + h,
        y0 + h * (A61 * a0 + A62 * b[0] + A63 * c[0] + A64 * d[0] + A65 * e[0]),
        y1 + h * (A61 * a1 + A62 * b[1] + A63 * c[1] + A64 * d[1] + A65 * e[1]),
        y2 + h * (A61 * a2 + A62 * b[2] + A63 * c[2] + A64 * d[2] + A65 * e[2]),
        y3 + h * (A61 * a3 + A62 * b[3] + A63 * c[3] + A64 * d[3] + A65 * e[3]),
        regime,
        s,
        zs,
        us,
        typ,
        c0,
        c1,
        ts,
        P,
    )
    n0 = y0 + h * (B1 * a0 + B3 * c[0] + B4 * d[0] + B5 * e[0] + B6 * f[0])
    n1 = y1 + h * (B1 * a1 + B3 * c[1] + B4 * d[1] + B5 * e[1] + B6 * f[1])
    n2 = y2 + h * (B1 * a2 + B3 * c[2] + B4 * d[2] + B5 * e[2] + B6 * f[2])
    n3 = y3 + h * (B1 * a3 + B3 * c[3] + B4 * d[3] + B5 * e[3] + B6 * f[3])
    g = rhs(t + h, n0, n1, n2, n3, regime, s, zs, us, typ, c0, c1, ts, P)
    rtol = P[P_RTOL]
    atol = P[P_ATOL]
    err = 0.0
    for i in range(4):
        if i == 0:
            yo, yn, ai, ci, di, ei, fi, gi = y0, n0, a0, c[0], d[0], e[0], f[0], g[0]
        elif i == 1:
            yo, yn, ai, ci, di, ei, fi, gi = y1, n1, a1, c[1], d[1], e[1], f[1], g[1]
        elif i == 2:
            yo, yn, ai, ci, di, ei, fi, gi = y2, n2, a2, c[2], d[2], e[2], f[2], g[2]
        else:
            yo, yn, ai, ci, di, ei, fi, gi = y3, n3, a3, c[3], d[3], e[3], f[3], g[3]
        ei_ = h * (E1 * ai + E3 * ci + E4 * di + E5 * ei + E6 * fi + E7 * gi)
        sc = atol + rtol * max(abs(yo), abs(yn))
        r = abs(ei_) / sc
        if r > err:
            err = r
    r5 = (
        h * (D1 * a0 + D3 * c[0] + D4 * d[0] + D5 * e[0] + D6 * f[0] + D7 * g[0]),
        h * (D1 * a1 + D3 * c[1] + D4 * d[1] + D5 * e[1] + D6 * f[1] + D7 * g[1]),
        h * (D1 * a2 + D3 * c[2] + D4 * d[2] + D5 * e[2] + D6 * f[2] + D7 * g[2]),
        h * (D1 * a3 + D3 * c[3] + D4 * d[3] + D5 * e[3] + D6 * f[3] + D7 * g[3]),
    )
    return (n0, n1, n2, n3), g, err, r5


@njit(cache=True, inline="always")
def dense(y0, y1, f0, f1, r5, h, tau):
    """Order-4 continuous extension of a Dormand-Prince step at ``t0 + tau h`` (one component)."""
    r2 = y1 - y0
    r3 = h * f0 - r2
    r4 = r2 - h * f1 - r3
    return y0 + tau * (r2 + (1.0 - tau) * (r3 + tau * (r4 + (1.0 - tau) * r5)))


# ---------------------------------------------------------------- cubic Hermite helpers
@njit(cache=True, inline="always")
def herm(p0, p1, d0, d1, h, tau):
    """Cubic Hermite interpolant at ``t0 + tau h`` of values ``p0, p1`` and slopes ``d0, d1`` at the ends."""
    t2 = tau * tau
    t3 = t2 * tau
    return (
        (2 * t3 - 3 * t2 + 1) * p0
        + (t3 - 2 * t2 + tau) * h * d0
        + (-2 * t3 + 3 * t2) * p1
        + (t3 - t2) * h * d1
    )


@njit(cache=True, inline="always")
def dherm(p0, p1, d0, d1, h, tau):
    """Derivative of :func:`herm` with respect to ``tau``."""
    t2 = tau * tau
    return (6 * t2 - 6 * tau) * (p0 - p1) + (3 * t2 - 4 * tau + 1) * h * d0 + (3 * t2 - 2 * tau) * h * d1


@njit(cache=True)
def herm_first_root(p0, p1, d0, d1, h, target, tmax=1.0):
    """First tau in (0, tmax] where the Hermite cubic crosses ``target``; -1 if none.

    An 8-point scan brackets the first sign change, then a safeguarded Newton iteration (bisection
    whenever Newton leaves the bracket) converges to round-off in a few steps.
    """
    q0 = p0 - target
    q1 = p1 - target
    # sign just after zero
    sg0 = q0
    if sg0 == 0.0:
        sg0 = h * d0
        if sg0 == 0.0:
            sg0 = herm(p0, p1, d0, d1, h, 1e-6) - target
    if sg0 == 0.0:
        return 0.0
    n = 8
    lo = 0.0
    hi = tmax
    qlo = sg0
    qhi = q1
    found = False
    for j in range(1, n + 1):
        tau = tmax * j / n
        q = herm(p0, p1, d0, d1, h, tau) - target
        if q * sg0 <= 0.0:
            hi = tau
            qhi = q
            found = True
            break
        lo = tau
        qlo = q
    if not found:
        return -1.0
    if qhi == 0.0:
        return hi
    # start from the secant (or the midpoint when lo is the degenerate start point)
    if lo == 0.0 and q0 == 0.0:
        x = 0.5 * (lo + hi)
    else:
        x = lo + (hi - lo) * qlo / (qlo - qhi)
    for _ in range(60):
        q = herm(p0, p1, d0, d1, h, x) - target
        if q == 0.0:
            return x
        if q * sg0 > 0.0:
            lo = x
        else:
            hi = x
        dq = dherm(p0, p1, d0, d1, h, x)
        xn = x - q / dq if dq != 0.0 else 0.5 * (lo + hi)
        if not (lo < xn < hi):
            xn = 0.5 * (lo + hi)
        if abs(xn - x) < 1e-15 or hi - lo < 1e-15:
            x = xn
            break
        x = xn
    # return a point on the far side of the crossing (the event has happened there)
    q = herm(p0, p1, d0, d1, h, x) - target
    if q * sg0 > 0.0:
        return hi
    return x


@njit(cache=True)
def herm_extremum_tau(p0, p1, d0, d1, h):
    """Location in [0, 1] of the first interior critical point of the Hermite cubic (-1 if none)."""
    a = 6 * p0 + 3 * h * d0 - 6 * p1 + 3 * h * d1
    b = -6 * p0 - 4 * h * d0 + 6 * p1 - 2 * h * d1
    c = h * d0
    if abs(a) < 1e-300:
        if b != 0.0:
            tau = -c / b
            if 0.0 <= tau <= 1.0:
                return tau
        return -1.0
    disc = b * b - 4 * a * c
    if disc < 0.0:
        disc = 0.0
    sq = math.sqrt(disc)
    r1 = (-b - sq) / (2 * a)
    r2 = (-b + sq) / (2 * a)
    best = 2.0
    if 0.0 <= r1 <= 1.0 and r1 < best:
        best = r1
    if 0.0 <= r2 <= 1.0 and r2 < best:
        best = r2
    return best if best <= 1.0 else -1.0


@njit(cache=True)
def herm_extremum(p0, p1, d0, d1, h):
    """Value of the Hermite cubic at its interior critical point where the derivative changes sign
    from ``d0`` to ``d1`` (assumes ``d0 * d1 < 0``)."""
    tau = herm_extremum_tau(p0, p1, d0, d1, h)
    if tau < 0.0:
        return p1
    return herm(p0, p1, d0, d1, h, tau)


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


@njit(cache=True, inline="always")
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


# ---------------------------------------------------------------- state of one analysis
# Between the regimes the state is carried in two small arrays; each regime loop reads it into
# locals, works on those (the time loop runs on scalars only) and writes it back when it returns.
# Float state S: the state of motion, the step size, peaks and event times, then constants of the run.
S_T, S_U, S_V, S_TH, S_OM, S_Z, S_SIDE, S_H = 0, 1, 2, 3, 4, 5, 6, 7
S_MAXTH, S_MAXU, S_MAXA, S_TUP, S_TOV, S_TLAST = 8, 9, 10, 11, 12, 13
S_AGLAST, S_KF = 14, 15  # ground acceleration and derivative (4 slots) at the end of the last rocking step
S_TEXC, S_TEND, S_TMAX, S_EALPHA, S_HLIN, S_HCON = 19, 20, 21, 22, 23, 24
NS = 25
# Integer state F: regime, input segment, counters and flags (0/1).
F_REGIME, F_K, F_NIMP, F_NSTEPS, F_STALL, F_NH = 0, 1, 2, 3, 4, 5
F_UPLIFTED, F_OVERTURNED, F_CERTAIN, F_DECIDED, F_FSAL = 6, 7, 8, 9, 10
NF = 11
# what a regime loop returns to the analysis: the regime has changed / the analysis has ended /
# the history buffer is full (it is grown and the same regime goes on)
_NEXT, _END, _FULL = 0, 1, 2


# ---------------------------------------------------------------- set-up and results
@njit(cache=True)
def _param_tuple(Parr):
    """The parameter vector as a tuple of floats, passed to the helpers without reference counting."""
    return (
        Parr[0],
        Parr[1],
        Parr[2],
        Parr[3],
        Parr[4],
        Parr[5],
        Parr[6],
        Parr[7],
        Parr[8],
        Parr[9],
        Parr[10],
        Parr[11],
        Parr[12],
        Parr[13],
        Parr[14],
        Parr[15],
        Parr[16],
        Parr[17],
        Parr[18],
        Parr[19],
        Parr[20],
        Parr[21],
        Parr[22],
        Parr[23],
        Parr[24],
        Parr[25],
        Parr[26],
        Parr[27],
        Parr[28],
        Parr[29],
        Parr[30],
        Parr[31],
        Parr[32],
        Parr[33],
        Parr[34],
        Parr[35],
    )


@njit(cache=True)
def _setup(P, ekind, acc, hist_on):
    """Initial state of an analysis: at rest in full contact, or rocking from ``(theta0, theta0')``.

    Parameters
    ----------
    P : tuple of float
        Parameter vector (``P_*`` layout).
    ekind : int
        Excitation code (``EXC_*``).
    acc : numpy.ndarray
        Record samples [m/s^2] (unused for a pulse).
    hist_on : bool
        Store the time histories.

    Returns
    -------
    S, F : numpy.ndarray
        Float and integer state (``S_*``, ``F_*`` layouts), with the constants of the run: end of the
        input, of its tail and of the longest analysis [s], ``E_alpha`` [J/kg], contact steps [s].
    Mrec : numpy.ndarray
        Transition matrix of the exact linear contact step over one record sample (2 x 4).
    H : numpy.ndarray
        History buffer (rows t, u, theta, regime, u', theta') holding the sample at ``t = 0``.
    """
    iso = int(P[P_ISO])
    S = np.zeros(NS)
    F = np.zeros(NF, dtype=np.int64)
    if ekind == EXC_RECORD:
        t_exc = (acc.shape[0] - 1) * P[P_DT]
    elif ekind == EXC_FULLSINE:
        t_exc = 2.0 * P[P_TD]
    else:
        t_exc = P[P_TD]
    t_end = t_exc + P[P_TAIL]
    S[S_TEXC] = t_exc
    S[S_TEND] = t_end
    S[S_TMAX] = t_end + P[P_MAXEXTRA]
    S[S_EALPHA] = e_alpha(P)
    # record matrix for the exact contact step
    Mrec = np.zeros((2, 4))
    if iso == ISO_LINEAR and ekind == EXC_RECORD:
        Mrec = lin_matrix(P[P_DT], P)
    S[S_HLIN] = 0.01 * P[P_TB] if iso != ISO_NONE else 0.01
    # contact steps of the Runge-Kutta path: small enough for Hermite peaks of A to ~1e-9
    S[S_HCON] = 0.005 * P[P_TB] if iso != ISO_NONE else 0.01

    th = 0.0
    om = 0.0
    s = 1.0
    regime = CONTACT
    if P[P_TH0] != 0.0:
        # free-rocking studies: start rocking at theta0 with theta0'
        th = P[P_TH0]
        om = P[P_OM0]
        s = 1.0 if th > 0.0 else -1.0
        regime = ROCKING
    S[S_TH] = th
    S[S_OM] = om
    S[S_SIDE] = s
    S[S_H] = min(1e-3, P[P_HMAX])
    S[S_MAXTH] = abs(th)
    S[S_TUP] = math.nan
    S[S_TOV] = math.nan
    S[S_TLAST] = -1.0
    F[F_REGIME] = regime
    F[F_UPLIFTED] = 1 if regime == ROCKING else 0
    F[F_DECIDED] = 1

    # histories: rows t, u, theta, regime, u', theta'
    H = np.empty((6, 1024 if hist_on else 1))
    if hist_on:
        _record(H, 0, 0.0, 0.0, th, regime, 0.0, om)
        F[F_NH] = 1
    return S, F, Mrec, H


@njit(cache=True)
def _finish(S, F, P, H):
    """Result vector (``R_*`` layout) and the histories trimmed to the samples stored."""
    alpha = P[P_ALPHA]
    res = np.zeros(NRES)
    if F[F_OVERTURNED] != 0 or F[F_CERTAIN] != 0:
        res[R_OUTCOME] = 2
        res[R_MAXTH] = HALF_PI / alpha
    elif F[F_UPLIFTED] != 0:
        res[R_OUTCOME] = 1
        res[R_MAXTH] = S[S_MAXTH] / alpha
    else:
        res[R_OUTCOME] = 0
        res[R_MAXTH] = 0.0
    res[R_NIMP] = F[F_NIMP]
    res[R_MAXU] = S[S_MAXU]
    res[R_TUP] = S[S_TUP]
    res[R_TOV] = S[S_TOV]
    res[R_TEND] = S[S_T]
    res[R_DECIDED] = 1.0 if F[F_DECIDED] != 0 else 0.0
    res[R_NSTEPS] = F[F_NSTEPS]
    res[R_MAXA] = S[S_MAXA]
    nh = F[F_NH]
    return (
        res,
        H[0, :nh].copy(),
        H[1, :nh].copy(),
        H[2, :nh].copy(),
        H[3, :nh].astype(np.int8),
        H[4, :nh].copy(),
        H[5, :nh].copy(),
    )


# ---------------------------------------------------------------- shared step helpers
@njit(cache=True, inline="always")
def _dp5_advance(t, u, v, th, om, k1, hstep, regime, s, z, typ, c0, c1, ts, P):
    """Accepted Dormand-Prince step from ``t`` [s], at most ``hstep`` [s] long (error control).

    For the FP isolator the step is cut at a reversal of ``u'`` (Bouc-Wen needs monotone steps).

    Returns
    -------
    yn, kn, r5 : tuple of float
        State ``(u, u', theta, theta')`` at the end of the step, its derivative (FSAL) and the
        dense-output coefficient.
    hstep : float
        Length of the step taken [s].
    h : float
        Proposed length of the next step [s].
    """
    while True:
        yn, kn, err, r5 = dp5_step(t, u, v, th, om, k1, hstep, regime, s, z, u, typ, c0, c1, ts, P)
        if err <= 1.0:
            break
        hstep = hstep * max(0.2, 0.9 * err**-0.2)
    fac = 5.0 if err == 0.0 else min(5.0, max(0.2, 0.9 * err**-0.2))
    h = min(hstep * fac, P[P_HMAX])
    if P[P_ISO] == ISO_FP and v * yn[1] < 0.0:
        tau = herm_first_root(v, yn[1], k1[1], kn[1], hstep, 0.0)
        if 0.0 < tau < 1.0 and tau * hstep > 1e-12:
            hstep = tau * hstep
            yn, kn, err, r5 = dp5_step(t, u, v, th, om, k1, hstep, regime, s, z, u, typ, c0, c1, ts, P)
    return yn, kn, r5, hstep, h


# ---------------------------------------------------------------- full contact
@njit(cache=True, inline="always")
def _uplift_check(t, u, v, z, typ, c0, c1, ts, max_A, stall, P):
    """Uplift check in full contact at ``t`` [s] (docs/model.md §5), with the peak of ``|A|`` [m/s^2].

    ``s theta''(0+) > 0`` exactly when ``s A < -g tan(alpha)``; it is checked on the equations
    themselves so that round-off at ``|A| = g tan(alpha)`` cannot start a zero-length excursion.
    No uplift in the ``no_uplift`` mode, nor once ``stall`` has counted 1000 impacts in a row at the
    time of the previous event (zero-progress guard).

    Returns
    -------
    up : bool
        The block uplifts at ``t``.
    s_up : float
        Rocking side of that uplift.
    max_A : float
        Peak ``|A|`` so far [m/s^2].
    """
    ag = ground(t, typ, c0, c1, ts)
    A = contact_A(u, v, z, ag, P)
    if abs(A) > max_A:
        max_A = abs(A)
    s_up = -1.0 if A > 0.0 else 1.0
    no_uplift_mode = P[P_NOUPLIFT] != 0.0
    up = False
    if abs(A) > P[P_THR] and not no_uplift_mode and stall < 1000:
        d0 = rhs(t, u, v, 0.0, 0.0, ROCKING, s_up, z, u, typ, c0, c1, ts, P)
        up = s_up * d0[3] > 0.0 or int(P[P_ISO]) == ISO_NONE
    return up, s_up, max_A


@njit(cache=True, inline="always")
def _contact_decision(t, u, v, z, max_u, max_A, uplifted, hist_on, t_end, t_max, ealpha, P):
    """Free-vibration decisions in full contact once the input has ended (docs/model.md §9).

    Stop for a block on the ground, for a certain 'rocking' outcome (early stop: contact energy
    below ``E_alpha`` [J/kg]), when no further uplift is possible (energy bound of
    :func:`no_more_uplift`) and nothing reported can change, or at the time limits ``t_end``,
    ``t_max`` [s].

    Returns
    -------
    stop, decided : bool
        End the analysis here; the outcome is decided (False only at ``t_max``).
    """
    iso = int(P[P_ISO])
    early = P[P_EARLY] != 0.0
    no_uplift_mode = P[P_NOUPLIFT] != 0.0
    if iso == ISO_NONE:
        return True, True
    if early and uplifted and energy(u, v, 0.0, 0.0, z, 1.0, CONTACT, P) < ealpha:
        # the outcome is 'rocking' and the block can never reach |theta| = alpha again
        return True, True
    thr_b = max_A * (1.0 + 1e-12) if no_uplift_mode else P[P_THR]
    if no_more_uplift(u, v, z, P, thr_b):
        if early or t >= t_end:
            return True, True
        # nothing reported can change any more: no uplift, and |u| stays below its peak
        # (|u| <= sqrt(2 e / k) with the energy e non-increasing in free vibration)
        if not hist_on and not no_uplift_mode:
            e_c = energy(u, v, 0.0, 0.0, z, 1.0, CONTACT, P)
            if math.sqrt(2.0 * e_c / P[P_KB]) <= max_u:
                return True, True
    if iso == ISO_FP and t >= t_end + 2.0 * P[P_TB]:
        return True, True
    if t >= t_max:
        return True, False
    return False, True


@njit(cache=True, inline="always")
def _contact_noniso(t, ts, te, typ, c0, c1, max_A, P):
    """Non-isolated block in contact: jump to the uplift instant on the segment, or to its end.

    Nothing moves, so nothing is integrated: the uplift time is found in closed form
    (:func:`noniso_uplift_time`) and the peak ``|x_g''|`` [m/s^2] of the segment is recorded.

    Returns
    -------
    t : float
        Uplift instant, or end of the segment [s].
    s_up : float
        Rocking side at the uplift.
    uplift : bool
        The block uplifts at ``t``.
    max_A : float
        Peak ``|A|`` so far [m/s^2].
    """
    no_uplift_mode = P[P_NOUPLIFT] != 0.0
    tu = math.inf
    if not no_uplift_mode:
        tu = noniso_uplift_time(t, te, typ, c0, c1, ts, P[P_THR])
    if tu < te:
        # uplift at the next pass (|A| >= thr there, strictly above right after)
        ag = ground(tu, typ, c0, c1, ts)
        return tu, -1.0 if ag > 0.0 else 1.0, True, max_A
    if typ == 1:
        amx = abs(c0)
    elif te < math.inf:
        amx = max(abs(c0), abs(c0 + c1 * (te - ts)))
    else:
        amx = 0.0
    if amx > max_A:
        max_A = amx
    return te, 1.0, False, max_A


@njit(cache=True)
def _lin_peak_A(u, v, ag0, c1, hstep, dA0, P):
    """Interior extremum of ``A`` [m/s^2] on an exact linear step, by bisection on the sign of ``A'``.

    ``(u, v)`` [m, m/s] is the state at the start of the step, ``ag0 + c1 tau`` [m/s^2] the ground
    acceleration, ``hstep`` [s] the step and ``dA0`` [m/s^3] the slope of ``A`` at its start.
    """
    lo = 0.0
    hi = hstep
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        um, vm = lin_exact(u, v, ag0, c1, mid, P)
        arm = -(ag0 + c1 * mid) - P[P_KB] * um - P[P_CB] * vm
        if -(P[P_KB] * vm + P[P_CB] * arm) * dA0 > 0.0:
            lo = mid
        else:
            hi = mid
        if hi - lo < 1e-15 * hstep:
            break
    um, vm = lin_exact(u, v, ag0, c1, 0.5 * (lo + hi), P)
    return -(P[P_KB] * um + P[P_CB] * vm)


@njit(cache=True)
def _lin_uplift_time(u, v, ag0, c1, hstep, thr, scan, P):
    """First instant [s] inside an exact linear step at which ``|A|`` exceeds ``thr`` [m/s^2].

    With ``scan`` a 64-point scan first brackets the crossing (``|A|`` rises above ``thr`` before an
    interior extremum); then bisection on the closed form. Returns the upper end of the final
    bracket, where ``|A| > thr`` holds.
    """
    tau_lo = 0.0
    tau_hi = hstep
    if scan:
        for j in range(1, 65):
            um, vm = lin_exact(u, v, ag0, c1, hstep * j / 64.0, P)
            if abs(P[P_KB] * um + P[P_CB] * vm) > thr:
                tau_hi = hstep * j / 64.0
                break
            tau_lo = hstep * j / 64.0
    for _ in range(80):
        mid = 0.5 * (tau_lo + tau_hi)
        um, vm = lin_exact(u, v, ag0, c1, mid, P)
        if abs(P[P_KB] * um + P[P_CB] * vm) > thr:
            tau_hi = mid
        else:
            tau_lo = mid
        if tau_hi - tau_lo < 1e-13:
            break
    return tau_hi


@njit(cache=True, inline="always")
def _contact_linear_exact(t, u, v, max_u, max_A, ts, te, c0, c1, ekind, Mrec, h_lin, P):
    """Exact step of the linear isolator in contact under a linear-in-time input.

    The step is one record sample (transition matrix ``Mrec``), or at most ``h_lin`` [s] on a pulse
    or the tail; it is cut at the uplift instant, found by bisection on the closed form, interior
    peaks of ``|A|`` included (exact in the ``no_uplift`` mode).

    Returns
    -------
    t, u, v : float
        Time [s], base displacement [m] and velocity [m/s] at the end of the step.
    max_u, max_A : float
        Peaks of ``|u|`` [m] and ``|A|`` [m/s^2] so far.
    k_inc : int
        1 if the step reached the end of the input segment.
    """
    thr = P[P_THR]
    no_uplift_mode = P[P_NOUPLIFT] != 0.0
    if te < math.inf:
        hstep = te - t
        if ekind != EXC_RECORD and hstep > h_lin:
            hstep = h_lin
    else:
        hstep = h_lin
    ag0 = c0 + c1 * (t - ts)
    if ekind == EXC_RECORD and te < math.inf and abs(hstep - P[P_DT]) < 1e-12 * P[P_DT]:
        ag1 = c0 + c1 * (te - ts)
        un = Mrec[0, 0] * u + Mrec[0, 1] * v + Mrec[0, 2] * ag0 + Mrec[0, 3] * ag1
        vn = Mrec[1, 0] * u + Mrec[1, 1] * v + Mrec[1, 2] * ag0 + Mrec[1, 3] * ag1
    else:
        un, vn = lin_exact(u, v, ag0, c1, hstep, P)
    A0 = -(P[P_KB] * u + P[P_CB] * v)
    A1 = -(P[P_KB] * un + P[P_CB] * vn)
    # interior extremum of A
    ar0 = -ag0 - P[P_KB] * u - P[P_CB] * v
    ar1 = -(ag0 + c1 * hstep) - P[P_KB] * un - P[P_CB] * vn
    dA0 = -(P[P_KB] * v + P[P_CB] * ar0)
    dA1 = -(P[P_KB] * vn + P[P_CB] * ar1)
    hit = False
    scan = False
    if dA0 * dA1 < 0.0:
        # interior extremum of A (cubic Hermite, error O(h^4); exact bisection for the peak
        # itself when the uplift amplitude is being measured)
        if no_uplift_mode:
            Am = _lin_peak_A(u, v, ag0, c1, hstep, dA0, P)
        else:
            Am = herm_extremum(A0, A1, dA0, dA1, hstep)
        if abs(Am) > max_A:
            max_A = abs(Am)
        if abs(Am) > thr:
            # the first point where |A| > thr lies before the extremum: bracket it by a scan
            hit = True
            scan = True
    if abs(A1) > thr:
        hit = True
    if hit and not no_uplift_mode:
        hstep = _lin_uplift_time(u, v, ag0, c1, hstep, thr, scan, P)
        un, vn = lin_exact(u, v, ag0, c1, hstep, P)
    # max |u| inside the step (velocity reversal)
    if v * vn < 0.0:
        ue = abs(herm_extremum(u, un, v, vn, hstep))
        if ue > max_u:
            max_u = ue
    if abs(A1) > max_A:
        max_A = abs(A1)
    t = t + hstep
    k_inc = 0
    if te < math.inf and abs(t - te) < 1e-12 * max(1.0, te):
        t = te
        k_inc = 1
    if abs(un) > max_u:
        max_u = abs(un)
    return t, un, vn, max_u, max_A, k_inc


@njit(cache=True, inline="always")
def _contact_uplift_tau(u, v, z, un, vn, d0, d1, hstep, A0, A1, dA0, dA1, P):
    """Fraction of a Runge-Kutta contact step at which ``|A|`` first exceeds ``g tan(alpha)``; -1 if never.

    ``(u, v)``, ``(un, vn)`` [m, m/s] are the states at the ends of the step, ``d0, d1`` [m/s^2] the
    base accelerations there, ``hstep`` [s] the step and, for the linear isolator, ``A0, A1`` [m/s^2],
    ``dA0, dA1`` [m/s^3] the Hermite data of ``A``; ``z`` is the Bouc-Wen variable at the start.
    A 16-point scan on the Hermite cubics, then bisection.
    """
    iso = int(P[P_ISO])
    thr = P[P_THR]
    hit = -1.0
    hit_lo = 0.0
    if iso == ISO_LINEAR:
        for j in range(1, 17):
            tau = j / 16.0
            if abs(herm(A0, A1, dA0, dA1, hstep, tau)) > thr:
                hit = tau
                hit_lo = tau - 1.0 / 16.0
                break
    elif P[P_KB] * (max(abs(u), abs(un)) + abs(un - u)) + P[P_MU] * P[P_G] > thr:
        # FP: |A| <= kb |u| + mu g, so only steps that can reach the threshold are searched
        for j in range(1, 17):
            tau = j / 16.0
            uu = herm(u, un, v, vn, hstep, tau)
            vv = herm(v, vn, d0, d1, hstep, tau)
            zz = bw_phi(z, uu - u, P)
            if abs(iso_force(uu, vv, zz, P)) > thr:
                hit = tau
                hit_lo = tau - 1.0 / 16.0
                break
    if hit <= 0.0:
        return -1.0
    lo = hit_lo
    hi = hit
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if iso == ISO_LINEAR:
            Amid = herm(A0, A1, dA0, dA1, hstep, mid)
        else:
            uu = herm(u, un, v, vn, hstep, mid)
            vv = herm(v, vn, d0, d1, hstep, mid)
            Amid = iso_force(uu, vv, bw_phi(z, uu - u, P), P)
        if abs(Amid) > thr:
            hi = mid
        else:
            lo = mid
        if (hi - lo) * hstep < 1e-13:
            break
    return hi


@njit(cache=True, inline="always")
def _contact_dp5(t, u, v, z, s, h, max_u, max_A, ts, te, typ, c0, c1, seg_h, h_con, P):
    """Runge-Kutta contact step (FP isolator, or linear isolator under a sine pulse).

    The step (at most ``h_con`` [s]) is cut at the uplift instant; the peaks of ``|A|`` and ``|u|``
    inside it are recorded.

    Returns
    -------
    t, u, v, z : float
        Time [s], base displacement [m] and velocity [m/s], Bouc-Wen variable at the end of the step.
    h : float
        Proposed next step [s].
    max_u, max_A : float
        Peaks of ``|u|`` [m] and ``|A|`` [m/s^2] so far.
    k_inc : int
        1 if the step reached the end of the input segment.
    """
    iso = int(P[P_ISO])
    no_uplift_mode = P[P_NOUPLIFT] != 0.0
    hstep = min(h, seg_h, te - t, h_con)
    k1 = rhs(t, u, v, 0.0, 0.0, CONTACT, s, z, u, typ, c0, c1, ts, P)
    yn, kn, r5, hstep, h = _dp5_advance(t, u, v, 0.0, 0.0, k1, hstep, CONTACT, s, z, typ, c0, c1, ts, P)
    un = yn[0]
    vn = yn[1]
    A0 = 0.0
    A1 = 0.0
    dA0 = 0.0
    dA1 = 0.0
    if iso == ISO_LINEAR:
        A0 = -(P[P_KB] * u + P[P_CB] * v)
        A1 = -(P[P_KB] * un + P[P_CB] * vn)
        dA0 = -(P[P_KB] * v + P[P_CB] * k1[1])
        dA1 = -(P[P_KB] * vn + P[P_CB] * kn[1])
        if dA0 * dA1 < 0.0:
            Am = abs(herm_extremum(A0, A1, dA0, dA1, hstep))
            if Am > max_A:
                max_A = Am
    # uplift inside the step?
    if not no_uplift_mode:
        hit = _contact_uplift_tau(u, v, z, un, vn, k1[1], kn[1], hstep, A0, A1, dA0, dA1, P)
        if hit > 0.0:
            hstep = hit * hstep
            yn, kn, err, r5 = dp5_step(t, u, v, 0.0, 0.0, k1, hstep, CONTACT, s, z, u, typ, c0, c1, ts, P)
            un = yn[0]
            vn = yn[1]
    zn = bw_phi(z, un - u, P) if iso == ISO_FP else 0.0
    if v * vn < 0.0:
        ue = abs(herm_extremum(u, un, v, vn, hstep))
        if ue > max_u:
            max_u = ue
    t = t + hstep
    k_inc = 0
    if abs(t - te) < 1e-12 * max(1.0, te):
        t = te
        k_inc = 1
    if abs(un) > max_u:
        max_u = abs(un)
    Ae = abs(iso_force(un, vn, zn, P))
    if Ae > max_A:
        max_A = Ae
    return t, un, vn, zn, h, max_u, max_A, k_inc


@njit(cache=True)
def _contact_phase(S, F, P, ekind, acc, Mrec, H, hist_on):
    """Time loop in full contact, up to an uplift or the end of the analysis.

    At each pass: peak of ``|A|``, uplift check (docs/model.md §5), free-vibration decisions once
    the input has ended, then one step: closed form for the block on the ground, exact step of the
    linear isolator on a linear-in-time input, Runge-Kutta otherwise.

    Parameters
    ----------
    S, F : numpy.ndarray
        Float and integer state, read at the start and written back at the end.
    P : tuple of float
        Parameter vector.
    ekind : int
        Excitation code.
    acc : numpy.ndarray
        Record samples [m/s^2].
    Mrec : numpy.ndarray
        Transition matrix of the exact linear step over one record sample.
    H : numpy.ndarray
        History buffer (6 x capacity), filled from column ``F[F_NH]`` on.
    hist_on : bool
        Store the time histories.

    Returns
    -------
    int
        ``_NEXT`` at an uplift, ``_END`` at the end of the analysis, ``_FULL`` when ``H`` is full.
    """
    iso = int(P[P_ISO])
    t_exc, t_end, t_max, ealpha = S[S_TEXC], S[S_TEND], S[S_TMAX], S[S_EALPHA]
    h_lin, h_con = S[S_HLIN], S[S_HCON]
    t, u, v, z, s, h = S[S_T], S[S_U], S[S_V], S[S_Z], S[S_SIDE], S[S_H]
    max_u, max_A = S[S_MAXU], S[S_MAXA]
    k, nsteps, stall, nh = F[F_K], F[F_NSTEPS], F[F_STALL], F[F_NH]
    uplifted = F[F_UPLIFTED] != 0
    code = _NEXT
    while True:
        if hist_on and nh >= H.shape[1]:
            code = _FULL
            break
        ts, te, typ, c0, c1 = segment(k, ekind, acc, P)
        if t >= te:
            k += 1
            continue
        seg_h = P[P_HMAX]
        if te - ts < seg_h:
            seg_h = te - ts
        up, s_up, max_A = _uplift_check(t, u, v, z, typ, c0, c1, ts, max_A, stall, P)
        if up:
            break
        # decisions after the input has ended
        if t >= t_exc:
            stop, decided = _contact_decision(
                t, u, v, z, max_u, max_A, uplifted, hist_on, t_end, t_max, ealpha, P
            )
            if stop:
                F[F_DECIDED] = 1 if decided else 0
                code = _END
                break
        if iso == ISO_NONE:
            t, s_up, up, max_A = _contact_noniso(t, ts, te, typ, c0, c1, max_A, P)
            if up:
                nsteps += 1
                break
            if t == math.inf:
                code = _END
                break
            k += 1  # t = te: on to the next segment
            continue
        if iso == ISO_LINEAR and typ == 0:
            t, u, v, max_u, max_A, k_inc = _contact_linear_exact(
                t, u, v, max_u, max_A, ts, te, c0, c1, ekind, Mrec, h_lin, P
            )
        else:
            t, u, v, z, h, max_u, max_A, k_inc = _contact_dp5(
                t, u, v, z, s, h, max_u, max_A, ts, te, typ, c0, c1, seg_h, h_con, P
            )
        k += k_inc
        nsteps += 1
        stall = 0
        if hist_on:
            _record(H, nh, t, u, 0.0, 0, v, 0.0)
            nh += 1
    if up:
        # uplift: the block starts rocking about the corner s_up
        F[F_REGIME] = ROCKING
        s = s_up
        S[S_TH] = 0.0
        S[S_OM] = 0.0
        if not uplifted:
            F[F_UPLIFTED] = 1
            S[S_TUP] = t
            if P[P_STOPUP] != 0.0:
                code = _END
    S[S_T], S[S_U], S[S_V], S[S_Z], S[S_SIDE], S[S_H] = t, u, v, z, s, h
    S[S_MAXU], S[S_MAXA] = max_u, max_A
    F[F_K], F[F_NSTEPS], F[F_STALL], F[F_NH] = k, nsteps, stall, nh
    return code


# ---------------------------------------------------------------- rocking
@njit(cache=True, inline="always")
def _rocking_event(th, thn, om, omn, s, hstep):
    """First event inside a rocking step, from the Hermite cubic of ``theta``: (event, tau).

    ``event`` is 0 (none), 1 (impact: ``s theta`` down to 0, a graze that dips below 0 included) or
    2 (overturn: ``s theta = pi/2``); ``tau`` is its fraction of the step ``hstep`` [s] (2 if none).
    ``th, thn`` [rad] and ``om, omn`` [rad/s] are the rotation and its rate at the ends of the step.
    """
    sth0 = s * th
    sth1 = s * thn
    event = 0
    tau_ev = 2.0
    if sth1 >= HALF_PI:
        tau = herm_first_root(sth0, sth1, s * om, s * omn, hstep, HALF_PI)
        if tau > 0.0:
            event = 2
            tau_ev = tau
    if sth1 < 0.0 or (s * om < 0.0 and s * omn > 0.0):
        check = True
        tmax = 1.0
        if sth1 >= 0.0:
            # graze: theta turns back inside the step; an impact iff the dip goes below zero
            tmax = herm_extremum_tau(sth0, sth1, s * om, s * omn, hstep)
            check = tmax > 0.0 and herm(sth0, sth1, s * om, s * omn, hstep, tmax) < 0.0
        if check:
            tau = herm_first_root(sth0, sth1, s * om, s * omn, hstep, 0.0, tmax)
            if tau > 0.0 and tau < tau_ev:
                event = 1
                tau_ev = tau
    return event, tau_ev


@njit(cache=True)
def _impact_state(y0, yn, k1, kn, r5, hstep, tau, alpha):
    """State at an impact located at the fraction ``tau`` of a rocking step.

    The instant is refined by Newton on ``theta`` of the continuous extension (``d theta / d tau =
    h theta'``); no extra Runge-Kutta step is needed. ``y0, yn`` are the states ``(u, u', theta,
    theta')`` at the ends of the step, ``k1, kn`` their derivatives, ``r5`` the dense-output
    coefficient, ``hstep`` [s] the step and ``alpha`` [rad] the slenderness angle.

    Returns
    -------
    u, v, om : float
        Base displacement [m], base velocity [m/s] and rotation rate [rad/s] at the impact.
    hstep : float
        Time from the start of the step to the impact [s].
    """
    u, v, th, om = y0
    un, vn, thn, omn = yn
    for _ in range(4):
        thd = dense(th, thn, om, omn, r5[2], hstep, tau)
        omd = dense(om, omn, k1[3], kn[3], r5[3], hstep, tau)
        if omd == 0.0 or abs(thd) <= 1e-14 * alpha:
            break
        tn = tau - thd / (hstep * omd)
        if not (0.0 < tn <= 1.0):
            break
        tau = tn
    ui = dense(u, un, v, vn, r5[0], hstep, tau)
    vi = dense(v, vn, k1[1], kn[1], r5[1], hstep, tau)
    omi = dense(om, omn, k1[3], kn[3], r5[3], hstep, tau)
    return ui, vi, omi, tau * hstep


@njit(cache=True, inline="always")
def _rocking_step(t, u, v, th, om, z, s, h, max_th, max_u, k1, ts, te, typ, c0, c1, seg_h, P):
    """One Dormand-Prince step in the rocking regime, ended at an impact or at overturning.

    Parameters
    ----------
    t, u, v, th, om, z : float
        Time [s], base displacement [m] and velocity [m/s], rotation [rad] and its rate [rad/s],
        Bouc-Wen variable [-].
    s : float
        Rocking side (+1 or -1).
    h : float
        Proposed step [s].
    max_th, max_u : float
        Peaks of ``|theta|`` [rad] and ``|u|`` [m] so far.
    k1 : tuple of float
        Derivative of ``(u, u', theta, theta')`` at ``t``.
    ts, te : float
        Start and end of the input segment [s].
    typ, c0, c1 : int, float, float
        Ground acceleration on the segment (see :func:`segment`).
    seg_h : float
        Largest step on the segment [s].
    P : tuple of float
        Parameter vector.

    Returns
    -------
    event : int
        0 none, 1 impact (the state returned is the one just before it), 2 overturn (only the time,
        that of overturning, is updated).
    t, u, v, th, om, z, h, max_th, max_u : float
        As on input, at the end of the step.
    kn : tuple of float
        Derivative at the end of the step (FSAL).
    k_inc : int
        1 if the step reached the end of the input segment.
    """
    hstep = min(h, seg_h, te - t)
    yn, kn, r5, hstep, h = _dp5_advance(t, u, v, th, om, k1, hstep, ROCKING, s, z, typ, c0, c1, ts, P)
    un, vn, thn, omn = yn
    event, tau_ev = _rocking_event(th, thn, om, omn, s, hstep)
    if event == 2:
        # overturn: time from the dense output
        return 2, t + tau_ev * hstep, u, v, th, om, z, h, max_th, max_u, kn, 0
    if event == 1:
        un, vn, omn, hstep = _impact_state((u, v, th, om), yn, k1, kn, r5, hstep, tau_ev, P[P_ALPHA])
        thn = 0.0
    # peaks inside the step
    if s * om > 0.0 and s * omn < 0.0:
        pk = herm_extremum(s * th, s * thn, s * om, s * omn, hstep)
        if pk > max_th:
            max_th = pk
    if v * vn < 0.0:
        ue = abs(herm_extremum(u, un, v, vn, hstep))
        if ue > max_u:
            max_u = ue
    if P[P_ISO] == ISO_FP:
        z = bw_phi(z, un - u, P)
    t = t + hstep
    k_inc = 0
    if te < math.inf and abs(t - te) < 1e-12 * max(1.0, te):
        t = te
        k_inc = 1
    if abs(thn) > max_th:
        max_th = abs(thn)
    if abs(un) > max_u:
        max_u = abs(un)
    return event, t, un, vn, thn, omn, z, h, max_th, max_u, kn, k_inc


@njit(cache=True)
def _impact(v, om, s, P):
    """Impact map at ``theta = 0`` (docs/model.md §7-§8).

    Restitution ``theta'+ = eps theta'-`` and the jump of the base velocity; rocking ceases when
    ``|theta'+| < eta p alpha``, else it goes on about the other corner.

    Returns
    -------
    v, om, s : float
        Base velocity [m/s], rotation rate [rad/s] and rocking side after the impact.
    ceased : bool
        Rocking has ceased (full contact).
    """
    eps = P[P_EPS]
    omp = eps * om
    if eps <= 0.0 or abs(omp) < P[P_ETA] * P[P_P] * P[P_ALPHA]:
        return v + P[P_BETA2] * om, 0.0, s, True
    return v + P[P_BETA1] * om, omp, -s, False


@njit(cache=True, inline="always")
def _rocking_decision(t, u, v, th, om, z, s, certain_over, t_max, ealpha, P):
    """Free-vibration decision while rocking once the input has ended (docs/model.md §9).

    With the energy below ``E_alpha`` [J/kg] the outcome is certain: overturning if ``s theta >
    alpha``, else the block can never overturn. An early stop ends the analysis there; a full run
    goes on until rocking ceases (complete impact count) or until ``t_max`` [s].

    Returns
    -------
    stop : bool
        End the analysis here.
    certain_over : bool
        Overturning is certain (now or at an earlier step, flag ``certain_over`` on input).
    decided : bool
        The outcome is decided (False only at ``t_max`` with the outcome still open).
    """
    e = energy(u, v, th, om, z, s, ROCKING, P)
    early = P[P_EARLY] != 0.0
    safe = False
    if e < ealpha:
        if s * th > P[P_ALPHA]:
            certain_over = True
            if early:
                return True, certain_over, True
        else:
            # can never overturn; a full run goes on until rocking ceases (complete impact count)
            safe = True
            if early:
                return True, certain_over, True
    if t >= t_max:
        return True, certain_over, safe or certain_over
    return False, certain_over, True


@njit(cache=True)
def _rocking_phase(S, F, P, ekind, acc, H, hist_on):
    """Time loop in the rocking regime, up to the end of rocking or of the analysis.

    At each step: Dormand-Prince step with event location (:func:`_rocking_step`), overturning,
    impact map with the cease-rocking rule, then the free-vibration decisions once the input has ended.

    Parameters
    ----------
    S, F : numpy.ndarray
        Float and integer state, read at the start and written back at the end.
    P : tuple of float
        Parameter vector.
    ekind : int
        Excitation code.
    acc : numpy.ndarray
        Record samples [m/s^2].
    H : numpy.ndarray
        History buffer (6 x capacity), filled from column ``F[F_NH]`` on.
    hist_on : bool
        Store the time histories.

    Returns
    -------
    int
        ``_NEXT`` when rocking ceases, ``_END`` at the end of the analysis, ``_FULL`` when ``H`` is full.
    """
    t_exc, t_max, ealpha = S[S_TEXC], S[S_TMAX], S[S_EALPHA]
    t, u, v, th, om, z, s, h = S[S_T], S[S_U], S[S_V], S[S_TH], S[S_OM], S[S_Z], S[S_SIDE], S[S_H]
    max_th, max_u, t_last = S[S_MAXTH], S[S_MAXU], S[S_TLAST]
    k, nsteps, stall, nh, n_imp = F[F_K], F[F_NSTEPS], F[F_STALL], F[F_NH], F[F_NIMP]
    certain_over = F[F_CERTAIN] != 0
    regime = ROCKING
    # first-same-as-last: the derivative at the end of the last step, valid while the input is smooth
    fsal_ok = F[F_FSAL] != 0
    kf = (S[S_KF], S[S_KF + 1], S[S_KF + 2], S[S_KF + 3])
    ag_last = S[S_AGLAST]
    code = _NEXT
    while True:
        if hist_on and nh >= H.shape[1]:
            code = _FULL
            break
        ts, te, typ, c0, c1 = segment(k, ekind, acc, P)
        if t >= te:
            k += 1
            continue
        seg_h = P[P_HMAX]
        if te - ts < seg_h:
            seg_h = te - ts
        if fsal_ok and abs(ground(t, typ, c0, c1, ts) - ag_last) <= 1e-12 * (1.0 + abs(ag_last)):
            k1 = kf
        else:
            k1 = rhs(t, u, v, th, om, ROCKING, s, z, u, typ, c0, c1, ts, P)
        fsal_ok = False
        event, t, u, v, th, om, z, h, max_th, max_u, kn, k_inc = _rocking_step(
            t, u, v, th, om, z, s, h, max_th, max_u, k1, ts, te, typ, c0, c1, seg_h, P
        )
        k += k_inc
        nsteps += 1
        if event == 2:
            F[F_OVERTURNED] = 1
            S[S_TOV] = t
            max_th = HALF_PI
            code = _END
            break
        if event == 0:
            kf = kn
            fsal_ok = True
            ag_last = ground(t, typ, c0, c1, ts)
        if event == 1:
            # zero-progress guard: an impact right at the previous event's time
            if t - t_last <= 1e-12 * max(1.0, t):
                stall += 1
            else:
                stall = 0
            t_last = t
            th = 0.0
            n_imp += 1
            v, om, s, ceased = _impact(v, om, s, P)
            if ceased:
                regime = CONTACT
        if hist_on:
            _record(H, nh, t, u, th, regime, v, om)
            nh += 1
        if regime == CONTACT:
            break
        # decisions in free vibration
        if t >= t_exc:
            stop, certain_over, decided = _rocking_decision(
                t, u, v, th, om, z, s, certain_over, t_max, ealpha, P
            )
            if stop:
                F[F_DECIDED] = 1 if decided else 0
                code = _END
                break
    F[F_REGIME] = regime
    F[F_CERTAIN] = 1 if certain_over else 0
    S[S_T], S[S_U], S[S_V], S[S_TH], S[S_OM], S[S_Z], S[S_SIDE], S[S_H] = t, u, v, th, om, z, s, h
    S[S_MAXTH], S[S_MAXU], S[S_TLAST] = max_th, max_u, t_last
    F[F_K], F[F_NSTEPS], F[F_STALL], F[F_NH], F[F_NIMP] = k, nsteps, stall, nh, n_imp
    F[F_FSAL] = 1 if fsal_ok else 0
    S[S_KF], S[S_KF + 1], S[S_KF + 2], S[S_KF + 3] = kf
    S[S_AGLAST] = ag_last
    return code


# ---------------------------------------------------------------- the analysis
@njit(cache=True)
def run(Parr, ekind, acc, hist_on):
    """Run one analysis: alternate the contact and rocking regime loops until the analysis ends.

    Parameters
    ----------
    Parr : numpy.ndarray
        Parameter vector (``NPAR`` floats, ``P_*`` layout; see :func:`isorock.engine.pack_parameters`).
    ekind : int
        Excitation code (``EXC_*``).
    acc : numpy.ndarray
        Record samples [m/s^2] (``EXC_RECORD``; ignored for a pulse).
    hist_on : bool
        Store the time histories at the integrator's steps.

    Returns
    -------
    res : numpy.ndarray
        Result vector (``NRES`` floats, ``R_*`` layout).
    t, u, theta, regime, u_dot, theta_dot : numpy.ndarray
        Histories [s, m, rad, -, m/s, rad/s] (empty unless ``hist_on``).
    """
    P = _param_tuple(Parr)
    S, F, Mrec, H = _setup(P, ekind, acc, hist_on)
    code = _NEXT
    while code != _END:
        if code == _FULL:
            H = _grow(H, F[F_NH])
        if F[F_REGIME] == CONTACT:
            code = _contact_phase(S, F, P, ekind, acc, Mrec, H, hist_on)
        else:
            code = _rocking_phase(S, F, P, ekind, acc, H, hist_on)
    return _finish(S, F, P, H)


@njit(cache=True)
def _record(H, n, t, u, th, rg, v, om):
    """Store one history sample in column ``n`` of ``H`` (which must have room for it).

    ``t`` [s], ``u`` [m], ``th`` [rad], regime ``rg``, ``v`` [m/s], ``om`` [rad/s].
    """
    H[0, n] = t
    H[1, n] = u
    H[2, n] = th
    H[3, n] = rg
    H[4, n] = v
    H[5, n] = om


@njit(cache=True)
def _grow(H, n):
    """Copy of the history buffer ``H`` (first ``n`` samples) with twice its capacity."""
    G2 = np.empty((6, 2 * H.shape[1]))
    G2[:, :n] = H[:, :n]
    return G2


@njit(cache=True, parallel=True)
def run_many(Ps, ekind, acc):
    """Run one analysis per row of ``Ps`` in parallel; returns the result vectors (rows x NRES)."""
    n = Ps.shape[0]
    out = np.empty((n, NRES))
    for i in prange(n):
        res = run(Ps[i], ekind, acc, False)[0]
        for j in range(NRES):
            out[i, j] = res[j]
    return out
