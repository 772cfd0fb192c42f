"""Layout of the kernel's arrays: the parameter vector, the result vector, the isolation and
excitation codes, and the state of an analysis carried between the two regime loops; the history
buffer."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

# ---------------------------------------------------------------- parameter vector layout
P_B, P_H, P_R, P_ALPHA, P_P, P_G, P_KAPPA, P_I43 = 0, 1, 2, 3, 4, 5, 6, 7
P_EPS, P_BETA1, P_BETA2, P_ISO, P_KB, P_CB, P_MU, P_Y = 8, 9, 10, 11, 12, 13, 14, 15
P_BWB, P_BWG, P_THR, P_ETA, P_RTOL, P_ATOL, P_TAIL, P_MAXEXTRA = 16, 17, 18, 19, 20, 21, 22, 23
P_EARLY, P_STOPUP, P_XI, P_WB, P_AMP, P_TD, P_DT, P_HMAX = 24, 25, 26, 27, 28, 29, 30, 31
P_NOUPLIFT, P_TB, P_TH0, P_OM0 = 32, 33, 34, 35
# sliding mode (docs/model.md §16): the object's friction coefficient on the base [-], rho = m / m_b,
# 1.0 to analyse sliding instead of rocking
P_MUO, P_RHO, P_SLIDE = 36, 37, 38
# vertical input (docs/model.md §17): 1.0 when the record carries a vertical; the vertical on the
# current input segment, a_v = P_AV0 + P_AV1 (t - P_AVTS) [m/s^2, m/s^3, s], set per segment (they are
# the last three slots, replaced by slicing the tuple)
P_VERT, P_AV0, P_AV1, P_AVTS = 39, 40, 41, 42
NPAR = 43

ISO_NONE, ISO_LINEAR, ISO_FP = 0, 1, 2
EXC_RECT, EXC_HALFSINE, EXC_FULLSINE, EXC_RECORD = 0, 1, 2, 3
CONTACT, ROCKING, SLIDE = 0, 1, 2

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
NS = 40
# Integer state F: regime, input segment, counters and flags (0/1).
F_REGIME, F_K, F_NIMP, F_NSTEPS, F_STALL, F_NH = 0, 1, 2, 3, 4, 5
F_UPLIFTED, F_OVERTURNED, F_CERTAIN, F_DECIDED, F_FSAL, F_NSTALL = 6, 7, 8, 9, 10, 11
F_NPK = 12  # reaction samples since the rocking motion was last restarted (0, 1, 2: two or more)
F_NSLIP = 13  # sliding mode: number of slips (transitions from sticking to slipping)
NF = 14
# what a regime loop returns to the analysis: the regime has changed / the analysis has ended /
# the history buffer is full (it is grown and the same regime goes on)
_NEXT, _END, _FULL = 0, 1, 2


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
    # element by element: a slice assignment costs numba seconds of compilation (its shape checks)
    for r in range(6):
        for j in range(n):
            G2[r, j] = H[r, j]
    return G2
