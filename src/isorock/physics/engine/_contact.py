"""The full-contact regime loop of the kernel and its step functions: uplift test, decisions in free
vibration, the block on the ground, the exact linear-isolator step and the Dormand-Prince step."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from isorock.physics.engine._layout import (
    _END,
    _FULL,
    _NEXT,
    CONTACT,
    EXC_RECORD,
    F_DECIDED,
    F_K,
    F_NH,
    F_NSLIP,
    F_NSTALL,
    F_NSTEPS,
    F_REGIME,
    F_STALL,
    F_UPLIFTED,
    ISO_FP,
    ISO_LINEAR,
    ISO_NONE,
    P_AV1,
    P_CB,
    P_DT,
    P_EARLY,
    P_G,
    P_HMAX,
    P_ISO,
    P_KB,
    P_MU,
    P_NOUPLIFT,
    P_SLIDE,
    P_STOPUP,
    P_TB,
    P_THR,
    P_THRN,
    P_VERT,
    REGIME,
    ROCKING,
    S_EALPHA,
    S_H,
    S_HCON,
    S_HLIN,
    S_MAXA,
    S_MAXU,
    S_OM,
    S_SIDE,
    S_T,
    S_TEND,
    S_TEXC,
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
    energy,
    fold_gravity,
    grav,
    gravity_ratio,
    ground,
    iso_force,
    lin_exact,
    no_more_uplift,
    noniso_uplift_time,
    noniso_uplift_time_vertical,
    over_threshold,
    rhs,
    segment,
    threshold_of,
    vertical_segment,
)
from isorock.physics.engine._numerics import _dp5_advance, dp5_step, herm, herm_extremum
from isorock.physics.engine._series import (
    NT,
    Z_ZERO,
    first_root,
    fp_coefficients,
    fp_direction,
    fp_step_length,
    poly,
    poly2,
)

# ---------------------------------------------------------------- full contact
_H_GRAZE = 1e-9
"""Shortest contact step cut at a predicted uplift [s] (zero-progress guard at a grazing threshold)."""


@njit_inner(forceinline=True)
def _uplift_check(t, u, v, z, typ, c0, c1, ts, max_A, stall, P):
    """Uplift check in full contact at ``t`` [s] (docs/model.md §5), with the peak of ``|A|`` [m/s^2].

    ``s theta''(0+) > 0`` exactly when ``s A < -g tan(alpha)``; it is checked on the equations
    themselves so that round-off at ``|A| = g tan(alpha)`` cannot start a zero-length excursion.
    No uplift in the ``no_uplift`` mode, nor once ``stall`` has counted 1000 impacts in a row at the
    time of the previous event (zero-progress guard).

    The peak of ``|A|`` is that of the block in full contact: at an uplift it takes at most the
    threshold ``g tan(alpha)``, the most that full contact holds (an input that jumps past it, as a
    rectangular pulse, meets a rocking block, whose reactions the rocking loop evaluates).

    Returns
    -------
    up : bool
        The block uplifts at ``t``.
    s_up : float
        Rocking side of that uplift.
    max_A : float
        Peak ``|A|`` in full contact so far [m/s^2].
    refused : bool
        The block would uplift but the zero-progress guard refused it (counted as a stall).
    """
    ag = ground(t, typ, c0, c1, ts)
    A = contact_A(u, v, z, ag, P)
    if P[P_VERT] != 0.0 and (int(P[P_ISO]) != ISO_FP or grav(t, P) <= 0.0):
        # under a vertical input the threshold is (g + a_v) tan(alpha) (or mu (g + a_v)): compare
        # A g / (g + a_v) with the constant one (the FP's force already follows g + a_v, so it is
        # compared as it is, until g + a_v <= 0 lifts the block off: a huge factor then)
        A = A * gravity_ratio(t, P)
    s_up = -1.0 if A > 0.0 else 1.0
    no_uplift_mode = P[P_NOUPLIFT] != 0.0
    up = False
    refused = False
    a_rec = abs(A)
    if over_threshold(A, P) and not no_uplift_mode:
        # the motion that would start: rocking, or slipping in the sliding mode (docs/model.md §16)
        rg = SLIDE if P[P_SLIDE] != 0.0 else ROCKING
        d0 = rhs(t, u, v, 0.0, 0.0, rg, s_up, z, u, typ, c0, c1, ts, P)
        up = s_up * d0[3] > 0.0 or int(P[P_ISO]) == ISO_NONE
        if up and stall >= 1000:
            up = False
            refused = True
        if up:
            a_rec = threshold_of(A, P)
    if a_rec > max_A:
        max_A = a_rec
    return up, s_up, max_A, refused


@njit_inner(forceinline=True)
def _contact_decision(t, u, v, z, max_u, max_A, uplifted, hist_on, t_end, t_max, ealpha, P):
    """Free-vibration decisions in full contact once the input has ended (docs/model.md §9).

    Stop for a block on the ground, for a certain 'rocking' outcome (early stop: contact energy
    below ``E_alpha`` [J/kg]), when no further uplift is possible (energy bound of
    :func:`no_more_uplift`) and nothing reported can change (a full run: neither the peak ``|u|``
    nor the peak ``|A|``, hence ``mu_required``), or at the time limits ``t_end``, ``t_max`` [s].

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
    if early and uplifted and energy(u, v, 0.0, 0.0, z, 1.0, REGIME[CONTACT], P) < ealpha:
        # the outcome is 'rocking' and the block can never reach |theta| = alpha again
        return True, True
    # (a body with two thresholds can lift off no more once |A| stays below the smaller)
    thr_b = max_A * (1.0 + 1e-12) if no_uplift_mode else min(P[P_THR], P[P_THRN])
    if no_more_uplift(u, v, z, P, thr_b):
        if early:
            return True, True
        # a full run also reports the peak |A| (the friction demand mu_required = |A|_max / g):
        # it ends once |A| can no longer exceed its peak either (for the FP isolator, whose bound
        # never drops below mu_b g, two isolation periods after the tail, as below)
        a_done = (
            no_uplift_mode
            or thr_b <= max_A
            or no_more_uplift(u, v, z, P, max_A * (1.0 + 1e-12))
            or (iso == ISO_FP and t >= t_end + 2.0 * P[P_TB])
        )
        if a_done:
            if t >= t_end:
                return True, True
            # nothing reported can change any more: no uplift, |A| and |u| stay below their peaks
            # (|u| <= sqrt(2 e / k) with the energy e non-increasing in free vibration)
            if not hist_on and not no_uplift_mode:
                e_c = energy(u, v, 0.0, 0.0, z, 1.0, REGIME[CONTACT], P)
                if math.sqrt(2.0 * e_c / P[P_KB]) <= max_u:
                    return True, True
        if t >= t_max:
            return True, True  # no uplift can come: the outcome is decided
    if iso == ISO_FP and t >= t_end + 2.0 * P[P_TB]:
        return True, True
    if t >= t_max:
        return True, False
    return False, True


