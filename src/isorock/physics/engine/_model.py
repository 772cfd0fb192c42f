"""The equations of the kernel (docs/model.md §3-§9): input segments, the Bouc-Wen closed form, the
isolator force, the equations of motion of both regimes, the exact linear SDOF in full contact, the
energy and the exact decisions of free vibration."""

from __future__ import annotations

import math

import numpy as np

from isorock.physics.engine._layout import (
    CONTACT,
    EXC_FULLSINE,
    EXC_RECORD,
    EXC_RECT,
    ISO_FP,
    ISO_LINEAR,
    ISO_NONE,
    P_ALPHA,
    P_ALPHAL,
    P_AMP,
    P_AV0,
    P_AV1,
    P_AVTS,
    P_BWB,
    P_BWG,
    P_CB,
    P_DT,
    P_G,
    P_H,
    P_I43,
    P_I43L,
    P_ISO,
    P_KAPPA,
    P_KB,
    P_MU,
    P_MUO,
    P_R,
    P_RHO,
    P_RL,
    P_TD,
    P_THR,
    P_THRN,
    P_VERT,
    P_WB,
    P_XI,
    P_Y,
    REGIME,
    S_NMIN,
    SLIDE,
    njit_inner,
)


# ---------------------------------------------------------------- excitation segments
@njit_inner(forceinline=True)
def segment(k, ekind, acc, P):
    """Segment ``k`` of the input: (t_start, t_end, type, c0, c1).

    type 0: ``x_g'' = c0 + c1 (t - t_start)``; type 1: ``x_g'' = c0 sin(c1 t)``.
    The last segment is the zero tail, with ``t_end = inf``.
    """
    amp = P[P_AMP]
    if ekind == EXC_RECORD:
        dt = P[P_DT]
        n = acc.shape[1]
        if k < n - 1:
            a0 = amp * acc[0, k]
            a1 = amp * acc[0, k + 1]
            return k * dt, (k + 1) * dt, 0, a0, (a1 - a0) / dt
        return (n - 1) * dt, math.inf, 0, 0.0, 0.0
    td = P[P_TD]
    dur = 2.0 * td if ekind == EXC_FULLSINE else td
    if k == 0:
        if ekind == EXC_RECT:
            return 0.0, dur, 0, amp, 0.0
        return 0.0, dur, 1, amp, math.pi / td
    return dur, math.inf, 0, 0.0, 0.0


@njit_inner(forceinline=True)
def vertical_segment(k, acc, P):
    """The parameter tuple with the vertical input of segment ``k`` in its last three slots.

    ``a_v = P_AV0 + P_AV1 (t - P_AVTS)`` [m/s^2] on the sample interval ``k`` of the record, zero on
    the tail. Called only when ``P[P_VERT]`` is set.
    """
    n = acc.shape[1]
    if k < n - 1:
        dt = P[P_DT]
        a0 = P[P_AMP] * acc[1, k]
        a1 = P[P_AMP] * acc[1, k + 1]
        return P[:P_AV0] + (a0, (a1 - a0) / dt, k * dt)
    return P[:P_AV0] + (0.0, 0.0, 0.0)


@njit_inner(forceinline=True)
def grav(t, P):
    """Effective gravity ``g + a_v(t)`` [m/s^2] (``g`` itself without a vertical input)."""
    if P[P_VERT] == 0.0:
        return P[P_G]
    return P[P_G] + P[P_AV0] + P[P_AV1] * (t - P[P_AVTS])


@njit_inner(forceinline=True)
def fold_gravity(S, ts, te, P):
    """Fold ``(g + a_v) / g`` [-] at the ends of the input segment ``[ts, te]`` [s] (where the linear
    ``a_v`` has its extremes) into the least normal force over weight ``S[S_NMIN]``: in full contact and
    while sliding the normal force per unit mass is ``g + a_v`` (docs/model.md §15, §17); at or below 0
    the object leaves its base (``jumps``)."""
    g = P[P_G]
    m = grav(ts, P) / g
    if te < math.inf:
        m = min(m, grav(te, P) / g)
    if m < S[S_NMIN]:
        S[S_NMIN] = m


@njit_inner(forceinline=True)
def gravity_ratio(t, P):
    """``g / (g + a_v(t))`` [-]: the factor that turns a base acceleration into the one that, compared
    with the constant thresholds ``g tan(alpha)`` and ``mu g``, decides uplift and slip under a vertical
    input (a vanishing or negative ``g + a_v`` gives a huge factor: the block leaves the base)."""
    if P[P_VERT] == 0.0:
        return 1.0
    ge = grav(t, P)
    return P[P_G] / max(ge, 1e-9 * P[P_G])


