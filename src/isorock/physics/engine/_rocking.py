"""The rocking regime loop of the kernel and its step functions: the Dormand-Prince step with event
location, the impact map and the decisions in free vibration."""

from __future__ import annotations

import math

from isorock.physics.engine._layout import (
    _END,
    _FULL,
    _NEXT,
    CONTACT,
    F_CERTAIN,
    F_DECIDED,
    F_FSAL,
    F_K,
    F_NH,
    F_NIMP,
    F_NPK,
    F_NSTEPS,
    F_OVERTURNED,
    F_REGIME,
    F_STALL,
    HALF_PI,
    ISO_FP,
    P_ALPHA,
    P_ALPHAL,
    P_BETA1,
    P_BETA1L,
    P_BETA2,
    P_EARLY,
    P_EPS,
    P_EPSL,
    P_ETA,
    P_G,
    P_HMAX,
    P_ISO,
    P_P,
    P_PL,
    P_VERT,
    REGIME,
    ROCKING,
    S_AGLAST,
    S_EALPHA,
    S_EALPHAL,
    S_EALPHAR,
    S_H,
    S_KF,
    S_MAXTH,
    S_MAXU,
    S_MUFAR,
    S_MUREQ,
    S_NFAR,
    S_NMIN,
    S_OM,
    S_PKA,
    S_PKB,
    S_SIDE,
    S_T,
    S_TEXC,
    S_TH,
    S_TLAST,
    S_TMAX,
    S_TOV,
    S_U,
    S_V,
    S_Z,
    _record,
    njit_inner,
)
from isorock.physics.engine._model import bw_phi, energy, grav, ground, rhs, segment, side, vertical_segment
from isorock.physics.engine._numerics import (
    _dp5_advance,
    dense,
    herm,
    herm_extremum,
    herm_extremum_tau,
    herm_first_root,
)


# ---------------------------------------------------------------- rocking
@njit_inner(forceinline=True)
def _reactions(t, th, om, s, k, typ, c0, c1, ts, P):
    """Contact reactions of the rocking block at one instant (docs/model.md §15).

    With ``C``, ``S`` the coordinates of the centre of mass relative to the pivot (§2), the block's
    absolute acceleration gives the horizontal and normal forces per unit block mass:
    ``H = A + C theta'' + S theta'^2``, ``N = g + S theta'' - C theta'^2`` (``A`` [m/s^2] the total
    base acceleration ``x_g'' + u''``). ``t`` [s], ``th`` [rad], ``om`` [rad/s], side ``s``; ``k``
    is the derivative of ``(u, u', theta, theta')`` and ``typ, c0, c1, ts`` the input segment.

    Returns
    -------
    q : float
        ``|H| / N`` [-]; ``inf`` if ``N <= 0``: the block would jump and ``H / N`` is not defined.
    n : float
        ``N / g`` [-].
    """
    R, alpha, _ = side(s, P)
    phi = alpha - s * th
    C = R * math.cos(phi)
    Sg = s * R * math.sin(phi)
    A = ground(t, typ, c0, c1, ts) + k[1]
    hx = A + C * k[3] + Sg * om * om
    nz = grav(t, P) + Sg * k[3] - C * om * om
    q = math.inf if nz <= 0.0 else abs(hx) / nz
    return q, nz / P[P_G]


@njit_inner(forceinline=True)
def _fold(q, n, inside, mu_req, n_min, mu_far, n_far):
    """Fold the reactions ``q = |H| / N`` [-], ``n = N / g`` [-] of one instant into the peaks.

    The reactions within ``|theta| <= alpha`` (``inside``) go into ``mu_req, n_min``; those beyond are
    held apart in ``mu_far, n_far``, which are merged into the first when the block comes back within
    ``alpha`` (here) and dropped if it falls (by the caller): the fall after the last passage of
    ``|theta| = alpha`` is the overturning itself, not a motion the model must hold.

    Returns
    -------
    mu_req, n_min, mu_far, n_far : float
        The peaks of ``|H| / N`` [-] and the least ``N / g`` [-] within and beyond ``alpha``.
    """
    if inside:
        if mu_far > mu_req:
            mu_req = mu_far
        if n_far < n_min:
            n_min = n_far
        mu_far, n_far = 0.0, 1.0
        if q > mu_req:
            mu_req = q
        if n < n_min:
            n_min = n
    else:
        if q > mu_far:
            mu_far = q
        if n < n_far:
            n_far = n
    return mu_req, n_min, mu_far, n_far


