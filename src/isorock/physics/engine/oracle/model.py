"""The oracle's equations: input segments, the equations of motion of both regimes, the uplift test and
the energy (docs/model.md §3-§9), written from the specification only."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from isorock.constants import G
from isorock.physics.excitation import GroundMotion, Pulse
from isorock.physics.model import Block, FPIsolation, System
from isorock.physics.result import REGIME_CONTACT, REGIME_ROCKING

__all__ = ["CONTACT", "ROCKING", "OracleModel", "energy", "input_segments", "Segment"]

CONTACT = REGIME_CONTACT
ROCKING = REGIME_ROCKING

# a state ``[u (m), u' (m/s), theta (rad), theta' (rad/s), Z (-)]``: a list, or solve_ivp's array
State = Sequence[float] | np.ndarray


# ----------------------------------------------------------------------------------------------
# input segments
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Segment:
    """Smooth piece of the ground acceleration, ``c0 + c1 (t - t0) + amp sin(omega t)`` [m/s^2].

    The expression is used on the closed interval ``[t0, t1]``; the integrator is restarted at
    ``t1``, so values at the boundary are never taken from the neighbouring piece.
    """

    t0: float
    t1: float
    c0: float = 0.0
    c1: float = 0.0
    amp: float = 0.0
    omega: float = 0.0

    def acc(self, t: float) -> float:
        """Ground acceleration ``x_g''(t)`` [m/s^2]."""
        return self.c0 + self.c1 * (t - self.t0) + self.amp * math.sin(self.omega * t)

    def dacc(self, t: float) -> float:
        """Ground jerk ``x_g'''(t)`` [m/s^3]."""
        return self.c1 + self.amp * self.omega * math.cos(self.omega * t)


def input_segments(exc: Pulse | GroundMotion) -> list[Segment]:
    """Smooth pieces of the excitation, from 0 to its duration [s]."""
    if isinstance(exc, Pulse):
        a0 = exc.amp * G
        if exc.shape == "rect":
            return [Segment(0.0, exc.td, c0=a0)]
        return [Segment(0.0, exc.duration, amp=a0, omega=math.pi / exc.td)]
    if isinstance(exc, GroundMotion):
        a = exc.acc
        dt = exc.dt
        segs = []
        for k in range(a.size - 1):
            segs.append(Segment(k * dt, (k + 1) * dt, c0=float(a[k]), c1=float(a[k + 1] - a[k]) / dt))
        return segs
    raise TypeError(f"excitation must be a Pulse or a GroundMotion, got {type(exc).__name__}")


# ----------------------------------------------------------------------------------------------
# model equations
# ----------------------------------------------------------------------------------------------
class OracleModel:
    """Equations of docs/model.md for one :class:`~isorock.physics.model.System`, per unit mass.

    Parameters
    ----------
    system : System
        Block and isolation.
    """

    def __init__(self, system: System) -> None:
        blk = system.block
        if not isinstance(blk, Block):
            # the general body has its own reference integrator, tests/engine/body_oracle.py
            raise TypeError("the uniform-block oracle takes a Block, not a RigidBody")
        iso = system.isolation
        self.system = system
        self.kind: str = iso.kind
        self.b = blk.b
        self.h = blk.h
        self.R = blk.R
        self.R2 = self.R * self.R
        self.I43 = 4.0 / 3.0 * self.R2  # I_O / m [m^2]
        self.alpha = blk.alpha
        self.p = blk.p
        self.kappa = system.kappa if self.kind != "none" else 0.0
        self.eps = system.eps
        self.beta1 = system.beta1
        self.beta2 = system.beta2
        self.thr = G * blk.b / blk.h  # g tan(alpha) [m/s^2]
        self.kb = system.kb
        self.cb = system.cb
        if isinstance(iso, FPIsolation):
            self.mu = iso.mu_b
            self.Rb = iso.R_b
            self.Y = iso.Y
            self.bw_beta = iso.beta
            self.bw_gamma = iso.gamma
        else:
            self.mu = 0.0
            self.Rb = math.inf
            self.Y = 1.0
            self.bw_beta = 0.0
            self.bw_gamma = 0.0
        if self.kind == "none":
            self.e_alpha = G * self.R * 2.0 * math.sin(self.alpha / 2.0) ** 2
        else:
            self.e_alpha = self.kappa * G * self.R * 2.0 * math.sin(self.alpha / 2.0) ** 2

    # -- isolator -----------------------------------------------------------------------------
    def fb(self, u: float, v: float, z: float) -> float:
        """Isolator force per unit total mass ``f_b`` [m/s^2] (§3)."""
        if self.kind == "linear":
            return self.kb * u + self.cb * v
        if self.kind == "fp":
            return self.kb * u + self.mu * G * z
        return 0.0

    def zdot(self, v: float, z: float) -> float:
        """Bouc-Wen ``Z'`` [1/s] (§3); 0 unless FP."""
        if self.kind != "fp":
            return 0.0
        return (v - self.bw_gamma * abs(v) * z * abs(z) - self.bw_beta * v * z * z) / self.Y

    # -- right-hand sides -----------------------------------------------------------------------
    def rhs_contact(self, t: float, y: State, seg: Segment) -> list[float]:
        """Full-contact regime (§4): ``d/dt [u, u', theta, theta', Z]``."""
        if self.kind == "none":
            return [0.0, 0.0, 0.0, 0.0, 0.0]
        u, v, _, _, z = y
        a = -seg.acc(t) - self.fb(u, v, z)
        return [v, a, 0.0, 0.0, self.zdot(v, z)]

    def rhs_rocking(self, t: float, y: State, seg: Segment, s: int) -> list[float]:
        """Rocking regime on side ``s`` (§6): ``d/dt [u, u', theta, theta', Z]``."""
        u, v, th, w, z = y
        c = self.h * math.cos(th) + s * self.b * math.sin(th)
        sg = s * self.b * math.cos(th) - self.h * math.sin(th)
        xg = seg.acc(t)
        if self.kind == "none":
            return [0.0, 0.0, w, -(c * xg + G * sg) / self.I43, 0.0]
        r1 = -xg - self.fb(u, v, z) - self.kappa * sg * w * w
        r2 = -c * xg - G * sg
        d = self.I43 - self.kappa * c * c
        udd = (self.I43 * r1 - self.kappa * c * r2) / d
        thdd = (r2 - c * r1) / d
        return [v, udd, w, thdd, self.zdot(v, z)]

    # -- derived quantities -------------------------------------------------------------------
    def total_acc_contact(self, t: float, y: State, seg: Segment) -> float:
        """Total base acceleration ``A = u'' + x_g''`` in full contact [m/s^2]."""
        if self.kind == "none":
            return seg.acc(t)
        return -self.fb(y[0], y[1], y[4])

    def total_jerk_contact(self, t: float, y: State, seg: Segment) -> float:
        """``dA/dt`` in full contact [m/s^3]."""
        if self.kind == "none":
            return seg.dacc(t)
        u, v, _, _, z = y
        a = -seg.acc(t) - self.fb(u, v, z)
        if self.kind == "linear":
            return -(self.kb * v + self.cb * a)
        return -(self.kb * v + self.mu * G * self.zdot(v, z))

    def uplift_side(self, t: float, y: State, seg: Segment) -> int:
        """Side on which rocking starts from full contact at ``(t, y)``, 0 if none (§5).

        Uplift requires ``|A| > g tan(alpha)`` strictly, and (the same condition up to round-off)
        that the rocking equations started at ``theta = theta' = 0`` on side ``s = -sgn A`` give
        ``s theta'' > 0``.
        """
        a = self.total_acc_contact(t, y, seg)
        if not abs(a) > self.thr:
            return 0
        s = -1 if a > 0 else 1
        y0 = [y[0], y[1], 0.0, 0.0, y[4]]
        if s * self.rhs_rocking(t, y0, seg, s)[3] > 0.0:
            return s
        return 0

    def pot(self, th: float, s: int) -> float:
        """CM height above rest, ``R cos(alpha - s theta) - h`` [m] (cancellation-free form)."""
        return s * self.b * math.sin(th) - 2.0 * self.h * math.sin(0.5 * th) ** 2

    def energy(self, regime: int, y: State, s: int) -> float:
        """Mechanical energy of §9 [m^2/s^2] (per unit total mass; per unit block mass if non-isolated)."""
        u, v, th, w, z = y
        if self.kind == "none":
            if regime == CONTACT:
                return 0.0
            return 0.5 * self.I43 * w * w + G * self.pot(th, s)
        eiso = 0.5 * self.kb * u * u
        if self.kind == "fp":
            eiso += 0.5 * self.mu * G * self.Y * z * z
        if regime == CONTACT:
            return 0.5 * v * v + eiso
        c = self.h * math.cos(th) + s * self.b * math.sin(th)
        k = self.kappa
        return 0.5 * v * v + k * c * v * w + 0.5 * k * self.I43 * w * w + k * G * self.pot(th, s) + eiso

    def uplift_bound(self, y: State) -> float:
        """Upper bound of ``|A|`` over all later full-contact free vibration [m/s^2] (§9).

        0 for the non-isolated block (no input, no base). Valid only after the input has ended.
        """
        if self.kind == "none":
            return 0.0
        e = self.energy(CONTACT, y, 0)
        if self.kind == "linear":
            wb = math.sqrt(self.kb)
            xi = self.cb / (2.0 * wb)
            return wb * math.sqrt(1.0 + 4.0 * xi * xi) * math.sqrt(2.0 * e)
        return G * math.sqrt(2.0 * e * self.Rb / G) / self.Rb + self.mu * G


def energy(system: System, regime: int, y: State, s: int) -> float:
    """Mechanical energy of docs/model.md §9 for a state ``y = [u, u', theta, theta', Z]``.

    Parameters
    ----------
    system : System
        Block and isolation.
    regime : int
        0 full contact, 1 rocking.
    y : sequence of float
        State ``[u (m), u' (m/s), theta (rad), theta' (rad/s), Z (-)]``.
    s : int
        Rocking side (+1 / -1); ignored in full contact.

    Returns
    -------
    float
        Energy per unit total mass [m^2/s^2] (per unit block mass for the non-isolated block).
    """
    return OracleModel(system).energy(regime, y, s)