@njit_inner(forceinline=True)
def _contact_noniso(t, ts, te, typ, c0, c1, max_A, P):
    """Non-isolated block in contact: jump to the uplift instant on the segment, or to its end.

    Nothing moves, so nothing is integrated: the uplift time is found in closed form
    (:func:`noniso_uplift_time`) and the peak ``|x_g''|`` [m/s^2] over the part of the segment run
    in full contact, from ``t`` on, is recorded (up to an uplift: the uplift test records it there).

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
    vert = P[P_VERT] != 0.0
    if not no_uplift_mode:
        if vert:
            tu = noniso_uplift_time_vertical(t, te, c0, c1, ts, P)
        else:
            tu = noniso_uplift_time(t, te, typ, c0, c1, ts, P[P_THR], P[P_THRN])
    if tu < te:
        # uplift at the next pass (|A| >= thr there, strictly above right after)
        ag = ground(tu, typ, c0, c1, ts)
        return tu, -1.0 if ag > 0.0 else 1.0, True, max_A
    if te == math.inf:
        amx = abs(c0)  # the zero tail (c0 = c1 = 0)
    elif vert:
        # |x_g''| g / (g + a_v), a ratio of linear functions: monotone, its peak at an end
        amx = max(
            abs(ground(t, typ, c0, c1, ts)) * gravity_ratio(t, P),
            abs(ground(te, typ, c0, c1, ts)) * gravity_ratio(te, P),
        )
    else:
        amx = max(abs(ground(t, typ, c0, c1, ts)), abs(ground(te, typ, c0, c1, ts)))
        if typ == 1:
            # a crest of c0 sin(c1 t) at (k + 1/2) pi / c1 inside [t, te]
            kc = math.ceil(t * c1 / math.pi - 0.5)
            if (kc + 0.5) * math.pi / c1 <= te:
                amx = abs(c0)
    if amx > max_A:
        max_A = amx
    return te, 1.0, False, max_A


@njit_inner()
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


@njit_inner()
def _lin_uplift_time(u, v, ag0, c1, hstep, scan, P):
    """First instant [s] inside an exact linear step at which ``A`` passes an uplift threshold
    (:func:`over_threshold`).

    With ``scan`` a 64-point scan first brackets the crossing (``|A|`` rises above ``thr`` before an
    interior extremum); then bisection on the closed form. Returns the upper end of the final
    bracket, where ``|A| > thr`` holds.
    """
    tau_lo = 0.0
    tau_hi = hstep
    if scan:
        for j in range(1, 65):
            um, vm = lin_exact(u, v, ag0, c1, hstep * j / 64.0, P)
            if over_threshold(-(P[P_KB] * um + P[P_CB] * vm), P):
                tau_hi = hstep * j / 64.0
                break
            tau_lo = hstep * j / 64.0
    for _ in range(80):
        mid = 0.5 * (tau_lo + tau_hi)
        um, vm = lin_exact(u, v, ag0, c1, mid, P)
        if over_threshold(-(P[P_KB] * um + P[P_CB] * vm), P):
            tau_hi = mid
        else:
            tau_lo = mid
        if tau_hi - tau_lo < 1e-13:
            break
    return tau_hi


@njit_inner(forceinline=True)
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
    Am = 0.0
    if dA0 * dA1 < 0.0:
        # interior extremum of A (cubic Hermite, error O(h^4); exact bisection for the peak
        # itself when the uplift amplitude is being measured)
        if no_uplift_mode:
            Am = _lin_peak_A(u, v, ag0, c1, hstep, dA0, P)
        else:
            Am = herm_extremum(A0, A1, dA0, dA1, hstep)
        if over_threshold(Am, P):
            # the first point where A passes a threshold lies before the extremum: bracket it by a scan
            hit = True
            scan = True
    if over_threshold(A1, P):
        hit = True
    if hit and not no_uplift_mode:
        hstep = _lin_uplift_time(u, v, ag0, c1, hstep, scan, P)
        un, vn = lin_exact(u, v, ag0, c1, hstep, P)
        # the step ends where A reaches a threshold: that is its peak in full contact (the extremum
        # and the end value above belong to the uncut step)
        Am = threshold_of(-(P[P_KB] * un + P[P_CB] * vn), P)
        A1 = Am
    if abs(Am) > max_A:
        max_A = abs(Am)
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


@njit_inner(forceinline=True)
def _contact_uplift_tau(u, v, z, un, vn, d0, d1, hstep, A0, A1, dA0, dA1, P):
    """Fraction of a Runge-Kutta contact step at which ``|A|`` first exceeds ``g tan(alpha)``; -1 if never.

    ``(u, v)``, ``(un, vn)`` [m, m/s] are the states at the ends of the step, ``d0, d1`` [m/s^2] the
    base accelerations there, ``hstep`` [s] the step and, for the linear isolator, ``A0, A1`` [m/s^2],
    ``dA0, dA1`` [m/s^3] the Hermite data of ``A``; ``z`` is the Bouc-Wen variable at the start.
    A 16-point scan on the Hermite cubics, then bisection.
    """
    iso = int(P[P_ISO])
    hit = -1.0
    hit_lo = 0.0
    if iso == ISO_LINEAR:
        for j in range(1, 17):
            tau = j / 16.0
            if over_threshold(herm(A0, A1, dA0, dA1, hstep, tau), P):
                hit = tau
                hit_lo = tau - 1.0 / 16.0
                break
    elif P[P_KB] * (max(abs(u), abs(un)) + abs(un - u)) + P[P_MU] * P[P_G] > min(P[P_THR], P[P_THRN]):
        # FP: |A| <= kb |u| + mu g, so only steps that can reach the threshold are searched
        for j in range(1, 17):
            tau = j / 16.0
            uu = herm(u, un, v, vn, hstep, tau)
            vv = herm(v, vn, d0, d1, hstep, tau)
            zz = bw_phi(z, uu - u, P)
            if over_threshold(-iso_force(uu, vv, zz, P), P):
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
            Amid = -iso_force(uu, vv, bw_phi(z, uu - u, P), P)
        if over_threshold(Amid, P):
            hi = mid
        else:
            lo = mid
        if (hi - lo) * hstep < 1e-13:
            break
    return hi


@njit_inner(forceinline=True)
def _reduced(A, dA, t, P):
    """``A g / (g + a_v)`` [m/s^2] and its time derivative [m/s^3] from ``A`` and ``A'`` at ``t``."""
    ge = grav(t, P)
    r = gravity_ratio(t, P)
    return A * r, (dA - A * P[P_AV1] / max(ge, 1e-9 * P[P_G])) * r