@njit_inner(forceinline=True)
def _vertex(ta, ya, tb, yb, tc, yc, sg):
    """Extreme value of the parabola through three consecutive samples ``(t, y)`` of a smooth function.

    Used where the middle sample is the largest (``sg = 1``) or the smallest (``sg = -1``) of the
    three: the parabola's vertex, which then lies in ``[ta, tc]`` [s], estimates the peak between the
    samples. Returns ``yb`` otherwise, or where one interval is under 1e-3 of the other (a step
    shortened to reach a segment end: its divided difference would be dominated by round-off).
    """
    ha = tb - ta
    hc = tc - tb
    if not (ha > 1e-3 * hc and hc > 1e-3 * ha):
        return yb
    if sg * (yb - ya) < 0.0 or sg * (yb - yc) < 0.0:
        return yb
    d1 = (yb - ya) / ha
    c2 = ((yc - yb) / hc - d1) / (ha + hc)
    if sg * c2 >= 0.0:
        return yb
    # p(t) = yb + d (t - tb) + c2 (t - tb)^2, with d = p'(tb)
    d = d1 + c2 * ha
    return yb - d * d / (4.0 * c2)


@njit_inner(forceinline=True)
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
        tau = herm_first_root(sth0, sth1, s * om, s * omn, hstep, HALF_PI, 1.0)
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


@njit_inner()
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