@njit_inner(forceinline=True)
def over_threshold(A, P):
    """True when a total base acceleration ``A`` [m/s^2] (reduced by ``g / (g + a_v)`` under a vertical)
    starts a motion: ``A > P_THR`` tips the body onto its left edge, ``A < -P_THRN`` onto its right one
    (the two are equal for a symmetric body: ``|A| > g tan(alpha)``; in the sliding mode both are
    ``mu g``)."""
    return A > P[P_THR] or -A > P[P_THRN]


@njit_inner(forceinline=True)
def threshold_of(A, P):
    """The threshold [m/s^2] on the side that ``A`` points to: ``P_THR`` for ``A > 0``, else ``P_THRN``."""
    return P[P_THR] if A > 0.0 else P[P_THRN]


@njit_inner(forceinline=True)
def ground(t, typ, c0, c1, ts):
    """Ground acceleration ``x_g''(t)`` [m/s^2] on a segment described as in :func:`segment`."""
    if typ == 0:
        return c0 + c1 * (t - ts)
    return c0 * math.sin(c1 * t)


# ---------------------------------------------------------------- Bouc-Wen closed form
@njit_inner(forceinline=True)
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


@njit_inner(forceinline=True)
def iso_force(u, v, z, P):
    """Isolator force per unit total mass ``f_b`` [m/s^2]."""
    iso = P[P_ISO]
    if iso == ISO_LINEAR:
        return P[P_KB] * u + P[P_CB] * v
    if iso == ISO_FP:
        return P[P_KB] * u + P[P_MU] * P[P_G] * z
    return 0.0


# ---------------------------------------------------------------- equations of motion
@njit_inner(forceinline=True)
def side(s, P):
    """Geometry of the rocking side ``s`` (docs/model.md §18): ``R_s`` [m], ``alpha_s`` [rad] and the
    moment of inertia about the edge per unit mass ``I_s`` [m^2] (``4/3 R^2`` for a uniform block).
    ``s = +1`` rocks about the right edge, ``s = -1`` about the left one."""
    if s > 0.0:
        return P[P_R], P[P_ALPHA], P[P_I43]
    return P[P_RL], P[P_ALPHAL], P[P_I43L]


@njit_inner(forceinline=True)
def rhs(t, u, v, th, om, regime, s, zs, us, typ, c0, c1, ts, P):
    """Time derivatives of ``(u, u', theta, theta')``."""
    ag = ground(t, typ, c0, c1, ts)
    iso = P[P_ISO]
    if iso == ISO_FP:
        z = bw_phi(zs, u - us, P)
    else:
        z = 0.0
    fb = 0.0
    if iso != ISO_NONE:
        fb = iso_force(u, v, z, P)
        if iso == ISO_FP and P[P_VERT] != 0.0:
            # the friction pendulum's forces follow its normal load, (m + m_b)(g + a_v)
            fb = fb * grav(t, P) / P[P_G]
    if regime == CONTACT:
        if iso == ISO_NONE:
            return 0.0, 0.0, 0.0, 0.0
        return v, -ag - fb, 0.0, 0.0
    if regime == SLIDE:
        # docs/model.md §16: th, om hold the slip s [m] and its rate s' [m/s], s the slip direction
        ge = grav(t, P)
        mug = P[P_MUO] * ge if ge > 0.0 else 0.0
        if iso == ISO_NONE:
            return 0.0, 0.0, om, -mug * s - ag
        rho = P[P_RHO]
        A = -(1.0 + rho) * fb + mug * rho * s
        return v, A - ag, om, -mug * s - A
    R, alpha, I43 = side(s, P)
    phi = alpha - s * th
    C = R * math.cos(phi)
    S = s * R * math.sin(phi)
    g = grav(t, P)
    if iso == ISO_NONE:
        return 0.0, 0.0, om, -(C * ag + g * S) / I43
    kap = P[P_KAPPA]
    r1 = -ag - fb - kap * S * om * om
    r2 = -C * ag - g * S
    D = I43 - kap * C * C
    return v, (I43 * r1 - kap * C * r2) / D, om, (r2 - C * r1) / D


# ---------------------------------------------------------------- exact linear SDOF in contact
@njit_inner()
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


@njit_inner()
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


@njit_inner(forceinline=True)
def contact_A(u, v, z, ag, P):
    """Total base acceleration in full contact [m/s^2]."""
    if P[P_ISO] == ISO_NONE:
        return ag
    return -iso_force(u, v, z, P)


