"""The integrator of the kernel: one Dormand-Prince 5(4) step with its error estimate and its
order-4 continuous extension, and the cubic Hermite helpers that locate events and peaks inside a
step."""

from __future__ import annotations

import math

from isorock.physics.engine._layout import ISO_FP, P_ATOL, P_HMAX, P_ISO, P_RTOL, njit_inner
from isorock.physics.engine._model import rhs

# Dormand-Prince 5(4) tableau
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


@njit_inner()
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


@njit_inner(forceinline=True)
def dense(y0, y1, f0, f1, r5, h, tau):
    """Order-4 continuous extension of a Dormand-Prince step at ``t0 + tau h`` (one component)."""
    r2 = y1 - y0
    r3 = h * f0 - r2
    r4 = r2 - h * f1 - r3
    return y0 + tau * (r2 + (1.0 - tau) * (r3 + tau * (r4 + (1.0 - tau) * r5)))


@njit_inner(forceinline=True)
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


@njit_inner(forceinline=True)
def dherm(p0, p1, d0, d1, h, tau):
    """Derivative of :func:`herm` with respect to ``tau``."""
    t2 = tau * tau
    return (6 * t2 - 6 * tau) * (p0 - p1) + (3 * t2 - 4 * tau + 1) * h * d0 + (3 * t2 - 2 * tau) * h * d1


@njit_inner()
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


@njit_inner()
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


@njit_inner()
def herm_extremum(p0, p1, d0, d1, h):
    """Value of the Hermite cubic at its interior critical point where the derivative changes sign
    from ``d0`` to ``d1`` (assumes ``d0 * d1 < 0``)."""
    tau = herm_extremum_tau(p0, p1, d0, d1, h)
    if tau < 0.0:
        return p1
    return herm(p0, p1, d0, d1, h, tau)


@njit_inner(forceinline=True)
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
        tau = herm_first_root(v, yn[1], k1[1], kn[1], hstep, 0.0, 1.0)
        if 0.0 < tau < 1.0 and tau * hstep > 1e-12:
            hstep = tau * hstep
            yn, kn, err, r5 = dp5_step(t, u, v, th, om, k1, hstep, regime, s, z, u, typ, c0, c1, ts, P)
    return yn, kn, r5, hstep, h
