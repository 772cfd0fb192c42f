"""The sliding regime loop of the kernel (docs/model.md §16): Coulomb stick-slip of the object on its base.

In the sliding mode the kernel analyses an object whose friction coefficient ``mu`` is below
``tan(alpha)``: friction can never lift an edge, so the object sticks or slips and never rocks. The
sticking object moves with its base, exactly as the block in full contact: the contact loop
(:mod:`._contact`) runs it, with the threshold ``mu g`` in place of ``g tan(alpha)``. This loop runs a
slip: Dormand-Prince steps of ``(u, u', s, s')`` with the slip direction ``sigma`` fixed, each ended
where ``s'`` returns to zero (located on the step's continuous extension); there the object sticks if
the friction can hold it (``|A| <= mu (g + a_v)`` with the base's acceleration when stuck), else it
slips back the other way.

The slip ``s`` [m] and its rate ``s'`` [m/s] travel in the state slots of ``theta`` and ``theta'``.
"""

from __future__ import annotations

import math

from isorock.physics.engine._layout import (
    _END,
    _FULL,
    _NEXT,
    CONTACT,
    F_DECIDED,
    F_K,
    F_NH,
    F_NSLIP,
    F_NSTEPS,
    F_REGIME,
    F_STALL,
    F_UPLIFTED,
    ISO_FP,
    P_HMAX,
    P_ISO,
    P_THR,
    P_VERT,
    REGIME,
    S_H,
    S_MAXU,
    S_OM,
    S_SIDE,
    S_SPEAK,
    S_T,
    S_TH,
    S_TMAX,
    S_TUP,
    S_U,
    S_V,
    S_Z,
    SLIDE,
    _record,
    njit_inner,
)
from isorock.physics.engine._model import (
    bw_phi,
    contact_A,
    fold_gravity,
    gravity_ratio,
    ground,
    rhs,
    segment,
    vertical_segment,
)
from isorock.physics.engine._numerics import _dp5_advance, dense, herm_extremum, herm_first_root


@njit_inner()
def _stop_tau(w, wn, k1w, knw, r5w, hstep, tau):
    """Fraction of the step where the slip rate ``s'`` reaches zero, refined on the continuous extension.

    ``tau`` is the Hermite estimate; a bracketed secant-bisection on the order-4 extension of
    ``s'`` (values ``w, wn`` [m/s], slopes ``k1w, knw`` [m/s^2], coefficient ``r5w``) returns a point
    on the far side of the zero (where the slip has stopped).
    """
    f = dense(w, wn, k1w, knw, r5w, hstep, tau)
    sg0 = w if w != 0.0 else k1w
    if f * sg0 > 0.0:
        lo, hi = tau, 1.0
    else:
        lo, hi = 0.0, tau
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        fm = dense(w, wn, k1w, knw, r5w, hstep, mid)
        if fm * sg0 > 0.0:
            lo = mid
        else:
            hi = mid
        if (hi - lo) * hstep < 1e-14:
            break
    return hi


@njit_inner(forceinline=True)
def _slip_step(t, u, v, x, w, z, sg, h, max_u, ts, te, typ, c0, c1, seg_h, P):
    """One Dormand-Prince step of a slip, ended where the slip rate ``s'`` returns to zero.

    ``t`` [s], base ``u`` [m] and ``u'`` [m/s], slip ``x`` [m] and its rate ``w`` [m/s], Bouc-Wen ``z``,
    slip direction ``sg``, proposed step ``h`` [s], peak ``|u|`` so far [m], the input segment and its
    largest step ``seg_h`` [s]. Returns the state at the end of the step, the next step, the peak
    ``|u|``, 1 if the segment's end was reached and whether the slip stopped there.
    """
    k1 = rhs(t, u, v, x, w, REGIME[SLIDE], sg, z, u, typ, c0, c1, ts, P)
    hstep = min(h, seg_h, te - t)
    yn, kn, r5, hstep, h = _dp5_advance(t, u, v, x, w, k1, hstep, REGIME[SLIDE], sg, z, typ, c0, c1, ts, P)
    un, vn, xn, wn = yn
    stop = False
    if sg * wn <= 0.0:
        # the slip rate returns to zero inside the step or at its end (its sign is that of sigma while
        # slipping): the first zero, from the Hermite cubic, refined on the continuous extension
        tau = herm_first_root(sg * w, sg * wn, sg * k1[3], sg * kn[3], hstep, 0.0, 1.0)
        if tau <= 0.0:
            tau = 1.0
        tau = _stop_tau(w, wn, k1[3], kn[3], r5[3], hstep, tau)
        un = dense(u, un, v, vn, r5[0], hstep, tau)
        vn2 = dense(v, vn, k1[1], kn[1], r5[1], hstep, tau)
        xn = dense(x, xn, w, wn, r5[2], hstep, tau)
        hstep = tau * hstep
        vn = vn2
        wn = 0.0
        stop = True
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
    return t, un, vn, xn, wn, z, h, max_u, k_inc, stop


