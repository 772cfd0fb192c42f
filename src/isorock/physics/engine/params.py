"""The parameter vector of the compiled kernel: a system and its excitation packed for
:func:`isorock.physics.engine.kernel.run` (layout: :mod:`isorock.physics.engine._layout`)."""

from __future__ import annotations

import numpy as np

import isorock.physics.engine.kernel as K
from isorock.constants import G
from isorock.physics.body import RigidBody
from isorock.physics.excitation import Excitation, GroundMotion, Pulse
from isorock.physics.model import System, impact_coefficients

__all__ = ["pack_parameters", "DEFAULT_RTOL", "DEFAULT_ATOL"]

DEFAULT_RTOL = 1e-8
"""Relative tolerance of the Runge-Kutta error control [-]."""
DEFAULT_ATOL = 1e-10
"""Absolute tolerance of the Runge-Kutta error control (m, m/s, rad, rad/s)."""

_EMPTY = np.zeros((1, 2))


def pack_parameters(
    system: System,
    excitation: Excitation,
    *,
    scale: float = 1.0,
    rtol: float = DEFAULT_RTOL,
    atol: float = DEFAULT_ATOL,
    eta: float = 1e-4,
    early_stop: bool = False,
    stop_at_uplift: bool = False,
    no_uplift: bool = False,
    max_extra: float = 100.0,
    theta0: float = 0.0,
    omega0: float = 0.0,
    hmax: float | None = None,
    friction: float | None = None,
) -> tuple[np.ndarray, int, np.ndarray]:
    """Parameter vector, excitation code and samples for :func:`isorock.physics.engine.kernel.run`.

    ``friction`` below ``tan(alpha)`` selects the sliding mode (docs/model.md §16); a record's
    vertical (``GroundMotion.vertical``) follows its horizontal samples in the returned array.
    """
    blk = system.block
    iso = system.isolation
    sliding = friction is not None and friction < blk.tan_alpha
    if sliding and (early_stop or stop_at_uplift or no_uplift or theta0 != 0.0):
        raise ValueError("the sliding mode runs full analyses only (no early stop, uplift search or theta0)")
    if system.sliding_only and not sliding:
        raise ValueError(
            "a system marked sliding_only is analysed only in the sliding mode: give its friction, below "
            f"tan(alpha) = {blk.tan_alpha:.4g}"
        )
    P = np.zeros(K.NPAR)
    P[K.P_G] = G
    P[K.P_KAPPA] = system.kappa if system.isolated else 0.0
    _pack_body(P, system)
    P[K.P_ETA] = eta
    P[K.P_RTOL] = rtol
    P[K.P_ATOL] = atol
    P[K.P_TAIL] = system.tail
    P[K.P_MAXEXTRA] = max_extra
    P[K.P_EARLY] = 1.0 if early_stop else 0.0
    P[K.P_STOPUP] = 1.0 if stop_at_uplift else 0.0
    P[K.P_NOUPLIFT] = 1.0 if no_uplift else 0.0
    P[K.P_TH0] = theta0
    P[K.P_OM0] = omega0
    if sliding:
        assert friction is not None
        P[K.P_SLIDE] = 1.0
        P[K.P_MUO] = friction
        P[K.P_RHO] = iso.rho if system.isolated else 0.0
        P[K.P_THR] = friction * G
        P[K.P_THRN] = friction * G
    if iso.kind == "linear":
        P[K.P_ISO] = K.ISO_LINEAR
        P[K.P_KB] = iso.kb
        P[K.P_CB] = iso.cb
        P[K.P_XI] = iso.xi_b
        P[K.P_WB] = iso.omega_b
        P[K.P_TB] = iso.Tb
    elif iso.kind == "fp":
        P[K.P_ISO] = K.ISO_FP
        P[K.P_KB] = iso.kb
        P[K.P_MU] = iso.mu_b
        P[K.P_Y] = iso.Y
        P[K.P_BWB] = iso.beta
        P[K.P_BWG] = iso.gamma
        P[K.P_WB] = iso.omega_b
        P[K.P_TB] = iso.Tb
    else:
        P[K.P_ISO] = K.ISO_NONE
    if isinstance(excitation, Pulse):
        ekind = excitation.code
        P[K.P_AMP] = excitation.amp * G * scale
        P[K.P_TD] = excitation.td
        acc = _EMPTY
        t_scale = excitation.td
    elif isinstance(excitation, GroundMotion):
        ekind = K.EXC_RECORD
        P[K.P_AMP] = scale
        P[K.P_DT] = excitation.dt
        # row 0 the horizontal, row 1 the vertical when there is one [m/s^2]
        acc = excitation.acc[None, :]
        if excitation.vertical is not None:
            P[K.P_VERT] = 1.0
            acc = np.ascontiguousarray(np.vstack([excitation.acc, excitation.vertical]))
        t_scale = 1.0
    else:
        raise TypeError(f"excitation must be a Pulse or a GroundMotion, not {type(excitation).__name__}")
    if hmax is None:
        # an event-safety cap only; accuracy comes from the error control
        hmax = min(0.25 / blk.p, 0.25 * t_scale, 0.05)
        if iso.kind != "none":
            hmax = min(hmax, iso.Tb / 50.0)
    P[K.P_HMAX] = hmax
    return P, ekind, acc


def _pack_body(P: np.ndarray, system: System) -> None:
    """The object's slots of the parameter vector: each side's geometry, impact and uplift threshold.

    A uniform :class:`~isorock.physics.model.Block` fills both sides with the values of the paper's formulas,
    computed as they always were (its results are bit for bit those of the symmetric model); a
    :class:`~isorock.physics.body.RigidBody` fills each side with its own (docs/model.md §18).
    """
    blk = system.block
    if isinstance(blk, RigidBody):
        kappa = system.kappa if system.isolated else 0.0
        P[K.P_H] = blk.h_cg
        P[K.P_B] = blk.b_right
        for s, slots in (
            (1.0, (K.P_R, K.P_ALPHA, K.P_I43, K.P_P, K.P_EPS, K.P_BETA1)),
            (-1.0, (K.P_RL, K.P_ALPHAL, K.P_I43L, K.P_PL, K.P_EPSL, K.P_BETA1L)),
        ):
            sd = blk.side(s)
            eps, beta1 = blk.impact(s, kappa)
            for slot, value in zip(slots, (sd.R, sd.alpha, sd.inertia, sd.p, eps, beta1), strict=True):
                P[slot] = value
        P[K.P_BETA2] = kappa * blk.h_cg
        # a positive base acceleration tips the body onto its left edge
        P[K.P_THR] = G * blk.left.tan_alpha
        P[K.P_THRN] = G * blk.right.tan_alpha
        return
    P[K.P_B] = blk.b
    P[K.P_H] = blk.h
    P[K.P_R] = blk.R
    P[K.P_ALPHA] = blk.alpha
    P[K.P_P] = blk.p
    P[K.P_I43] = 4.0 / 3.0 * blk.R**2
    if system.isolated:
        P[K.P_EPS], P[K.P_BETA1], P[K.P_BETA2] = impact_coefficients(blk.lam, blk.h, system.isolation.rho)
    else:
        P[K.P_EPS] = blk.eps_housner
    P[K.P_THR] = system.uplift_acc
    P[K.P_THRN] = P[K.P_THR]
    for left, right in (
        (K.P_RL, K.P_R),
        (K.P_ALPHAL, K.P_ALPHA),
        (K.P_I43L, K.P_I43),
        (K.P_PL, K.P_P),
        (K.P_EPSL, K.P_EPS),
        (K.P_BETA1L, K.P_BETA1),
    ):
        P[left] = P[right]