@njit_inner(forceinline=True)
def _contact_step_end(t, hstep, te, u, un, v, vn, zn, max_u, max_A, P):
    """End of a contact step of ``hstep`` [s] from ``t`` to the state ``(un, vn, zn)``: the new time
    (snapped to the segment end ``te``), the peaks of ``|u|`` [m] (an interior one where ``u'``
    changed sign) and of ``|A|`` [m/s^2] at the end, and 1 if the segment end was reached."""
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
    if P[P_VERT] != 0.0 and int(P[P_ISO]) == ISO_LINEAR:
        Ae = Ae * gravity_ratio(t, P)
    if Ae > max_A:
        max_A = Ae
    return t, max_u, max_A, k_inc


@njit_inner(forceinline=True)
def _contact_dp5(t, u, v, z, s, h, max_u, max_A, ts, te, typ, c0, c1, seg_h, h_con, graze, P):
    """Runge-Kutta contact step (FP isolator, or linear isolator under a sine pulse).

    The step (at most ``h_con`` [s]) is cut at the uplift instant; the peaks of ``|A|`` and ``|u|``
    inside it are recorded. ``graze`` is true when the previous step was a cut shorter than
    ``_H_GRAZE`` [s]: another such cut is then lengthened to ``_H_GRAZE``.

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
    tiny : bool
        The step was cut at a predicted uplift less than ``_H_GRAZE`` after its start.
    """
    iso = int(P[P_ISO])
    no_uplift_mode = P[P_NOUPLIFT] != 0.0
    tiny = False
    hstep = min(h, seg_h, te - t, h_con)
    k1 = rhs(t, u, v, 0.0, 0.0, REGIME[CONTACT], s, z, u, typ, c0, c1, ts, P)
    yn, kn, r5, hstep, h = _dp5_advance(
        t, u, v, 0.0, 0.0, k1, hstep, REGIME[CONTACT], s, z, typ, c0, c1, ts, P
    )
    un = yn[0]
    vn = yn[1]
    A0 = 0.0
    A1 = 0.0
    dA0 = 0.0
    dA1 = 0.0
    Am = 0.0
    Am_signed = 0.0
    if iso == ISO_LINEAR:
        A0 = -(P[P_KB] * u + P[P_CB] * v)
        A1 = -(P[P_KB] * un + P[P_CB] * vn)
        dA0 = -(P[P_KB] * v + P[P_CB] * k1[1])
        dA1 = -(P[P_KB] * vn + P[P_CB] * kn[1])
        if P[P_VERT] != 0.0:
            # the Hermite data of A g / (g + a_v), compared with the constant threshold
            A0, dA0 = _reduced(A0, dA0, t, P)
            A1, dA1 = _reduced(A1, dA1, t + hstep, P)
        if dA0 * dA1 < 0.0:
            Am_signed = herm_extremum(A0, A1, dA0, dA1, hstep)
            Am = abs(Am_signed)
    # uplift inside the step?
    if not no_uplift_mode:
        hit = _contact_uplift_tau(u, v, z, un, vn, k1[1], kn[1], hstep, A0, A1, dA0, dA1, P)
        if hit > 0.0 and Am > threshold_of(Am_signed, P):
            # the step is cut where A reaches the threshold, before the extremum: that is its
            # peak in full contact
            Am = threshold_of(Am_signed, P)
        if hit > 0.0 and hit * hstep < _H_GRAZE:
            # a second cut in a row closer than _H_GRAZE to the start is a grazing threshold (|A|
            # within round-off of g tan(alpha), never above it after the cut): the step is cut at
            # _H_GRAZE instead, so the loop makes progress; a genuine crossing is then caught by
            # the next uplift check
            if graze:
                hit = min(1.0, _H_GRAZE / hstep)
            tiny = True
        if hit > 0.0:
            hstep = hit * hstep
            yn, kn, err, r5 = dp5_step(
                t, u, v, 0.0, 0.0, k1, hstep, REGIME[CONTACT], s, z, u, typ, c0, c1, ts, P
            )
            un = yn[0]
            vn = yn[1]
    if Am > max_A:
        max_A = Am
    zn = bw_phi(z, un - u, P) if iso == ISO_FP else 0.0
    t, max_u, max_A, k_inc = _contact_step_end(t, hstep, te, u, un, v, vn, zn, max_u, max_A, P)
    return t, un, vn, zn, h, max_u, max_A, k_inc, tiny


