"""Independent reference integrator ("oracle") of the planar rocking of a general rigid body.

Written apart from the engine (tests only): it imports nothing from :mod:`isorock` but
:data:`isorock.constants.G`, takes plain numbers, and integrates with :func:`scipy.integrate.solve_ivp`
and its own event handling. The equations below were derived here from the Lagrangian and from
impulse-momentum balances; for a uniform block they reduce to docs/model.md (``/work/shared/physics.md``).

The body
--------
In the plane of motion the centre of mass (CM) is at height ``h`` above the base, the footprint's
edges at horizontal distances ``b_left`` (edge at ``x = -b_left``) and ``b_right`` (``x = +b_right``)
from the CM, and ``r`` is the radius of gyration about the CM (``I_c = m r^2``). A uniform block has
``b_left = b_right = b`` and ``r^2 = (b^2 + h^2)/3``.

Side ``s = +1``: rotation about the right edge (``theta > 0``, clockwise, leaning to ``+x``); ``s = -1``:
about the left edge (``theta < 0``). Per side ``b_s`` (``b_right`` for ``+1``, ``b_left`` for ``-1``),
``R_s = sqrt(b_s^2 + h^2)``, ``alpha_s = atan(b_s/h)``, ``I_s = r^2 + R_s^2`` (moment of inertia about
the edge per unit mass) and ``p_s = sqrt(g R_s / I_s)``.

Equations (per unit mass)
-------------------------
``x`` positive right, ``x_g''`` the ground acceleration, ``u`` the base displacement relative to the
ground, ``A = u'' + x_g''`` the total base acceleration, ``kappa = rho/(1+rho)``, ``rho = m/m_b``,
``g_e = g + a_v`` (``a_v`` the optional vertical ground acceleration, positive up).

* Isolator force per unit total mass ``f_b``: none (``u = 0``); linear ``omega_b^2 u + 2 xi_b omega_b u'``;
  friction pendulum ``(g_e/g) [(g/R_b) u + mu_b g Z]`` with ``Y Z' = u' - gamma |u'| Z|Z| - beta u' Z^2``.
* Full contact: ``u'' = -x_g'' - f_b``, ``A = -f_b`` (``A = x_g''`` on a fixed base).
* Rocking on side ``s``: the CM relative to the pivot is at ``(h sin(theta) - s b_s cos(theta),
  C)`` with ``C = h cos(theta) + s b_s sin(theta) = R_s cos(alpha_s - s theta)``; its velocity
  relative to the base is ``(C theta', S theta')``, ``S = s b_s cos(theta) - h sin(theta) =
  s R_s sin(alpha_s - s theta)``. Then
  ``T = (m+m_b)/2 v^2 + m v C theta' + m/2 I_s theta'^2`` (``v = x_g' + u'``), ``V = m g_e C + V_iso`` and
  Lagrange's equations give the 2x2 system

  ``u'' + kappa C theta'' = -x_g'' - f_b - kappa S theta'^2``,
  ``C u'' + I_s theta'' = -C x_g'' - g_e S``,

  with determinant ``I_s - kappa C^2 >= r^2 + (1-kappa) R_s^2 > 0``. Fixed base:
  ``theta'' = -(C x_g'' + g_e S)/I_s``.
* Uplift: at ``theta = theta' = 0`` on side ``s`` the system gives
  ``theta'' = -(h A + s g_e b_s)/(I_s - kappa h^2)``, so rocking starts on ``s = -1`` when
  ``A > g_e b_left/h`` and on ``s = +1`` when ``A < -g_e b_right/h`` (the first instant, strictly).
* Impact at ``theta = 0`` from side ``s`` (old edge, ``b_old = b_s``) onto the other edge (``b_new``):
  see :func:`restitution`. ``theta'+ = eps_s theta'-`` and the base velocity jumps by
  ``kappa h (theta'- - theta'+)`` (0 on a fixed base). Rocking ceases (``theta'+ = 0``, the same jump,
  then uplift re-checked at once) when ``eps_s <= 0`` or ``|theta'+| < eta p_s alpha_s`` with ``s`` the
  side being left. Every impact is counted, the final cease impact included.
* Overturn when ``|theta|`` reaches ``pi/2``.

Excitation
----------
``excitation`` is one of

* ``None``: no ground motion;
* ``(fun, t_exc)`` or ``(fun, t_exc, breaks)``: ``x_g''(t) = fun(t)`` [m/s^2] on ``[0, t_exc]``, zero
  after; ``breaks`` are the instants inside where ``fun`` is not smooth (the integrator restarts there,
  and the right-hand limit is used at each restart). :func:`pulse_excitation` builds the paper's pulses;
* ``[(t0, t1, fun), ...]``: contiguous pieces from ``t0 = 0``, each with its own callable used on its
  closed interval only (for inputs that jump inside; the right-hand limit is used at each restart),
  zero after the last ``t1``;
* ``(dt, acc)``: samples ``acc[k]`` at ``t = k dt``, linear in between, zero after the last sample; the
  integrator restarts at every sample.

``vertical`` (optional) has the same form as the input: a callable ``a_v(t)`` on ``[0, t_exc]`` for a
callable excitation, ``[(t0, t1, fun), ...]`` on the same pieces for a piecewise one, or samples at
the same instants for a sampled one.

Returns of :func:`simulate_body`
--------------------------------
``outcome``
    ``'no_uplift'``, ``'rocking'`` (rocked, no overturn; also when started rocking) or ``'overturn'``.
``n_impacts``
    Impacts at ``theta = 0``, the final cease impacts included.
``max_theta_over_alpha``
    Peak of ``|theta|/alpha_s`` over the motion, ``alpha_s`` that of the side rocked on at that time; on
    overturn ``(pi/2)/alpha_s`` of the side it fell to.
``max_abs_theta``
    Peak ``|theta|`` [rad] (``pi/2`` on overturn).
``max_base_disp``
    Peak ``|u|`` [m] (0 on a fixed base).
``t_uplift``, ``t_overturn``
    First uplift, overturn instant [s]; None when it did not happen.
``t_end``
    Time the analysis ended [s] (``t_end``, or the overturn instant).
``t``, ``y``, ``side``, ``regime``
    Histories at every integrator step, peak and event (events twice: before and after the map):
    ``t`` [s] (n,), ``y`` (n, 5) = ``u`` [m], ``u'`` [m/s], ``theta`` [rad], ``theta'`` [rad/s], ``Z``
    [-], ``side`` (n,) (0 in full contact) and ``regime`` (n,) (0 full contact, 1 rocking).
``impacts``
    One dict per impact: ``t``, ``side`` (before), ``w_minus``, ``w_plus`` [rad/s], ``v_minus``,
    ``v_plus`` [m/s] (base velocity), ``eps`` (coefficient used) and ``ceased``.
``uplifts``
    ``(t, side)`` of every start of rocking.
``eps``
    Restitution coefficients ``{+1: eps_{+1}, -1: eps_{-1}}`` (keyed by the side being left).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from isorock.constants import G

__all__ = ["BodyModel", "pulse_excitation", "restitution", "simulate_body", "CONTACT", "ROCKING"]

CONTACT, ROCKING = 0, 1
_EPS = float(np.finfo(float).eps)


# ----------------------------------------------------------------------------------------------
# impact
# ----------------------------------------------------------------------------------------------
def restitution(b_old: float, b_new: float, h: float, r: float, kappa: float = 0.0) -> tuple[float, float]:
    """Coefficient of restitution and base-velocity coefficient of an impact of a general body.

    Derivation. At ``theta = 0`` the CM is at ``(0, h)`` above the base; the old edge is at distance
    ``b_old`` on one side of it, the new (landing) edge at ``b_new`` on the other. Before the impact the
    body turns about the old edge: the CM velocity is ``(v- + h w-, s b_old w-)`` (``v`` the absolute
    base velocity, ``w = theta'``); after it, about the new edge: ``(v+ + h w+, -s b_new w+)``. The
    impulse acts at the new edge (no moment about it), the isolator and gravity are finite, and the
    new edge moves with the base (its velocity is finite), so the angular momentum of the body about
    the new edge is conserved:

    ``H = m [h (v + h w) - (s b_new)(v_y)] + m r^2 w``, i.e.
    ``h v- + (r^2 + h^2 - b_old b_new) w- = h v+ + (r^2 + h^2 + b_new^2) w+``,

    ``J w- + h v- = I_new w+ + h v+`` with ``J = r^2 + h^2 - b_old b_new``, ``I_new = r^2 + h^2 + b_new^2``.
    Fixed base (``v+ = v-``, the ground takes the horizontal impulse): ``eps = J / I_new``. Isolated
    base: the horizontal momentum of body + base ``(m+m_b) v + m h w`` is conserved (no external
    horizontal impulse), ``v+ - v- = -kappa h (w+ - w-)``, hence
    ``(I_new - kappa h^2) w+ = (J - kappa h^2) w-``:

    ``eps = (J - kappa h^2) / (I_new - kappa h^2)``,
    ``v+ = v- + beta1 w-``, ``beta1 = kappa h (1 - eps) = kappa h b_new (b_new + b_old)/(I_new - kappa h^2)``.

    Uniform block (``b_old = b_new = b``, ``r^2 = R^2/3``): ``eps = 1 - 1.5 sin^2(alpha)`` (fixed) and
    docs/model.md §7's ``eps``, ``beta1`` (isolated).

    Parameters
    ----------
    b_old, b_new : float
        Horizontal distances from the CM to the edge being left and to the landing edge [m].
    h : float
        CM height [m].
    r : float
        Radius of gyration about the CM [m].
    kappa : float
        ``m/(m+m_b)`` [-]; 0 for a fixed base.

    Returns
    -------
    eps : float
        ``theta'+ / theta'-`` [-].
    beta1 : float
        Base velocity jump per unit ``theta'-`` [m] (0 for a fixed base).
    """
    j = r * r + h * h - b_old * b_new
    i_new = r * r + h * h + b_new * b_new
    eps = (j - kappa * h * h) / (i_new - kappa * h * h)
    return eps, kappa * h * (1.0 - eps)


# ----------------------------------------------------------------------------------------------
# excitation pieces
# ----------------------------------------------------------------------------------------------
def _zero(t: float) -> float:
    return 0.0


@dataclass(frozen=True)
class _Piece:
    """A smooth stretch of input on the closed interval ``[t0, t1]``.

    ``ag``/``av``: horizontal/vertical ground acceleration [m/s^2]. ``lin``: both are linear,
    ``ag = a0 + a1 (t - t0)``, ``av = v0 + v1 (t - t0)`` (closed-form uplift on a fixed base).
    """

    t0: float
    t1: float
    ag: Callable[[float], float] = _zero
    av: Callable[[float], float] = _zero
    lin: tuple[float, float, float, float] | None = None

    def dav(self, t: float) -> float:
        """``a_v'`` [m/s^3] (slope, or a central difference for a callable)."""
        if self.lin is not None:
            return self.lin[3]
        if self.av is _zero:
            return 0.0
        d = 1e-6 * max(1.0, self.t1 - self.t0)
        lo, hi = max(self.t0, t - d), min(self.t1, t + d)
        return (self.av(hi) - self.av(lo)) / (hi - lo) if hi > lo else 0.0


def _linear_piece(t0: float, t1: float, a0: float, a1: float, v0: float, v1: float) -> _Piece:
    return _Piece(
        t0,
        t1,
        ag=lambda t: a0 + a1 * (t - t0),
        av=lambda t: v0 + v1 * (t - t0),
        lin=(a0, a1, v0, v1),
    )


def _pieces(excitation, vertical, t_end: float) -> list[_Piece]:
    """The input cut at its kinks and jumps, then zero input to ``t_end``, clipped to ``[0, t_end]``."""
    out: list[_Piece] = []
    t_exc = 0.0
    if excitation is None:
        if vertical is not None:
            raise ValueError("a vertical acceleration needs a horizontal excitation")
    elif isinstance(excitation, list):  # [(t0, t1, fun), ...]: one callable per piece
        if vertical is not None and not isinstance(vertical, list):
            raise ValueError("a piecewise excitation takes a piecewise vertical (or None)")
        vert = vertical or [None] * len(excitation)
        for (a, b, fun), vp in zip(excitation, vert, strict=True):
            if vp is not None and (vp[0], vp[1]) != (a, b):
                raise ValueError("the vertical's pieces must be the horizontal's")
            out.append(_Piece(float(a), float(b), ag=fun, av=_zero if vp is None else vp[2]))
        t_exc = float(excitation[-1][1])
    elif callable(excitation[0]):
        fun = excitation[0]
        t_exc = float(excitation[1])
        breaks = sorted({0.0, t_exc, *(float(b) for b in (excitation[2] if len(excitation) > 2 else ()))})
        breaks = [b for b in breaks if 0.0 <= b <= t_exc]
        if vertical is not None and not callable(vertical):
            raise ValueError("a callable excitation takes a callable vertical")
        av = vertical if vertical is not None else _zero
        for a, b in zip(breaks[:-1], breaks[1:], strict=True):
            out.append(_Piece(a, b, ag=fun, av=av))
    else:
        dt = float(excitation[0])
        acc = np.asarray(excitation[1], dtype=float)
        vv = np.zeros_like(acc) if vertical is None else np.asarray(vertical, dtype=float)
        if vv.shape != acc.shape or acc.ndim != 1 or acc.size < 2:
            raise ValueError("samples: acc (and vertical) must be 1-D arrays of one length >= 2")
        for k in range(acc.size - 1):
            out.append(
                _linear_piece(
                    k * dt,
                    (k + 1) * dt,
                    float(acc[k]),
                    float(acc[k + 1] - acc[k]) / dt,
                    float(vv[k]),
                    float(vv[k + 1] - vv[k]) / dt,
                )
            )
        t_exc = (acc.size - 1) * dt
    out.append(_linear_piece(t_exc, max(t_end, t_exc), 0.0, 0.0, 0.0, 0.0))
    clipped = []
    for pc in out:
        if pc.t0 >= t_end or pc.t1 <= pc.t0:
            continue
        if pc.t1 > t_end:
            pc = _Piece(pc.t0, t_end, pc.ag, pc.av, pc.lin)
        clipped.append(pc)
    return clipped


def pulse_excitation(shape: str, td: float, amp_g: float) -> tuple[Callable[[float], float], float]:
    """The paper's pulses as a callable excitation ``(fun, duration)``.

    Parameters
    ----------
    shape : {"rect", "halfsine", "fullsine"}
        Rectangular ``A`` on ``[0, td]``; ``A sin(pi t/td)`` on ``[0, td]`` or on ``[0, 2 td]``.
    td : float
        Half-cycle duration [s].
    amp_g : float
        Amplitude ``A`` in g [-].

    Returns
    -------
    fun : callable
        ``x_g''(t)`` [m/s^2].
    duration : float
        Duration of the input [s].
    """
    a0 = amp_g * G
    w = math.pi / td
    if shape == "rect":
        return (lambda t: a0), td
    if shape == "halfsine":
        return (lambda t: a0 * math.sin(w * t)), td
    if shape == "fullsine":
        return (lambda t: a0 * math.sin(w * t)), 2.0 * td
    raise ValueError(f"unknown pulse shape {shape!r}")


# ----------------------------------------------------------------------------------------------
# model
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Side:
    """Geometry of one pivot edge: ``b`` [m], ``R`` [m], ``alpha`` [rad], ``I`` = I_s/m [m^2], ``p`` [1/s]."""

    b: float
    R: float
    alpha: float
    I: float
    p: float


@dataclass
class BodyModel:
    """Equations of motion of the general body on its base, per unit mass (see the module docstring).

    Parameters
    ----------
    b_left, b_right, h, r : float
        Edge distances from the CM, CM height, radius of gyration [m].
    isolation : tuple
        ``('none',)``, ``('linear', Tb, xi_b, rho)`` or ``('fp', mu_b, R_b, rho[, Y, beta, gamma])``.
    """

    b_left: float
    b_right: float
    h: float
    r: float
    isolation: tuple = ("none",)
    kind: str = field(init=False)
    sides: dict[int, Side] = field(init=False)

    def __post_init__(self) -> None:
        if min(self.b_left, self.b_right, self.h) <= 0 or self.r < 0:
            raise ValueError("b_left, b_right, h must be > 0 and r >= 0")
        self.sides = {}
        for s, b in ((1, self.b_right), (-1, self.b_left)):
            R = math.hypot(b, self.h)
            inertia = self.r**2 + R * R
            self.sides[s] = Side(b, R, math.atan2(b, self.h), inertia, math.sqrt(G * R / inertia))
        iso = tuple(self.isolation)
        self.kind = str(iso[0])
        self.kb = self.cb = self.mu = 0.0
        self.Y, self.bw_beta, self.bw_gamma = 3.0e-4, 0.1, 0.9
        self.kappa = 0.0
        self.Tb = math.inf
        if self.kind == "linear":
            Tb, xi, rho = map(float, iso[1:4])
            wb = 2.0 * math.pi / Tb
            self.kb, self.cb, self.Tb = wb * wb, 2.0 * xi * wb, Tb
            self.kappa = rho / (1.0 + rho)
        elif self.kind == "fp":
            mu, Rb, rho = map(float, iso[1:4])
            if len(iso) > 4:
                self.Y, self.bw_beta, self.bw_gamma = map(float, iso[4:7])
            self.kb, self.mu, self.Tb = G / Rb, mu, 2.0 * math.pi * math.sqrt(Rb / G)
            self.kappa = rho / (1.0 + rho)
        elif self.kind != "none":
            raise ValueError(f"unknown isolation {iso!r}")

    # -- impact coefficients ----------------------------------------------------------------------
    def eps(self, s_old: int) -> float:
        """Restitution coefficient of an impact leaving side ``s_old`` [-]."""
        return restitution(self.sides[s_old].b, self.sides[-s_old].b, self.h, self.r, self.kappa)[0]

    # -- isolator -------------------------------------------------------------------------------
    def fb(self, u: float, v: float, z: float, ge: float) -> float:
        """Isolator force per unit total mass [m/s^2]."""
        if self.kind == "linear":
            return self.kb * u + self.cb * v
        if self.kind == "fp":
            return ge / G * (self.kb * u + self.mu * G * z)
        return 0.0

    def zdot(self, v: float, z: float) -> float:
        """Bouc-Wen ``Z'`` [1/s] (0 unless FP)."""
        if self.kind != "fp":
            return 0.0
        return (v - self.bw_gamma * abs(v) * z * abs(z) - self.bw_beta * v * z * z) / self.Y

    # -- right-hand sides -----------------------------------------------------------------------
    def rhs_contact(self, t: float, y, pc: _Piece) -> list[float]:
        """Full contact: ``d/dt [u, u', theta, theta', Z]``."""
        if self.kind == "none":
            return [0.0] * 5
        v, z = y[1], y[4]
        return [v, -pc.ag(t) - self.fb(y[0], v, z, G + pc.av(t)), 0.0, 0.0, self.zdot(v, z)]

    def rhs_rocking(self, t: float, y, pc: _Piece, s: int) -> list[float]:
        """Rocking on side ``s``: ``d/dt [u, u', theta, theta', Z]``."""
        u, v, th, w, z = y
        sd = self.sides[s]
        c = self.h * math.cos(th) + s * sd.b * math.sin(th)
        sg = s * sd.b * math.cos(th) - self.h * math.sin(th)
        xg = pc.ag(t)
        ge = G + pc.av(t)
        r2 = -c * xg - ge * sg
        if self.kind == "none":
            return [0.0, 0.0, w, r2 / sd.I, 0.0]
        r1 = -xg - self.fb(u, v, z, ge) - self.kappa * sg * w * w
        det = sd.I - self.kappa * c * c
        return [v, (sd.I * r1 - self.kappa * c * r2) / det, w, (r2 - c * r1) / det, self.zdot(v, z)]

    # -- uplift ---------------------------------------------------------------------------------
    def total_acc(self, t: float, y, pc: _Piece) -> float:
        """Total base acceleration ``A`` in full contact [m/s^2]."""
        if self.kind == "none":
            return pc.ag(t)
        return -self.fb(y[0], y[1], y[4], G + pc.av(t))

    def total_jerk(self, t: float, y, pc: _Piece) -> float:
        """``dA/dt`` in full contact, isolated base [m/s^3]."""
        u, v, z = y[0], y[1], y[4]
        a = -pc.ag(t) - self.fb(u, v, z, G + pc.av(t))
        if self.kind == "linear":
            return -(self.kb * v + self.cb * a)
        ge = G + pc.av(t)
        return -(ge / G) * (self.kb * v + self.mu * G * self.zdot(v, z)) - pc.dav(t) / G * (
            self.kb * u + self.mu * G * z
        )

    def excess(self, t: float, y, pc: _Piece, s: int) -> float:
        """``-s A - g_e b_s/h`` [m/s^2]: positive when the uplift threshold of side ``s`` is passed."""
        return -s * self.total_acc(t, y, pc) - (G + pc.av(t)) * self.sides[s].b / self.h

    def uplift_side(self, t: float, y, pc: _Piece) -> int:
        """Side on which rocking starts at ``(t, y)`` from full contact, 0 if none.

        Requires the threshold strictly passed and ``s theta''(0+) > 0`` from the rocking equations.
        """
        for s in (-1, 1):
            if self.excess(t, y, pc, s) > 0.0:
                y0 = [y[0], y[1], 0.0, 0.0, y[4]]
                if s * self.rhs_rocking(t, y0, pc, s)[3] > 0.0:
                    return s
        return 0

    # -- energy ---------------------------------------------------------------------------------
    def energy(self, y, s: int) -> float:
        """Mechanical energy without input, ``g_e = g`` [m^2/s^2].

        Per unit block mass on a fixed base, ``I_s theta'^2/2 + g (C - h)``; per unit total mass on an
        isolated one, ``u'^2/2 + kappa C u' theta' + kappa I_s theta'^2/2 + kappa g (C - h) + e_iso``
        (``s = 0``: full contact), ``e_iso = kb u^2/2`` (+ ``mu_b g Y Z^2/2`` for FP).
        """
        u, v, th, w, z = (float(x) for x in y)
        if s == 0:
            c, pot, inertia = self.h, 0.0, 0.0
        else:
            sd = self.sides[s]
            c = self.h * math.cos(th) + s * sd.b * math.sin(th)
            pot = s * sd.b * math.sin(th) - 2.0 * self.h * math.sin(0.5 * th) ** 2  # C - h
            inertia = sd.I
        if self.kind == "none":
            return 0.5 * inertia * w * w + G * pot
        k = self.kappa
        e_iso = 0.5 * self.kb * u * u + (0.5 * self.mu * G * self.Y * z * z if self.kind == "fp" else 0.0)
        return 0.5 * v * v + k * c * v * w + 0.5 * k * inertia * w * w + k * G * pot + e_iso


# ----------------------------------------------------------------------------------------------
# the run
# ----------------------------------------------------------------------------------------------
def _ev(terminal: bool, direction: float) -> Callable[[Callable], Callable]:
    """Decorator: a ``solve_ivp`` event function with its ``terminal`` and ``direction`` attributes."""

    def mark(fn: Callable) -> Callable:
        fn.terminal = terminal
        fn.direction = direction
        return fn

    return mark


def _root(f: Callable[[float], float], a: float, b: float) -> float:
    """Root of ``f`` in ``[a, b]`` (``f(a) f(b) <= 0``) to machine precision."""
    fa, fb = f(a), f(b)
    if fa == 0.0:
        return a
    if fb == 0.0 or fa * fb > 0.0:
        return b
    return brentq(f, a, b, xtol=1e-15, rtol=4.0 * _EPS, maxiter=300)


@dataclass
class _End:
    t: float
    y: np.ndarray
    reason: str  # "bound", "impact", "overturn", "uplift"
    side: int = 0


class _Run:
    """One analysis: a state machine over pieces, regimes and events."""

    def __init__(
        self,
        model: BodyModel,
        pieces: list[_Piece],
        *,
        rtol: float,
        atol: float,
        eta: float,
        eps: float | None,
        method: str | None,
    ) -> None:
        self.m = model
        self.pieces = pieces
        self.rtol, self.atol, self.eta, self.eps_user = rtol, atol, eta, eps
        self.method = method or ("LSODA" if model.kind == "fp" else "DOP853")
        scales = [2.0 * math.pi / max(sd.p for sd in model.sides.values())]
        if model.kind != "none":
            scales.append(model.Tb)
        self.h_free = min(scales) / 40.0
        self.hist_t: list[np.ndarray] = []
        self.hist_y: list[np.ndarray] = []
        self.hist_s: list[np.ndarray] = []
        self.impacts: list[dict] = []
        self.uplifts: list[tuple[float, int]] = []
        self.max_ratio = 0.0
        self.max_th = 0.0
        self.max_u = 0.0

    # -- records --------------------------------------------------------------------------------
    def record(self, t, y, s: int) -> None:
        """Add points ``t`` (n,), ``y`` (5, n) on side ``s`` (0: full contact) and update the peaks."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        y = np.asarray(y, dtype=float).reshape(5, -1)
        if t.size == 0:
            return
        self.hist_t.append(t)
        self.hist_y.append(y.T.copy())
        self.hist_s.append(np.full(t.size, s, dtype=int))
        self.max_u = max(self.max_u, float(np.max(np.abs(y[0]))))
        if s != 0:
            th = float(np.max(np.abs(y[2])))
            self.max_th = max(self.max_th, th)
            self.max_ratio = max(self.max_ratio, th / self.m.sides[s].alpha)

    def _extrema(self, sol, t_cut: float, comps: Sequence[int]) -> tuple[np.ndarray, np.ndarray]:
        """Zeros of the rates of ``comps`` (velocity indices 1, 3) inside the steps up to ``t_cut``."""
        ts, ys = [], []
        for k in comps:
            for i in range(len(sol.t) - 1):
                a, b = sol.t[i], min(sol.t[i + 1], t_cut)
                if b <= a:
                    break
                ya, yb = sol.sol(a)[k], sol.sol(b)[k]
                if ya * yb < 0.0:
                    tx = _root(lambda tt, k=k: sol.sol(tt)[k], a, b)
                    ts.append(tx)
                    ys.append(sol.sol(tx))
        if not ts:
            return np.empty(0), np.empty((5, 0))
        return np.array(ts), np.array(ys).T

    def finish(self, sol, t_cut: float, y_cut: np.ndarray, s: int, comps: Sequence[int]) -> None:
        """Record the steps of ``sol`` strictly inside ``(t0, t_cut)``, the extrema and the end point."""
        keep = (sol.t > sol.t[0]) & (sol.t < t_cut)
        te, ye = self._extrema(sol, t_cut, comps)
        t_all = np.concatenate([sol.t[keep], te, [t_cut]])
        y_all = np.concatenate([sol.y[:, keep], ye, y_cut[:, None]], axis=1)
        order = np.argsort(t_all, kind="stable")
        self.record(t_all[order], y_all[:, order], s)

    # -- integration ----------------------------------------------------------------------------
    def solve(self, fun, t0: float, t1: float, y0: np.ndarray, events: list, h_max: float, first=None):
        if first is not None:
            first = min(first, h_max, t1 - t0)
            first = first if first > 0 else None
        kw = dict(rtol=self.rtol, atol=self.atol, events=events, dense_output=True, max_step=h_max)
        kw["first_step"] = first
        try:
            sol = solve_ivp(fun, (t0, t1), y0, method=self.method, **kw)
        except ValueError as exc:  # an event the interpolant cannot bracket: retry with Radau
            if self.method == "Radau" or "different signs" not in str(exc):
                raise
            sol = solve_ivp(fun, (t0, t1), y0, method="Radau", **kw)
        if sol.status < 0:
            raise RuntimeError(f"body oracle: solve_ivp failed at t={sol.t[-1]:.9g}: {sol.message}")
        return sol

    def h_max(self, pc: _Piece) -> float:
        if pc.lin is not None:
            return self.h_free
        return min(self.h_free, (pc.t1 - pc.t0) / 20.0)

    # -- full contact ---------------------------------------------------------------------------
    def strict_uplift(self, tc: float, t_hi: float, state: Callable, pc: _Piece) -> tuple[float, int] | None:
        """First instant from ``tc`` (up to ``t_hi``) at which the uplift condition holds strictly."""
        for j in range(-1, 90):
            tt = tc if j < 0 else tc + 4.0 * _EPS * max(1.0, abs(tc)) * 2.0**j
            if tt > t_hi:
                return None
            side = self.m.uplift_side(tt, state(tt), pc)
            if side:
                return tt, side
        return None

    def contact_fixed(self, t0: float, y0: np.ndarray, pc: _Piece) -> _End:
        """Fixed base in full contact: nothing moves; the first threshold crossing of ``A = x_g''``."""
        m = self.m

        def state(tt: float) -> np.ndarray:
            return y0

        cands = []
        for s in (-1, 1):

            def f(tt: float, s=s) -> float:
                return m.excess(tt, y0, pc, s)

            if pc.lin is not None:
                f0, f1 = f(t0), f(pc.t1)
                if f0 <= 0.0 < f1:
                    cands.append(_root(f, t0, pc.t1))
            else:
                tc = self._scan(f, t0, pc.t1)
                if tc is not None:
                    cands.append(tc)
        for tc in sorted(cands):
            found = self.strict_uplift(tc, pc.t1, state, pc)
            if found is not None:
                self.record(found[0], y0, 0)
                return _End(found[0], y0.copy(), "uplift", found[1])
        self.record(pc.t1, y0, 0)
        return _End(pc.t1, y0.copy(), "bound")

    @staticmethod
    def _scan(f: Callable[[float], float], a: float, b: float, dt: float = 1e-4) -> float | None:
        """First upward crossing of 0 by ``f`` on ``[a, b]``, on a grid of spacing at most ``dt``."""
        n = max(64, math.ceil((b - a) / dt))
        grid = np.linspace(a, b, n + 1)
        prev = f(grid[0])
        for i in range(1, n + 1):
            cur = f(grid[i])
            if prev <= 0.0 < cur:
                return _root(f, grid[i - 1], grid[i])
            prev = cur
        return None

    def contact_isolated(self, t0: float, y0: np.ndarray, pc: _Piece) -> _End:
        m = self.m

        def fun(t, y):
            return m.rhs_contact(t, y, pc)

        events = []
        for s in (-1, 1):
            events.append(_ev(True, 1.0)(lambda t, y, s=s: m.excess(t, y, pc, s)))
        sol = self.solve(fun, t0, pc.t1, y0, events, self.h_max(pc))
        t_end = float(sol.t[-1])
        up: tuple[float, float] | None = None  # (crossing, latest usable time)
        if sol.status == 1:
            up = (t_end, max(sol.sol.interpolants[-1].t_max, t_end))
        # an excursion above a threshold that starts and ends inside one step
        miss = self._missed_uplift(sol, t_end, pc)
        if miss is not None and (up is None or miss[0] < up[0]):
            up = miss
        if up is not None:
            found = self.strict_uplift(up[0], min(up[1], pc.t1), sol.sol, pc)
            if found is None:  # grazing the threshold: no uplift
                t_go = min(up[1], pc.t1)
                y_go = sol.sol(t_go)
                self.finish(sol, t_go, y_go, 0, (1,))
                return _End(t_go, y_go, "bound")
            y_up = sol.sol(found[0])
            y_up[2] = y_up[3] = 0.0
            self.finish(sol, found[0], y_up, 0, (1,))
            return _End(found[0], y_up, "uplift", found[1])
        y_end = sol.y[:, -1].copy()
        self.finish(sol, t_end, y_end, 0, (1,))
        return _End(t_end, y_end, "bound")

    def _missed_uplift(self, sol, t_end: float, pc: _Piece) -> tuple[float, float] | None:
        """A threshold excursion inside one step: located at the step's maximum of the excess."""
        m = self.m
        pc_state = sol.sol
        for i in range(len(sol.t) - 1):
            a, b = sol.t[i], min(sol.t[i + 1], t_end)
            if b <= a:
                break
            for s in (-1, 1):

                def d(tt: float, s=s) -> float:  # d/dt of the excess of side s
                    y = pc_state(tt)
                    return -s * m.total_jerk(tt, y, pc) - pc.dav(tt) * m.sides[s].b / m.h

                if d(a) > 0.0 > d(b):
                    tx = _root(d, a, b)
                    if m.excess(tx, pc_state(tx), pc, s) > 0.0:
                        tc = _root(lambda tt, s=s: m.excess(tt, pc_state(tt), pc, s), a, tx)
                        return tc, tx
        return None

    # -- rocking --------------------------------------------------------------------------------
    def rocking(self, t0: float, y0: np.ndarray, pc: _Piece, s: int) -> _End:
        m = self.m

        def fun(t, y):
            return m.rhs_rocking(t, y, pc, s)

        @_ev(True, -1.0)
        def ev_impact(t, y):
            # a positive constant while the body has not yet left theta = 0 (start of an excursion)
            if s * y[3] >= 0.0 and s * y[2] <= 0.0:
                return 1.0
            return s * y[2]

        @_ev(True, 1.0)
        def ev_overturn(t, y):
            return s * y[2] - 0.5 * math.pi

        d = fun(t0, y0)
        first = 0.05 * abs(y0[3] / d[3]) if (y0[3] != 0.0 and d[3] != 0.0) else None
        sol = self.solve(fun, t0, pc.t1, y0, [ev_impact, ev_overturn], self.h_max(pc), first)
        t_end = float(sol.t[-1])
        y_end = sol.y[:, -1].copy()
        reason = "bound"
        if sol.status == 1:
            reason = "overturn" if sol.t_events[1].size else "impact"
        comps = (1, 3) if m.kind != "none" else (3,)
        self.finish(sol, t_end, y_end, s, comps)
        return _End(t_end, y_end, reason, s)

    def impact(self, t: float, y: np.ndarray, s: int) -> bool:
        """Apply the impact map in place; True if rocking ceased."""
        m = self.m
        w_m, v_m = float(y[3]), float(y[1])
        e = m.eps(s) if self.eps_user is None else float(self.eps_user)
        w_p = e * w_m
        sd = m.sides[s]
        cease = e <= 0.0 or abs(w_p) < self.eta * sd.p * sd.alpha
        if cease:
            w_p = 0.0
        y[2] = 0.0
        y[3] = w_p
        y[1] = v_m + m.kappa * m.h * (w_m - w_p) if m.kind != "none" else 0.0
        self.impacts.append(
            dict(t=t, side=s, w_minus=w_m, w_plus=w_p, v_minus=v_m, v_plus=float(y[1]), eps=e, ceased=cease)
        )
        return cease

    # -- main loop ------------------------------------------------------------------------------
    def run(self, y0: np.ndarray, t_end: float) -> dict:
        m = self.m
        t, y = 0.0, y0.copy()
        s = 0
        if y[2] != 0.0 or y[3] != 0.0:
            s = int(np.sign(y[2])) if y[2] != 0.0 else int(np.sign(y[3]))
        started = s != 0
        t_up = t_over = None
        self.k = 0
        self.record(t, y, s)
        n_stall, t_prev = 0, -1.0
        while True:
            n_stall = n_stall + 1 if t - t_prev < 1e-10 else 0
            t_prev = t
            if n_stall > 20_000:
                raise RuntimeError(f"body oracle: no progress at t={t:.12g} s")
            while self.k < len(self.pieces) and t >= self.pieces[self.k].t1:
                self.k += 1
            if self.k == len(self.pieces):
                break
            pc = self.pieces[self.k]
            if s == 0:
                side = m.uplift_side(t, y, pc)  # right-hand limit of the input at restarts
                if side:
                    s = side
                    self.uplifts.append((t, s))
                    t_up = t if t_up is None else t_up
                    continue
                end = self.contact_fixed(t, y, pc) if m.kind == "none" else self.contact_isolated(t, y, pc)
            else:
                end = self.rocking(t, y, pc, s)
            t, y = float(end.t), np.array(end.y, dtype=float)
            if end.reason == "uplift":
                s = end.side
                self.uplifts.append((t, s))
                t_up = t if t_up is None else t_up
            elif end.reason == "overturn":
                t_over = t
                break
            elif end.reason == "impact":
                ceased = self.impact(t, y, s)
                s = 0 if ceased else -s
                self.record(t, y, s)
        return self.result(t, y, s, started, t_up, t_over)

    def result(self, t, y, s, started, t_up, t_over) -> dict:
        m = self.m
        if t_over is not None:
            outcome = "overturn"
            ratio = 0.5 * math.pi / m.sides[s].alpha
            max_th = 0.5 * math.pi
        else:
            outcome = "rocking" if (started or t_up is not None) else "no_uplift"
            ratio, max_th = self.max_ratio, self.max_th
        return {
            "outcome": outcome,
            "n_impacts": len(self.impacts),
            "max_theta_over_alpha": ratio,
            "max_abs_theta": max_th,
            "max_base_disp": self.max_u if m.kind != "none" else 0.0,
            "t_uplift": t_up,
            "t_overturn": t_over,
            "t_end": t,
            "t": np.concatenate(self.hist_t),
            "y": np.concatenate(self.hist_y),
            "side": np.concatenate(self.hist_s),
            "regime": (np.concatenate(self.hist_s) != 0).astype(int),
            "impacts": self.impacts,
            "uplifts": self.uplifts,
            "eps": {1: m.eps(1), -1: m.eps(-1)},
        }


def simulate_body(
    b_left: float,
    b_right: float,
    h: float,
    r: float,
    *,
    isolation: tuple = ("none",),
    excitation=None,
    t_end: float,
    eta: float = 1e-4,
    eps: float | None = None,
    theta0: float = 0.0,
    omega0: float = 0.0,
    vertical=None,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    method: str | None = None,
) -> dict:
    """Rocking response of a general rigid body on a fixed, linear or friction-pendulum base.

    Parameters
    ----------
    b_left, b_right : float
        Horizontal distances from the CM to the left and right edges of the footprint [m].
    h : float
        Height of the CM above the base [m].
    r : float
        Radius of gyration about the CM [m].
    isolation : tuple
        ``('none',)``, ``('linear', Tb [s], xi_b [-], rho [-])`` or
        ``('fp', mu_b [-], R_b [m], rho [-][, Y [m], beta [-], gamma [-]])``.
    excitation : None, tuple or list
        ``(fun, t_exc[, breaks])``, ``[(t0, t1, fun), ...]`` or ``(dt, acc)``; see the module docstring.
    t_end : float
        End of the analysis [s] (earlier only on overturn).
    eta : float
        Cease-rocking parameter [-].
    eps : float, optional
        Restitution coefficient overriding both sides' (the base jump follows from horizontal momentum).
    theta0, omega0 : float
        Initial rotation [rad] and rate [rad/s]; non-zero: start rocking on side ``sgn theta0``
        (``sgn omega0`` if ``theta0 = 0``), the base at rest.
    vertical : callable or array, optional
        Vertical ground acceleration [m/s^2], positive up, in the excitation's form.
    rtol, atol : float
        ``solve_ivp`` tolerances.
    method : str, optional
        ``solve_ivp`` method; default DOP853, LSODA for the friction pendulum.

    Returns
    -------
    dict
        See the module docstring.

    Notes
    -----
    The run stops at ``t_end`` or at the overturn. A run compared with one that stopped at its own
    overturn instant should be given a slightly later ``t_end`` (nothing happens after an overturn), or
    the fall may end a hair beyond ``t_end`` here. A callable input ``(fun, t_exc, breaks)`` is evaluated
    on each closed piece between its breaks, so at a break both neighbouring pieces use ``fun(break)``:
    an input that jumps inside needs the piecewise form. On a fixed base a callable input is searched for
    the uplift threshold on a grid of 0.1 ms (closed form on sampled inputs); on an isolated base by
    events plus a check of the threshold excess's maxima inside each step. The model does not check the
    sign of the normal force (jumping, ``g_e < 0``).
    """
    model = BodyModel(b_left, b_right, h, r, tuple(isolation))
    pieces = _pieces(excitation, vertical, float(t_end))
    run = _Run(model, pieces, rtol=rtol, atol=atol, eta=eta, eps=eps, method=method)
    return run.run(np.array([0.0, 0.0, theta0, omega0, 0.0]), float(t_end))