@njit_inner(forceinline=True)
def _stick_or_reverse(t, u, v, z, sg, k, ekind, acc, P):
    """Where the slip rate is zero at ``t`` [s]: the object sticks if friction can carry it with its base
    (``|A| <= mu (g + a_v)``, the base's acceleration when stuck), else it slips back the other way.

    Returns ``(stuck, sigma, P)``, ``P`` carrying the vertical of the segment of ``t``.
    """
    ts, te, typ, c0, c1 = segment(k, ekind, acc, P)
    if P[P_VERT] != 0.0:
        P = vertical_segment(k, acc, P)
    A = contact_A(u, v, z, ground(t, typ, c0, c1, ts), P)
    if P[P_VERT] != 0.0 and P[P_ISO] != ISO_FP:
        A = A * gravity_ratio(t, P)
    if abs(A) <= P[P_THR]:
        return True, sg, P
    return False, (-1.0 if A > 0.0 else 1.0), P


@njit_inner()
def _sliding_phase(S, F, P, ekind, acc, H, hist_on):
    """Time loop of one slip (and of the slips that follow it without sticking), up to sticking or the
    end of the analysis.

    Parameters
    ----------
    S, F : numpy.ndarray
        Float and integer state, read at the start and written back at the end.
    P : tuple of float
        Parameter vector.
    ekind : int
        Excitation code.
    acc : numpy.ndarray
        Record samples [m/s^2]: row 0 the horizontal, row 1 the vertical when there is one.
    H : numpy.ndarray
        History buffer (6 x capacity): rows t, u, s, regime, u', s' in this mode.
    hist_on : bool
        Store the time histories.

    Returns
    -------
    int
        ``_NEXT`` when the object sticks, ``_END`` at the end of the analysis, ``_FULL`` when ``H`` is full.
    """
    t_max = S[S_TMAX]
    t, u, v, x, w, z, sg, h = S[S_T], S[S_U], S[S_V], S[S_TH], S[S_OM], S[S_Z], S[S_SIDE], S[S_H]
    max_u, max_x = S[S_MAXU], S[S_SPEAK]
    k, nsteps, nh = F[F_K], F[F_NSTEPS], F[F_NH]
    vert = P[P_VERT] != 0.0
    regime = SLIDE
    code = _NEXT
    t_start = t
    while True:
        if hist_on and nh >= H.shape[1]:
            code = _FULL
            break
        # the segment lookup is written out in each regime loop, as in _contact and _rocking: a shared
        # helper (a loop of its own) made the rocking analysis of a record 13 % slower (bench_engine)
        ts, te, typ, c0, c1 = segment(k, ekind, acc, P)
        if t >= te:
            k += 1
            continue
        if vert:
            P = vertical_segment(k, acc, P)
            fold_gravity(S, ts, te, P)
        seg_h = P[P_HMAX]
        if te - ts < seg_h:
            seg_h = te - ts
        t, u, v, x, w, z, h, max_u, k_inc, stop = _slip_step(
            t, u, v, x, w, z, sg, h, max_u, ts, te, typ, c0, c1, seg_h, P
        )
        k += k_inc
        nsteps += 1
        # s is monotone while slipping (s' keeps the sign of sigma): its peak is at a step end
        if abs(x) > max_x:
            max_x = abs(x)
        if abs(u) > max_u:
            max_u = abs(u)
        if stop:
            stuck, sg_new, P = _stick_or_reverse(t, u, v, z, sg, k, ekind, acc, P)
            # a slip that ends where it (or its last reversal) began: the input grazes the threshold
            # (|A| = mu g to round-off), where the object cannot slip; it sticks, and the contact loop
            # stops starting slips there after 1000 of them in a row (as impacts while rocking)
            idle = t - t_start <= 1e-12 * max(1.0, t)
            if stuck or idle:
                regime = CONTACT
                F[F_STALL] = F[F_STALL] + 1 if idle else 0
                if idle and t_start == S[S_T]:
                    # no slip happened: it is not counted (nor is its instant the first slip's), and
                    # the round-off it moved (1e-37 m) is undone
                    x, max_x = S[S_TH], S[S_SPEAK]
                    F[F_NSLIP] -= 1
                    if F[F_NSLIP] == 0:
                        F[F_UPLIFTED] = 0
                        S[S_TUP] = math.nan
            else:
                sg = sg_new
                t_start = t
        if hist_on:
            _record(H, nh, t, u, x, regime, v, w)
            nh += 1
        if regime == CONTACT:
            break
        if t >= t_max:
            F[F_DECIDED] = 0
            code = _END
            break
    F[F_REGIME] = regime
    S[S_T], S[S_U], S[S_V], S[S_TH], S[S_OM], S[S_Z], S[S_SIDE], S[S_H] = t, u, v, x, w, z, sg, h
    S[S_MAXU], S[S_SPEAK] = max_u, max_x
    F[F_K], F[F_NSTEPS], F[F_NH] = k, nsteps, nh
    return code