@njit_inner(forceinline=True)
def _contact_fp_series(t, u, v, z, max_u, max_A, ts, te, c0, c1, seg_h, h_con, graze, C, P):
    """Taylor-series contact step of the FP isolator on a linear-in-time input (:mod:`._series`).

    The step is as long as the input segment allows (at most ``seg_h`` and ``h_con`` [s]) and the
    series' tolerance admits; it is cut where ``u'`` reverses, where the Bouc-Wen variable crosses
    zero and at the uplift instant (as :func:`_contact_dp5`, whose ``graze`` rule it shares). ``C``
    is the series' work array.

    Returns
    -------
    t, u, v, z : float
        Time [s], base displacement [m] and velocity [m/s], Bouc-Wen variable at the end of the step.
    h : float
        Length of the step taken [s] (a first guess for a Runge-Kutta step after it).
    max_u, max_A : float
        Peaks of ``|u|`` [m] and ``|A|`` [m/s^2] so far (``|A|`` peaks where ``u'`` reverses: at step ends).
    k_inc : int
        1 if the step reached the end of the input segment.
    tiny : bool
        The step was cut at a predicted uplift less than ``_H_GRAZE`` after its start.
    """
    no_uplift_mode = P[P_NOUPLIFT] != 0.0
    tiny = False
    ag0 = c0 + c1 * (t - ts)
    a0 = -ag0 - iso_force(u, v, z, P)  # base acceleration relative to the ground [m/s^2]
    d = fp_direction(v, a0)
    fp_coefficients(u, v, z, ag0, c1, d, C, P)
    hstep = fp_step_length(C, min(seg_h, te - t, h_con), P)
    un, vn = poly2(C, hstep)
    cut = False
    # a reversal of u' ends the step (the hysteresis law changes branch there)
    if vn * d < 0.0:
        if v * d > 0.0:
            tau = first_root(C[1], hstep)
            if tau > 1e-12:
                hstep = tau
                cut = True
        else:
            # v starts at a round-off remainder of the other sign: shorten until it keeps its sign
            for _ in range(40):
                hstep *= 0.5
                if poly(C[1], hstep) * d >= 0.0:
                    break
            cut = True
    # so does a zero of the Bouc-Wen variable while unloading (the law's coefficient changes there)
    if d * z < -Z_ZERO and poly(C[2], hstep) * z <= 0.0:
        tau = first_root(C[2], hstep)
        if tau > 1e-12:
            hstep = tau
            cut = True
    if cut:
        un, vn = poly2(C, hstep)
    zn = bw_phi(z, un - u, P)
    fn = iso_force(un, vn, zn, P)
    if not no_uplift_mode and over_threshold(-fn, P):
        # |A| = |kb u + mu g Z| is monotone on the step (u is, and Z rises with u): it exceeds
        # g tan(alpha) first where the series of kb u + mu g Z - sign thr changes sign (row 3)
        sg = 1.0 if fn > 0.0 else -1.0
        kb = P[P_KB]
        mug = P[P_MU] * P[P_G]
        for j in range(NT + 1):
            C[3, j] = kb * C[0, j] + mug * C[2, j]
        # (f_b > 0 is a negative A: the threshold P_THRN of the right edge)
        C[3, 0] -= sg * (P[P_THRN] if sg > 0.0 else P[P_THR])
        # at the start |A| is at the threshold within round-off (the uplift test said no): the step
        # is cut _H_GRAZE after it, where |A| is above it
        tau = 0.0 if C[3, 0] * sg >= 0.0 else first_root(C[3], hstep)
        if tau < hstep:
            if tau < _H_GRAZE:
                # a cut this close to the start is a grazing threshold (see _contact_dp5)
                if graze or tau <= 0.0:
                    tau = min(hstep, _H_GRAZE)
                tiny = True
            hstep = tau
            un, vn = poly2(C, hstep)
            zn = bw_phi(z, un - u, P)
    t, max_u, max_A, k_inc = _contact_step_end(t, hstep, te, u, un, v, vn, zn, max_u, max_A, P)
    return t, un, vn, zn, hstep, max_u, max_A, k_inc, tiny