# ---------------------------------------------------------------- energy (docs/model.md §9)
@njit_inner()
def energy(u, v, th, om, z, s, regime, P):
    """Mechanical energy per unit mass of docs/model.md §9 in the given regime [J/kg]."""
    iso = P[P_ISO]
    g = P[P_G]
    if iso == ISO_NONE:
        if regime == CONTACT:
            return 0.0
        R, alpha, I43 = side(s, P)
        return 0.5 * I43 * om * om + g * (R * math.cos(alpha - s * th) - P[P_H])
    if iso == ISO_LINEAR:
        eiso = 0.5 * P[P_KB] * u * u
    else:
        eiso = 0.5 * P[P_KB] * u * u + 0.5 * P[P_MU] * g * P[P_Y] * z * z
    if regime == CONTACT:
        return 0.5 * v * v + eiso
    kap = P[P_KAPPA]
    R, alpha, I43 = side(s, P)
    C = R * math.cos(alpha - s * th)
    return 0.5 * v * v + kap * C * v * om + 0.5 * kap * I43 * om * om + kap * g * (C - P[P_H]) + eiso


@njit_inner()
def e_alpha(s, P):
    """Potential energy ``E_alpha`` [J/kg] of the block at rest at ``theta = alpha_s`` on side ``s``,
    from upright.

    Per unit mass of the block, or of block and base (factor ``kappa``) on an isolated base.
    """
    g = P[P_G]
    R, alpha, _ = side(s, P)
    base = g * R * (1.0 - math.cos(alpha))
    if P[P_ISO] == ISO_NONE:
        return base
    return P[P_KAPPA] * base


@njit_inner()
def no_more_uplift(u, v, z, P, thr):
    """Exact bound (free vibration, full contact): True if ``|A|`` can never exceed ``thr`` again."""
    iso = P[P_ISO]
    if iso == ISO_NONE:
        return True
    e = energy(u, v, 0.0, 0.0, z, 1.0, REGIME[CONTACT], P)
    if iso == ISO_LINEAR:
        xi = P[P_XI]
        return P[P_WB] * math.sqrt(1.0 + 4.0 * xi * xi) * math.sqrt(2.0 * e) < thr
    g = P[P_G]
    Rb = g / P[P_KB]
    return g * math.sqrt(2.0 * e * Rb / g) / Rb + P[P_MU] * g < thr


# ---------------------------------------------------------------- non-isolated uplift search
@njit_inner()
def noniso_uplift_time_vertical(t, te, c0, c1, ts, P):
    """First time >= t (and < te) on a record segment at which ``|x_g''| >= (g + a_v) k``, or inf.

    ``k`` is ``tan(alpha)`` (rocking) or ``mu`` (sliding): ``P_THR / g``; ``x_g''`` and ``a_v`` are
    both linear on the segment, so each side's condition is a linear inequality in time.
    """
    g = P[P_G]
    best = math.inf
    for sg in (1.0, -1.0):
        # the threshold of the side this sign tips the body onto (P_THR for a positive input)
        kk = (P[P_THR] if sg > 0.0 else P[P_THRN]) / P[P_G]
        # f(x) = sg (c0 + c1 x) - k (g + av0 + av1 (x - xv)), x = time - ts
        f0 = sg * c0 - kk * (g + P[P_AV0] + P[P_AV1] * (ts - P[P_AVTS]))
        f1 = sg * c1 - kk * P[P_AV1]
        x = t - ts
        fx = f0 + f1 * x
        if fx > 0.0:
            return t
        if f1 > 0.0:
            tc = ts - f0 / f1
            if tc >= t and tc < te and tc < best:
                best = tc
    return best


@njit_inner()
def noniso_uplift_time(t, te, typ, c0, c1, ts, thp, thn):
    """First time >= t (and < te) at which ``x_g'' >= thp`` or ``x_g'' <= -thn`` on a smooth segment, or
    inf.

    ``thp``, ``thn`` [m/s^2] are the uplift thresholds of a positive and a negative input (equal for a
    symmetric body: the condition is then ``|x_g''| >= thr``).
    """
    if typ == 0:
        a = c0 + c1 * (t - ts)
        if a > thp or -a > thn:
            return t
        if c1 > 0.0:
            tc = ts + (thp - c0) / c1
        elif c1 < 0.0:
            tc = ts + (-thn - c0) / c1
        else:
            return math.inf
        if tc >= t and tc < te:
            return tc
        return math.inf
    amp = abs(c0)
    if amp <= thp and amp <= thn:
        return math.inf
    td = math.pi / c1
    k = math.floor(t / td)
    while k * td < te:
        # half-cycle k of c0 sin(c1 t): positive where c0 > 0 and k is even, or c0 < 0 and k is odd
        thr = thp if (c0 > 0.0) == (int(k) % 2 == 0) else thn
        if amp > thr:
            t1 = td * math.asin(thr / amp) / math.pi
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
