"""Layout of the kernel's arrays: the parameter vector, the result vector, the isolation and
excitation codes, and the state of an analysis carried between the two regime loops; the history
buffer; the decorator of the helpers that only compiled code calls (:func:`njit_inner`)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from numba.core import config
from numba.core.registry import CPUDispatcher

# ---------------------------------------------------------------- parameter vector layout
P_B, P_H, P_R, P_ALPHA, P_P, P_G, P_KAPPA, P_I43 = 0, 1, 2, 3, 4, 5, 6, 7
P_EPS, P_BETA1, P_BETA2, P_ISO, P_KB, P_CB, P_MU, P_Y = 8, 9, 10, 11, 12, 13, 14, 15
P_BWB, P_BWG, P_THR, P_ETA, P_RTOL, P_ATOL, P_TAIL, P_MAXEXTRA = 16, 17, 18, 19, 20, 21, 22, 23
P_EARLY, P_STOPUP, P_XI, P_WB, P_AMP, P_TD, P_DT, P_HMAX = 24, 25, 26, 27, 28, 29, 30, 31
P_NOUPLIFT, P_TB, P_TH0, P_OM0 = 32, 33, 34, 35
# sliding mode (docs/model.md §16): the object's friction coefficient on the base [-], rho = m / m_b,
# 1.0 to analyse sliding instead of rocking
P_MUO, P_RHO, P_SLIDE = 36, 37, 38
# a body of general geometry (docs/model.md §18): the slots P_R, P_ALPHA, P_I43, P_P, P_EPS, P_BETA1 hold
# the values of the side s = +1 (rocking about the right edge), these those of s = -1 (the left edge):
# R_s [m], alpha_s [rad], I_s / m about the edge [m^2], p_s [rad/s], and the restitution eps [-] and base
# jump beta1 [m/rad] of an impact landing from that side; P_THR is the uplift threshold of a positive
# total base acceleration (which tips the body onto its left edge), P_THRN that of a negative one
# [m/s^2]. A uniform block has equal sides, and the kernel's arithmetic is that of the symmetric model.
P_RL, P_ALPHAL, P_I43L, P_PL, P_EPSL, P_BETA1L, P_THRN = 39, 40, 41, 42, 43, 44, 45
# vertical input (docs/model.md §17): 1.0 when the record carries a vertical; the vertical on the
# current input segment, a_v = P_AV0 + P_AV1 (t - P_AVTS) [m/s^2, m/s^3, s], set per segment (they are
# the last three slots, replaced by slicing the tuple)
P_VERT, P_AV0, P_AV1, P_AVTS = 46, 47, 48, 49
NPAR = 50

ISO_NONE, ISO_LINEAR, ISO_FP = 0, 1, 2
EXC_RECT, EXC_HALFSINE, EXC_FULLSINE, EXC_RECORD = 0, 1, 2, 3
CONTACT, ROCKING, SLIDE = 0, 1, 2
REGIME = np.array([CONTACT, ROCKING, SLIDE])
"""The regime codes in an array. ``REGIME[ROCKING]`` is ``ROCKING`` typed as a plain integer, not as a
numba literal: a helper called with it is compiled once for every regime (with literals ``rhs``,
``dp5_step`` ... were compiled once per regime, seconds of the first compilation), and LLVM, which
reads the constant array, still specializes each inlined copy."""

# result vector layout
R_OUTCOME, R_MAXTH, R_NIMP, R_MAXU, R_TUP, R_TOV, R_TEND, R_DECIDED, R_NSTEPS, R_MAXA = range(10)
R_STALLS = 10  # uplift tests refused by the zero-progress guard
R_MUREQ, R_NMIN = 11, 12  # peak |horizontal / normal| contact force, least normal force / weight
R_JUMPS = 13  # 1 if the normal contact force vanishes (N <= 0: the block would jump), else 0
R_NSLIP, R_SPEAK, R_SRES = 14, 15, 16  # sliding mode: slips, peak |s| [m], residual s [m]
NRES = 17

HALF_PI = 0.5 * math.pi

# ---------------------------------------------------------------- state of one analysis
# Between the regimes the state is carried in two small arrays; each regime loop reads it into
# locals, works on those (the time loop runs on scalars only) and writes it back when it returns.
# Float state S: the state of motion, the step size, peaks and event times, then constants of the run.
S_T, S_U, S_V, S_TH, S_OM, S_Z, S_SIDE, S_H = 0, 1, 2, 3, 4, 5, 6, 7
S_MAXTH, S_MAXU, S_MAXA, S_TUP, S_TOV, S_TLAST = 8, 9, 10, 11, 12, 13
S_AGLAST, S_KF = 14, 15  # ground acceleration and derivative (4 slots) at the end of the last rocking step
S_TEXC, S_TEND, S_TMAX, S_EALPHA, S_HLIN, S_HCON = 19, 20, 21, 22, 23, 24
S_MUREQ, S_NMIN = 25, 26  # contact reactions while rocking: peak |H| / N, least N / (m g)
# the last two reaction samples of the rocking motion: t, |H| / N, N / g, |theta| <= alpha (0/1), u'
S_PKA, S_PKB = 27, 32
S_MUFAR, S_NFAR = 37, 38  # the reactions beyond |theta| = alpha not yet kept: peak |H| / N, least N / g
S_SPEAK = 39  # sliding mode: peak |s| [m] (s itself and s' are held in S_TH and S_OM)
# E_alpha of each side [J/kg] (S_EALPHA holds the smaller, which bounds a return to either side)
S_EALPHAR, S_EALPHAL = 40, 41
NS = 42
# Integer state F: regime, input segment, counters and flags (0/1).
F_REGIME, F_K, F_NIMP, F_NSTEPS, F_STALL, F_NH = 0, 1, 2, 3, 4, 5
F_UPLIFTED, F_OVERTURNED, F_CERTAIN, F_DECIDED, F_FSAL, F_NSTALL = 6, 7, 8, 9, 10, 11
F_NPK = 12  # reaction samples since the rocking motion was last restarted (0, 1, 2: two or more)
F_NSLIP = 13  # sliding mode: number of slips (transitions from sticking to slipping)
NF = 14
# what a regime loop returns to the analysis: the regime has changed / the analysis has ended /
# the history buffer is full (it is grown and the same regime goes on)
_NEXT, _END, _FULL = 0, 1, 2


# ---------------------------------------------------------------- compiled helpers
class _KernelOnly(CPUDispatcher):
    """A compiled helper without a Python entry point (see :func:`njit_inner`)."""

    _twin = None

    def __call__(self, *args, **kwargs):
        # without its CPython wrapper numba would jump to a null address: call a twin that has one,
        # compiled on the first call from Python (a test, a debugging session). Not cached: numba's
        # cache keys a function's code by its signature, not by these options, so a cached twin and
        # the kernel's copy would take each other's place.
        if self._twin is None:
            skip = ("nopython", "no_cpython_wrapper", "no_cfunc_wrapper")
            options = {k: v for k, v in self.targetoptions.items() if k not in skip}
            self._twin = njit(**options)(self.py_func)
        return self._twin(*args, **kwargs)


def njit_inner(**options):
    """``njit(cache=True, **options)`` for a helper of the kernel, compiled without a Python entry point.

    numba gives every compiled function a CPython wrapper (unboxing its arguments from Python objects,
    boxing its results) and a C-callable wrapper. The kernel calls its helpers from compiled code only,
    and their wrappers (the 43-float parameter tuple unboxed, the result tuples boxed) were about a
    fifth of the first compilation: they are left out (``no_cpython_wrapper``, ``no_cfunc_wrapper``).
    Called from Python, such a helper compiles a twin with a wrapper and calls it (the tests do).
    """

    def wrap(func):
        if config.DISABLE_JIT:
            return func
        targetoptions = {"nopython": True, "no_cpython_wrapper": True, "no_cfunc_wrapper": True, **options}
        disp = _KernelOnly(py_func=func, locals={}, targetoptions=targetoptions)
        disp.enable_caching()
        return disp

    return wrap


@njit_inner()
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


@njit_inner()
def _grow(H, n):
    """Copy of the history buffer ``H`` (first ``n`` samples) with twice its capacity."""
    G2 = np.empty((6, 2 * H.shape[1]))
    # element by element: a slice assignment costs numba seconds of compilation (its shape checks)
    for r in range(6):
        for j in range(n):
            G2[r, j] = H[r, j]
    return G2