@njit(inline="always")
def _contact_loop(S, F, P, ekind, acc, Mrec, H, hist_on, iso):
    """Time loop in full contact, up to an uplift or the end of the analysis.

    At each pass: peak of ``|A|``, uplift check (docs/model.md §5), free-vibration decisions once
    the input has ended, then one step: closed form for the block on the ground, exact step of the
    linear isolator on a linear-in-time input, Taylor series of the friction pendulum on a
    linear-in-time input, Runge-Kutta otherwise.

    ``iso`` is the isolation model (``ISO_*``), a constant of the caller: the loop is inlined in numba's
    IR into one function per model (:func:`_contact_phase_linear`, ...), where numba drops the steps
    of the other models before it types them, so that an analysis compiles only the steps of its own
    model (the friction pendulum's series, the closed form of the fixed base).

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
    Mrec : numpy.ndarray
        Transition matrix of the exact linear step over one record sample.
    H : numpy.ndarray
        History buffer (6 x capacity), filled from column ``F[F_NH]`` on.
    hist_on : bool
        Store the time histories.
    iso : int
        Isolation model (``ISO_*``): a constant, equal to ``P[P_ISO]``.

    Returns
    -------
    int
        ``_NEXT`` at an uplift, ``_END`` at the end of the analysis, ``_FULL`` when ``H`` is full.
    """
    t_exc, t_end, t_max, ealpha = S[S_TEXC], S[S_TEND], S[S_TMAX], S[S_EALPHA]
    h_lin, h_con = S[S_HLIN], S[S_HCON]
    t, u, v, z, s, h = S[S_T], S[S_U], S[S_V], S[S_Z], S[S_SIDE], S[S_H]
    max_u, max_A = S[S_MAXU], S[S_MAXA]
    k, nsteps, stall, nh = F[F_K], F[F_NSTEPS], F[F_STALL], F[F_NH]
    uplifted = F[F_UPLIFTED] != 0
    vert = P[P_VERT] != 0.0
    # the theta row of the histories: 0 in full contact, the slip (constant while it sticks) when sliding
    x_hist = S[S_TH]
    # False, but not a literal: a literal False would have numba compile the step functions twice
    # (for Literal[bool](False) and for bool), seconds of the first compilation
    graze = nsteps < 0
    C = np.empty((5, NT + 1))  # work array of the FP isolator's series step
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
            fold_gravity(S, ts, te, P)
        seg_h = P[P_HMAX]
        if te - ts < seg_h:
            seg_h = te - ts
        up, s_up, max_A, refused = _uplift_check(t, u, v, z, typ, c0, c1, ts, max_A, stall, P)
        if refused:
            F[F_NSTALL] += 1
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
            t_was = t
            t, s_up, up, max_A = _contact_noniso(t, ts, te, typ, c0, c1, max_A, P)
            if up and t == t_was and stall >= 1000:
                # zero-progress guard: 1000 motions in a row started and ended at this instant (an
                # input that grazes the threshold); no start is tested again before the segment's end
                up = False
                F[F_NSTALL] += 1
                t = te
            if up:
                nsteps += 1
                break
            if t == math.inf:
                code = _END
                break
            k += 1  # t = te: on to the next segment
            continue
        if iso == ISO_LINEAR and typ == 0 and not vert:
            t, u, v, max_u, max_A, k_inc = _contact_linear_exact(
                t, u, v, max_u, max_A, ts, te, c0, c1, ekind, Mrec, h_lin, P
            )
            graze = nsteps < 0
        elif iso == ISO_FP and typ == 0 and not vert:
            t, u, v, z, h, max_u, max_A, k_inc, graze = _contact_fp_series(
                t, u, v, z, max_u, max_A, ts, te, c0, c1, seg_h, h_con, graze, C, P
            )
        else:
            t, u, v, z, h, max_u, max_A, k_inc, graze = _contact_dp5(
                t, u, v, z, s, h, max_u, max_A, ts, te, typ, c0, c1, seg_h, h_con, graze, P
            )
        k += k_inc
        nsteps += 1
        stall = 0
        if hist_on:
            _record(H, nh, t, u, x_hist, REGIME[CONTACT], v, 0.0)
            nh += 1
    if up and P[P_SLIDE] != 0.0:
        # the object starts to slip in the direction s_up (its slip S_TH is kept: it accumulates)
        F[F_REGIME] = SLIDE
        F[F_NSLIP] += 1
        s = s_up
        S[S_OM] = 0.0
        if not uplifted:
            F[F_UPLIFTED] = 1
            S[S_TUP] = t  # the first slip
    elif up:
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


@njit_inner()
def _contact_phase_linear(S, F, P, ekind, acc, Mrec, H, hist_on):
    """:func:`_contact_loop` of the linear isolator."""
    return _contact_loop(S, F, P, ekind, acc, Mrec, H, hist_on, ISO_LINEAR)


@njit_inner()
def _contact_phase_fp(S, F, P, ekind, acc, Mrec, H, hist_on):
    """:func:`_contact_loop` of the friction pendulum."""
    return _contact_loop(S, F, P, ekind, acc, Mrec, H, hist_on, ISO_FP)


@njit_inner()
def _contact_phase_none(S, F, P, ekind, acc, Mrec, H, hist_on):
    """:func:`_contact_loop` of the fixed base."""
    return _contact_loop(S, F, P, ekind, acc, Mrec, H, hist_on, ISO_NONE)