@njit_inner(forceinline=True)
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
        Peaks of ``|theta|`` [rad] in the current excursion and of ``|u|`` [m] so far.
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
    t_a, u_a, v_a, om_a : float
        Time [s], base displacement [m] and velocity [m/s], rotation rate [rad/s] where ``|theta|``
        first crosses ``alpha`` inside the step (before an impact or overturning), from the
        continuous extension; ``t_a`` is NaN if it does not.
    """
    hstep = min(h, seg_h, te - t)
    yn, kn, r5, hstep, h = _dp5_advance(t, u, v, th, om, k1, hstep, REGIME[ROCKING], s, z, typ, c0, c1, ts, P)
    un, vn, thn, omn = yn
    event, tau_ev = _rocking_event(th, thn, om, omn, s, hstep)
    # first crossing of |theta| = alpha (the contact reactions are evaluated there, docs/model.md §15)
    _, alpha, _ = side(s, P)
    in0 = s * th <= alpha
    if event == 0:
        cross = in0 != (s * thn <= alpha)
        if not cross and s * om * (s * omn) < 0.0:
            # a turning point inside the step: out and back in (or in and back out) within it
            tx = herm_extremum_tau(s * th, s * thn, s * om, s * omn, hstep)
            if tx > 0.0:
                cross = in0 != (herm(s * th, s * thn, s * om, s * omn, hstep, tx) <= alpha)
        tmax = 1.0
    else:
        cross = in0 if event == 2 else not in0
        tmax = tau_ev
    t_a, u_a, v_a, om_a = math.nan, 0.0, 0.0, 0.0
    if cross:
        tau = herm_first_root(s * th, s * thn, s * om, s * omn, hstep, alpha, tmax)
        if tau > 0.0:
            t_a = t + tau * hstep
            u_a = dense(u, un, v, vn, r5[0], hstep, tau)
            v_a = dense(v, vn, k1[1], kn[1], r5[1], hstep, tau)
            om_a = dense(om, omn, k1[3], kn[3], r5[3], hstep, tau)
    if event == 2:
        # overturn: time from the dense output
        return 2, t + tau_ev * hstep, u, v, th, om, z, h, max_th, max_u, kn, 0, t_a, u_a, v_a, om_a
    if event == 1:
        un, vn, omn, hstep = _impact_state((u, v, th, om), yn, k1, kn, r5, hstep, tau_ev, alpha)
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
    return event, t, un, vn, thn, omn, z, h, max_th, max_u, kn, k_inc, t_a, u_a, v_a, om_a


@njit_inner()
def _impact(v, om, s, P):
    """Impact map at ``theta = 0`` (docs/model.md §7-§8).

    Restitution ``theta'+ = eps_s theta'-`` and the jump of the base velocity of an impact landing from
    side ``s`` (docs/model.md §18: the two differ for an asymmetric body); rocking ceases when
    ``|theta'+| < eta p_s alpha_s``, else it goes on about the other edge.

    Returns
    -------
    v, om, s : float
        Base velocity [m/s], rotation rate [rad/s] and rocking side after the impact.
    ceased : bool
        Rocking has ceased (full contact).
    """
    if s > 0.0:
        eps, beta1, p, alpha = P[P_EPS], P[P_BETA1], P[P_P], P[P_ALPHA]
    else:
        eps, beta1, p, alpha = P[P_EPSL], P[P_BETA1L], P[P_PL], P[P_ALPHAL]
    omp = eps * om
    if eps <= 0.0 or abs(omp) < P[P_ETA] * p * alpha:
        return v + P[P_BETA2] * om, 0.0, s, True
    return v + beta1 * om, omp, -s, False


@njit_inner(forceinline=True)
def _rocking_decision(t, u, v, th, om, z, s, certain_over, t_max, ealpha, ealpha_s, P):
    """Free-vibration decision while rocking once the input has ended (docs/model.md §9).

    Beyond ``alpha_s`` with the energy below that side's ``E_alpha`` (``ealpha_s`` [J/kg]) overturning
    is certain; within it and below the smaller ``E_alpha`` of the two sides (``ealpha``) the block can
    never overturn. An early stop ends the analysis there; a full run goes on until rocking ceases
    (complete impact count) or until ``t_max`` [s].

    Returns
    -------
    stop : bool
        End the analysis here.
    certain_over : bool
        Overturning is certain (now or at an earlier step, flag ``certain_over`` on input).
    decided : bool
        The outcome is decided (False only at ``t_max`` with the outcome still open).
    """
    e = energy(u, v, th, om, z, s, REGIME[ROCKING], P)
    early = P[P_EARLY] != 0.0
    safe = False
    _, alpha, _ = side(s, P)
    if s * th > alpha:
        if e < ealpha_s:
            certain_over = True
            if early:
                return True, certain_over, True
    elif e < ealpha:
        # can never overturn; a full run goes on until rocking ceases (complete impact count)
        safe = True
        if early:
            return True, certain_over, True
    if t >= t_max:
        return True, certain_over, safe or certain_over
    return False, certain_over, True


@njit_inner()
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
        Record samples [m/s^2]: row 0 the horizontal, row 1 the vertical when there is one.
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
    ealpha_r, ealpha_l = S[S_EALPHAR], S[S_EALPHAL]
    t, u, v, th, om, z, s, h = S[S_T], S[S_U], S[S_V], S[S_TH], S[S_OM], S[S_Z], S[S_SIDE], S[S_H]
    # the peak |theta| of the current excursion [rad], folded over its side's alpha into the peak of
    # |theta| / alpha_s (S_MAXTH) when the side changes and at the end (a quotient rounds monotonically:
    # for a uniform block this is the largest |theta| over alpha, bit for bit)
    max_n, max_u, t_last = S[S_MAXTH], S[S_MAXU], S[S_TLAST]
    max_th = 0.0
    # contact reactions (docs/model.md §15): sampled at every step end, at the start of a step that
    # does not continue the previous one, just before an impact and where |theta| crosses alpha;
    # between consecutive samples of one smooth stretch the peak is taken from the parabola through
    # the last three. Those beyond |theta| = alpha are held apart (see _fold).
    mu_req, n_min = S[S_MUREQ], S[S_NMIN]
    mu_far, n_far = S[S_MUFAR], S[S_NFAR]
    npk = F[F_NPK]
    ta, qa, na, ia, va = S[S_PKA], S[S_PKA + 1], S[S_PKA + 2], S[S_PKA + 3] != 0.0, S[S_PKA + 4]
    tb, qb, nb, ib, vb = S[S_PKB], S[S_PKB + 1], S[S_PKB + 2], S[S_PKB + 3] != 0.0, S[S_PKB + 4]
    fp = P[P_ISO] == ISO_FP
    vert = P[P_VERT] != 0.0
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
        if vert:
            P = vertical_segment(k, acc, P)
        # the slenderness angle of the side it rocks on (s changes at impacts only, after its uses)
        alpha = P[P_ALPHA] if s > 0.0 else P[P_ALPHAL]
        seg_h = P[P_HMAX]
        if te - ts < seg_h:
            seg_h = te - ts
        if fsal_ok and abs(ground(t, typ, c0, c1, ts) - ag_last) <= 1e-12 * (1.0 + abs(ag_last)):
            k1 = kf
        else:
            k1 = rhs(t, u, v, th, om, REGIME[ROCKING], s, z, u, typ, c0, c1, ts, P)
            # a step that does not continue the previous one (after an uplift, an impact, a jump of
            # the input) starts a new smooth stretch with the reactions at its start
            q, n = _reactions(t, th, om, s, k1, typ, c0, c1, ts, P)
            ins = abs(th) <= alpha
            mu_req, n_min, mu_far, n_far = _fold(q, n, ins, mu_req, n_min, mu_far, n_far)
            npk = 1
            tb, qb, nb, ib, vb = t, q, n, ins, v
        fsal_ok = False
        u0, z0 = u, z
        event, t, u, v, th, om, z, h, max_th, max_u, kn, k_inc, t_a, u_a, v_a, om_a = _rocking_step(
            t, u, v, th, om, z, s, h, max_th, max_u, k1, ts, te, typ, c0, c1, seg_h, P
        )
        k += k_inc
        nsteps += 1
        if t_a == t_a:
            # the step crosses |theta| = alpha: the reactions there (Bouc-Wen from the step's start)
            th_a = s * alpha
            ka = rhs(t_a, u_a, v_a, th_a, om_a, REGIME[ROCKING], s, z0, u0, typ, c0, c1, ts, P)
            q, n = _reactions(t_a, th_a, om_a, s, ka, typ, c0, c1, ts, P)
            mu_req, n_min, mu_far, n_far = _fold(q, n, True, mu_req, n_min, mu_far, n_far)
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
        else:
            # reactions just before the impact (the impulse itself is not a finite force)
            kn = rhs(t, u, v, th, om, REGIME[ROCKING], s, z, u, typ, c0, c1, ts, P)
        # the reactions at the end of the step, and the peak between it and the two samples before
        q, n = _reactions(t, th, om, s, kn, typ, c0, c1, ts, P)
        ins = abs(th) <= alpha
        mu_req, n_min, mu_far, n_far = _fold(q, n, ins, mu_req, n_min, mu_far, n_far)
        # (three samples of one smooth stretch, all on one side of |theta| = alpha; on the FP
        # isolator all with one sign of u', as Bouc-Wen changes branch where u' reverses)
        if npk >= 2 and ia == ins and ib == ins and (not fp or (va * vb > 0.0 and va * v > 0.0)):
            nv = _vertex(ta, na, tb, nb, t, n, -1.0)
            qv = qb
            if na > 0.0 and nb > 0.0 and n > 0.0:
                qv = _vertex(ta, qa, tb, qb, t, q, 1.0)
            mu_req, n_min, mu_far, n_far = _fold(qv, nv, ins, mu_req, n_min, mu_far, n_far)
        # at the end of an input segment the input may have a kink: a new stretch starts there
        npk = 1 if k_inc == 1 else min(npk + 1, 2)
        ta, qa, na, ia, va = tb, qb, nb, ib, vb
        tb, qb, nb, ib, vb = t, q, n, ins, v
        if event == 1:
            # zero-progress guard: an impact right at the previous event's time
            if t - t_last <= 1e-12 * max(1.0, t):
                stall += 1
            else:
                stall = 0
            t_last = t
            th = 0.0
            n_imp += 1
            if max_th / alpha > max_n:
                max_n = max_th / alpha
            max_th = 0.0
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
                t, u, v, th, om, z, s, certain_over, t_max, ealpha, ealpha_r if s > 0.0 else ealpha_l, P
            )
            if stop:
                F[F_DECIDED] = 1 if decided else 0
                code = _END
                break
    F[F_REGIME] = regime
    F[F_CERTAIN] = 1 if certain_over else 0
    S[S_T], S[S_U], S[S_V], S[S_TH], S[S_OM], S[S_Z], S[S_SIDE], S[S_H] = t, u, v, th, om, z, s, h
    alpha = P[P_ALPHA] if s > 0.0 else P[P_ALPHAL]
    if max_th / alpha > max_n:
        max_n = max_th / alpha
    S[S_MAXTH], S[S_MAXU], S[S_TLAST] = max_n, max_u, t_last
    if code != _FULL:
        # the block has come back (rocking ceased) or the run ends: the reactions beyond alpha are
        # kept unless it overturns (with a full history buffer the same motion goes on)
        if F[F_OVERTURNED] == 0 and not certain_over:
            mu_req, n_min = max(mu_req, mu_far), min(n_min, n_far)
        mu_far, n_far = 0.0, 1.0
    S[S_MUREQ], S[S_NMIN], S[S_MUFAR], S[S_NFAR] = mu_req, n_min, mu_far, n_far
    S[S_PKA], S[S_PKA + 1], S[S_PKA + 2], S[S_PKA + 3], S[S_PKA + 4] = ta, qa, na, 1.0 if ia else 0.0, va
    S[S_PKB], S[S_PKB + 1], S[S_PKB + 2], S[S_PKB + 3], S[S_PKB + 4] = tb, qb, nb, 1.0 if ib else 0.0, vb
    F[F_NPK] = npk
    F[F_K], F[F_NSTEPS], F[F_STALL], F[F_NH], F[F_NIMP] = k, nsteps, stall, nh, n_imp
    F[F_FSAL] = 1 if fsal_ok else 0
    S[S_KF], S[S_KF + 1], S[S_KF + 2], S[S_KF + 3] = kf
    S[S_AGLAST] = ag_last
    return code
