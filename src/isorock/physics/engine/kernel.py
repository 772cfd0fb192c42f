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
* Contact reactions (docs/model.md §15): ``|A|`` in full contact (capped at ``g tan(alpha)`` at an
  uplift); while rocking ``|H| / N`` and ``N`` at every step end, at the crossings of
  ``|theta| = alpha`` and before impacts, with the peak between samples from a parabola through three.
* Bouc-Wen: for a monotone base motion ``dZ/du = (1 - gamma Z|Z| - beta Z^2)/Y`` has a
  closed-form solution, so ``Z`` is an exact algebraic function of the base
  displacement within a step (``bw_phi``); steps end at every reversal of ``u'``.
  The stiff variable never enters the Runge-Kutta error control.
* Friction pendulum in full contact under a linear-in-time input (records, rectangular pulse,
  tail): a Taylor-series step of order 10 (``_series``) whose coefficients follow from a
  recurrence, as long as a record sample where the Runge-Kutta path needed several steps to follow
  the isolator's pre-yield oscillation; cut at reversals of ``u'``, at zeros of ``Z`` while
  unloading and at the uplift instant, ``Z`` taken from its closed form at the end of each step.

Code layout
-----------
:func:`run` sets an analysis up (:func:`_setup`), then alternates the regime loops (the contact loop
of its isolation model, :func:`_contact_phase_linear` and the like, and :func:`_rocking_phase`, or
:func:`_sliding_phase` in the sliding mode) until it ends, and assembles the result
(:func:`_finish`). Between the loops the state travels in two small arrays; inside a loop it is
held in scalars and advanced by the step functions (``_contact_*``, ``_rocking_*``), which are
inlined into the loops: called once per step with the 43-float parameter tuple they would cost
5-15 % of the run time. They are inlined by LLVM (``forceinline=True``), not in numba's IR
(``inline="always"``), which types every inlined copy again: the first compilation takes half the
time for the same machine code. Modules: ``_layout`` (parameter, result and state layouts, history
buffer), ``_model`` (the equations), ``_numerics`` (Dormand-Prince step, dense output, Hermite
helpers), ``_series`` (the friction pendulum's Taylor-series step in contact), ``_contact``,
``_rocking`` and ``_sliding`` (the regime loops), ``_cache`` (the compiled code's freshness); this
module sets up, runs and finishes an analysis.

What compiles when
------------------
numba compiles a function, and all it calls, at its first call; the whole engine took 20-40 s, all
of it waited for by the first analysis after an install. So :func:`simulate` compiles only what its
analysis runs: one entry point per isolation model and mode (``run_linear``, ``run_fp``,
``run_none`` and their ``_sliding`` twins, chosen by :func:`run`), in which numba drops the other
models' contact steps (the friction pendulum's series, the fixed base's closed form) and the loop of
the other mode before typing them (:func:`_analysis`, inlined in numba's IR with the model and mode
as constants). The regime loops and their steps are compiled once, cached, and shared by the entry
points and by the parallel batch kernel :func:`run_many`, which serves every model and mode. The
helpers that only compiled code calls have no Python entry point (``_layout.njit_inner``): their
wrappers, which convert the 43-float parameter tuple from and to Python objects, were about a fifth
of the compilation.

All state is per unit mass; see ``docs/model.md`` for the equations.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from isorock.physics.engine._contact import _contact_phase_fp, _contact_phase_linear, _contact_phase_none
from isorock.physics.engine._layout import (
    _END,
    _FULL,
    _NEXT,
    CONTACT,
    EXC_FULLSINE,
    EXC_HALFSINE,
    EXC_RECORD,
    EXC_RECT,
    F_CERTAIN,
    F_DECIDED,
    F_NH,
    F_NIMP,
    F_NSLIP,
    F_NSTALL,
    F_NSTEPS,
    F_OVERTURNED,
    F_REGIME,
    F_UPLIFTED,
    HALF_PI,
    ISO_FP,
    ISO_LINEAR,
    ISO_NONE,
    NF,
    NPAR,
    NRES,
    NS,
    P_ALPHA,
    P_ALPHAL,
    P_AMP,
    P_ATOL,
    P_AV0,
    P_AV1,
    P_AVTS,
    P_B,
    P_BETA1,
    P_BETA1L,
    P_BETA2,
    P_BWB,
    P_BWG,
    P_CB,
    P_DT,
    P_EARLY,
    P_EPS,
    P_EPSL,
    P_ETA,
    P_G,
    P_H,
    P_HMAX,
    P_I43,
    P_I43L,
    P_ISO,
    P_KAPPA,
    P_KB,
    P_MAXEXTRA,
    P_MU,
    P_MUO,
    P_NOUPLIFT,
    P_OM0,
    P_P,
    P_PL,
    P_R,
    P_RHO,
    P_RL,
    P_RTOL,
    P_SLIDE,
    P_STOPUP,
    P_TAIL,
    P_TB,
    P_TD,
    P_TH0,
    P_THR,
    P_THRN,
    P_VERT,
    P_WB,
    P_XI,
    P_Y,
    R_DECIDED,
    R_JUMPS,
    R_MAXA,
    R_MAXTH,
    R_MAXU,
    R_MUREQ,
    R_NIMP,
    R_NMIN,
    R_NSLIP,
    R_NSTEPS,
    R_OUTCOME,
    R_SPEAK,
    R_SRES,
    R_STALLS,
    R_TEND,
    R_TOV,
    R_TUP,
    ROCKING,
    S_EALPHA,
    S_EALPHAL,
    S_EALPHAR,
    S_H,
    S_HCON,
    S_HLIN,
    S_MAXA,
    S_MAXTH,
    S_MAXU,
    S_MUREQ,
    S_NFAR,
    S_NMIN,
    S_OM,
    S_SIDE,
    S_SPEAK,
    S_T,
    S_TEND,
    S_TEXC,
    S_TH,
    S_TLAST,
    S_TMAX,
    S_TOV,
    S_TUP,
    _grow,
    _record,
    njit_inner,
)
from isorock.physics.engine._model import e_alpha, lin_matrix
from isorock.physics.engine._rocking import _rocking_phase
from isorock.physics.engine._sliding import _sliding_phase

# the kernel's interface: run(), run_many() and the layout of their parameter and result vectors
__all__ = [
    "run",
    "run_many",
    "P_B",
    "P_H",
    "P_R",
    "P_ALPHA",
    "P_ALPHAL",
    "P_RL",
    "P_I43L",
    "P_PL",
    "P_EPSL",
    "P_BETA1L",
    "P_THRN",
    "P_P",
    "P_G",
    "P_KAPPA",
    "P_I43",
    "P_EPS",
    "P_BETA1",
    "P_BETA2",
    "P_ISO",
    "P_KB",
    "P_CB",
    "P_MU",
    "P_Y",
    "P_BWB",
    "P_BWG",
    "P_THR",
    "P_ETA",
    "P_RTOL",
    "P_ATOL",
    "P_TAIL",
    "P_MAXEXTRA",
    "P_EARLY",
    "P_STOPUP",
    "P_XI",
    "P_WB",
    "P_AMP",
    "P_TD",
    "P_DT",
    "P_HMAX",
    "P_NOUPLIFT",
    "P_TB",
    "P_TH0",
    "P_OM0",
    "P_MUO",
    "P_RHO",
    "P_SLIDE",
    "P_VERT",
    "P_AV0",
    "P_AV1",
    "P_AVTS",
    "NPAR",
    "ISO_NONE",
    "ISO_LINEAR",
    "ISO_FP",
    "EXC_RECT",
    "EXC_HALFSINE",
    "EXC_FULLSINE",
    "EXC_RECORD",
    "R_OUTCOME",
    "R_MAXTH",
    "R_NIMP",
    "R_MAXU",
    "R_TUP",
    "R_TOV",
    "R_TEND",
    "R_DECIDED",
    "R_NSTEPS",
    "R_MAXA",
    "R_STALLS",
    "R_MUREQ",
    "R_NMIN",
    "R_JUMPS",
    "R_NSLIP",
    "R_SPEAK",
    "R_SRES",
    "NRES",
]


# ---------------------------------------------------------------- set-up and results
@njit_inner()
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
        Parr[36],
        Parr[37],
        Parr[38],
        Parr[39],
        Parr[40],
        Parr[41],
        Parr[42],
        Parr[43],
        Parr[44],
        Parr[45],
        Parr[46],
        Parr[47],
        Parr[48],
        Parr[49],
    )


@njit_inner()
def _setup(P, ekind, acc, hist_on):
    """Initial state of an analysis: at rest in full contact, or rocking from ``(theta0, theta0')``.

    Parameters
    ----------
    P : tuple of float
        Parameter vector (``P_*`` layout).
    ekind : int
        Excitation code (``EXC_*``).
    acc : numpy.ndarray
        Record samples [m/s^2], row 0 the horizontal, row 1 the vertical (unused for a pulse).
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
        t_exc = (acc.shape[1] - 1) * P[P_DT]
    elif ekind == EXC_FULLSINE:
        t_exc = 2.0 * P[P_TD]
    else:
        t_exc = P[P_TD]
    t_end = t_exc + P[P_TAIL]
    S[S_TEXC] = t_exc
    S[S_TEND] = t_end
    S[S_TMAX] = t_end + P[P_MAXEXTRA]
    S[S_EALPHAR] = e_alpha(1.0, P)
    S[S_EALPHAL] = e_alpha(-1.0, P)
    S[S_EALPHA] = min(S[S_EALPHAR], S[S_EALPHAL])
    # record matrix for the exact contact step
    Mrec = np.zeros((2, 4))
    if iso == ISO_LINEAR and ekind == EXC_RECORD and P[P_VERT] == 0.0:
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
    S[S_MAXTH] = abs(th) / (P[P_ALPHA] if s > 0.0 else P[P_ALPHAL])
    S[S_TUP] = math.nan
    S[S_TOV] = math.nan
    S[S_TLAST] = -1.0
    S[S_MUREQ] = 0.0
    S[S_NMIN] = 1.0
    S[S_NFAR] = 1.0
    F[F_REGIME] = regime
    F[F_UPLIFTED] = 1 if regime == ROCKING else 0
    F[F_DECIDED] = 1

    # histories: rows t, u, theta, regime, u', theta'
    H = np.empty((6, 1024 if hist_on else 1))
    if hist_on:
        _record(H, F[F_NH], 0.0, 0.0, th, regime, 0.0, om)
        F[F_NH] = 1
    return S, F, Mrec, H


@njit_inner()
def _finish(S, F, P, H):
    """Result vector (``R_*`` layout) and the histories trimmed to the samples stored."""
    # the slenderness angle of the side of the last motion (that of the fall on overturning)
    alpha = P[P_ALPHA] if S[S_SIDE] > 0.0 else P[P_ALPHAL]
    res = np.zeros(NRES)
    if P[P_SLIDE] != 0.0:
        # sliding mode (docs/model.md §16): the block never lifts off; its slips are reported
        res[R_OUTCOME] = 0
        res[R_MAXTH] = 0.0
        res[R_NSLIP] = F[F_NSLIP]
        res[R_SPEAK] = S[S_SPEAK]
        res[R_SRES] = S[S_TH]
    elif F[F_OVERTURNED] != 0 or F[F_CERTAIN] != 0:
        res[R_OUTCOME] = 2
        res[R_MAXTH] = HALF_PI / alpha
    elif F[F_UPLIFTED] != 0:
        res[R_OUTCOME] = 1
        res[R_MAXTH] = S[S_MAXTH]
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
    res[R_STALLS] = F[F_NSTALL]
    # contact reactions: in full contact H / N = |A| / g and N = m g (docs/model.md §15); the
    # rocking part is infinite exactly when a sample had N <= 0, that is when the block jumps
    res[R_MUREQ] = max(S[S_MAXA] / P[P_G], S[S_MUREQ])
    res[R_NMIN] = S[S_NMIN]
    res[R_JUMPS] = 1.0 if S[S_NMIN] <= 0.0 else 0.0
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


# ---------------------------------------------------------------- the analysis
@njit(inline="always")
def _analysis(Parr, ekind, acc, hist_on, iso, sliding):
    """One analysis: alternate the contact loop and the rocking (or sliding) loop until it ends.

    Inlined in numba's IR into its callers. In an entry point (``run_linear`` ...) ``iso`` (``ISO_*``)
    and ``sliding`` are constants, and numba drops the branches of the other models and mode before
    it types them: the entry point compiles its own contact loop only, and the sliding loop only in
    the sliding mode. In :func:`run_many` they are read from each row, and every loop is called.
    """
    P = _param_tuple(Parr)
    S, F, Mrec, H = _setup(P, ekind, acc, hist_on)
    code = _NEXT
    while code != _END:
        if code == _FULL:
            H = _grow(H, F[F_NH])
        if F[F_REGIME] == CONTACT:
            if iso == ISO_LINEAR:
                code = _contact_phase_linear(S, F, P, ekind, acc, Mrec, H, hist_on)
            elif iso == ISO_FP:
                code = _contact_phase_fp(S, F, P, ekind, acc, Mrec, H, hist_on)
            else:
                code = _contact_phase_none(S, F, P, ekind, acc, Mrec, H, hist_on)
        elif sliding:
            # the sliding mode (P_SLIDE): contact and slipping, the block never rocks
            code = _sliding_phase(S, F, P, ekind, acc, H, hist_on)
        else:
            code = _rocking_phase(S, F, P, ekind, acc, H, hist_on)
    return _finish(S, F, P, H)


@njit(cache=True)
def run_linear(Parr, ekind, acc, hist_on):
    """:func:`run` for the linear isolator (rocking mode)."""
    return _analysis(Parr, ekind, acc, hist_on, ISO_LINEAR, False)


@njit(cache=True)
def run_fp(Parr, ekind, acc, hist_on):
    """:func:`run` for the friction pendulum (rocking mode)."""
    return _analysis(Parr, ekind, acc, hist_on, ISO_FP, False)


@njit(cache=True)
def run_none(Parr, ekind, acc, hist_on):
    """:func:`run` for the fixed base (rocking mode)."""
    return _analysis(Parr, ekind, acc, hist_on, ISO_NONE, False)


@njit(cache=True)
def run_linear_sliding(Parr, ekind, acc, hist_on):
    """:func:`run` for the linear isolator, sliding mode."""
    return _analysis(Parr, ekind, acc, hist_on, ISO_LINEAR, True)


@njit(cache=True)
def run_fp_sliding(Parr, ekind, acc, hist_on):
    """:func:`run` for the friction pendulum, sliding mode."""
    return _analysis(Parr, ekind, acc, hist_on, ISO_FP, True)


@njit(cache=True)
def run_none_sliding(Parr, ekind, acc, hist_on):
    """:func:`run` for the fixed base, sliding mode."""
    return _analysis(Parr, ekind, acc, hist_on, ISO_NONE, True)


@njit(cache=True, parallel=True)
def run_many(Ps, ekind, acc):
    """Run one analysis per row of ``Ps`` in parallel; returns the result vectors (rows x NRES).

    One kernel for every isolation model and mode, read from each row: it calls the regime loops
    that the entry points of :func:`run` compile (and cache). A kernel per entry point would be
    quicker to compile for one model, but six of them took 21 s, against 8 s for this one.
    """
    n = Ps.shape[0]
    out = np.empty((n, NRES))
    # False, but not a literal: the regime loops are then those compiled for simulate(), not second ones
    no_hist = n < 0
    for i in prange(n):
        Parr = Ps[i]
        res = _analysis(Parr, ekind, acc, no_hist, int(Parr[P_ISO]), Parr[P_SLIDE] != 0.0)[0]
        for j in range(NRES):
            out[i, j] = res[j]
    return out


_RUN = {
    (ISO_LINEAR, False): run_linear,
    (ISO_FP, False): run_fp,
    (ISO_NONE, False): run_none,
    (ISO_LINEAR, True): run_linear_sliding,
    (ISO_FP, True): run_fp_sliding,
    (ISO_NONE, True): run_none_sliding,
}
"""The compiled analysis of each (isolation model, sliding mode)."""


def _key(P) -> tuple[int, bool]:
    """The isolation model and mode of the parameter vector ``P``: the key of :data:`_RUN`."""
    return int(P[P_ISO]), bool(P[P_SLIDE] != 0.0)


def run(Parr, ekind, acc, hist_on):
    """Run one analysis: alternate the contact and rocking regime loops until the analysis ends.

    Calls the compiled entry point of the analysis's isolation model and mode (``P_ISO``,
    ``P_SLIDE``; :data:`_RUN`), which numba compiles at its first use.

    Parameters
    ----------
    Parr : numpy.ndarray
        Parameter vector (``NPAR`` floats, ``P_*`` layout; see
        :func:`isorock.physics.engine.pack_parameters`).
    ekind : int
        Excitation code (``EXC_*``).
    acc : numpy.ndarray
        Record samples [m/s^2] (``EXC_RECORD``; ignored for a pulse): row 0 the horizontal, row 1 the
        vertical when there is one (``P_VERT``).
    hist_on : bool
        Store the time histories at the integrator's steps.

    Returns
    -------
    res : numpy.ndarray
        Result vector (``NRES`` floats, ``R_*`` layout).
    t, u, theta, regime, u_dot, theta_dot : numpy.ndarray
        Histories [s, m, rad, -, m/s, rad/s] (empty unless ``hist_on``).
    """
    return _RUN[_key(Parr)](Parr, ekind, acc, hist_on)
