"""Independent reference integrator ("oracle") of the sliding object on a fixed or isolated base.

Written apart from the engine: it reads only the parameter dataclasses (:mod:`isorock.physics.model`,
:mod:`isorock.physics.excitation`) and :data:`isorock.constants.G`, and integrates with scipy's DOP853 stepper
under its own event location. The tests compare :func:`isorock.physics.engine.simulate` (``friction=mu``)
with it.

Model (per unit mass; ``rho = m/m_b``; ``g_e = G + a_v`` the effective gravity, ``g+ = max(g_e, 0)``)
-----------------------------------------------------------------------------------------------
* isolator force per unit total mass ``f_b``: linear ``kb u + cb u'``; friction pendulum
  ``(g_e/G) (kb u + mu_b G Z)`` with Bouc-Wen ``Y Z' = u' - gamma |u'| Z |Z| - beta u' Z^2``, ``Z(0) = 0``;
  0 without isolation (and ``u = 0``).
* STICK: ``u'' = -a_g - f_b``, base acceleration ``A = -f_b`` (``a_g`` on the ground), ``s' = 0``.
  Slip starts when ``|A| > mu g_e``, in the direction ``sigma = -sign(A)``.
* SLIP (``sigma`` fixed): ``A = a_g + u'' = -(1 + rho) f_b + mu rho g+ sigma`` (``a_g`` on the ground),
  ``s'' = -mu g+ sigma - A``. When ``s'`` returns to 0 the object sticks if ``|A_stick| <= mu g_e``
  (``A_stick = -f_b``, or ``a_g``), else slips on in the direction ``-sign(A_stick)`` (a reversal).

Method
------
* The time axis is cut at every kink or jump of the input: each record interval ``[k dt, (k+1) dt]``
  (input linear there), the pulse (smooth) and the free tail (zero input) are separate segments, so
  the right-hand side the stepper sees is smooth; a regime check at each segment start catches jumps
  (the rectangular pulse, a record whose first or last sample is not zero).
* Inside a segment DOP853 (order 8, ``rtol``/``atol``, step at most 0.01 s) advances the state
  ``(u, u', s, s', W_f, W_A, W_g, W_b)`` with the work integrals ``W_f = int mu g+ |s'| dt``,
  ``W_A = int A s' dt``, ``W_g = int a_g (u' + kappa s') dt`` and ``W_b = int f_b u' dt``
  (``kappa = rho/(1+rho)``) for the two energy balances the tests check: the object's relative
  kinetic energy ``s'^2/2 = -W_f - W_A`` and, per unit total mass, the kinetic energy of the isolated
  pair ``(1-kappa) u'^2/2 + kappa (u'+s')^2/2 = -W_g - W_b - kappa W_f``.
* After each step the regime's event functions are checked for a sign change and the first root is
  found by Brent's method on the step's dense output (``xtol`` 1e-14 s); the integration restarts at
  every event from the exact event state.
* Events: slip onset ``±A - mu g_e`` rising (STICK); ``sigma s'`` falling to 0 (SLIP: stick or reversal,
  ``s'`` set to exactly 0); ``u' = 0`` (isolated bases: extremum of ``u``; FP: new Bouc-Wen anchor,
  ``u'`` set to exactly 0). ``max|s|`` and ``max|u|`` are taken at these zeros of ``s'`` and ``u'``
  (where the extrema are) and at the end of the run.
* Friction pendulum: along a monotone stretch of ``u`` the Bouc-Wen law is the separable ODE
  ``Y dZ/du = 1 - gamma sign(u') Z|Z| - beta Z^2``, integrated in closed form (tan branch while
  ``Z`` opposes the motion, tanh branch after it changes sign) from the anchor ``(u0, Z0)`` set at each
  reversal of ``u'``. ``Z`` is then an explicit function of ``u`` and the stiff Bouc-Wen ODE never has
  to be integrated.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import DOP853
from scipy.optimize import brentq

from isorock.constants import G
from isorock.physics.excitation import GroundMotion, Pulse
from isorock.physics.model import System

__all__ = ["simulate_sliding", "bouc_wen_z"]

STICK, SLIP = 0, 1
MAX_STEP = 0.01  # [s]: no event function can cross zero twice inside one step
N_STATE = 8  # u, u', s, s', W_f, W_A, W_g, W_b


def bouc_wen_z(du: float, z0: float, Y: float, beta: float, gamma: float) -> float:
    """Bouc-Wen ``Z`` after a monotone isolator displacement ``du`` [m] from the anchor value ``z0``.

    ``Y dZ/du = 1 - gamma sign(du) Z|Z| - beta Z^2``. In the loading frame ``w = sign(du) Z``,
    ``x = |du|/Y``: ``dw/dx = 1 + (gamma - beta) w^2`` while ``w < 0`` (tan branch) and
    ``dw/dx = 1 - (gamma + beta) w^2`` once ``w >= 0`` (tanh branch), both integrated exactly.
    """
    if du == 0.0:
        return z0
    d = 1.0 if du > 0.0 else -1.0
    x = abs(du) / Y
    w = d * z0
    if w < 0.0:
        b = gamma - beta
        if b > 0.0:
            sb = math.sqrt(b)
            x0 = math.atan(-sb * w) / sb  # travel to w = 0
            if x < x0:
                tn = math.tan(sb * x)
                return d * (sb * w + tn) / (1.0 - sb * w * tn) / sb
        else:
            x0 = -w
            if x < x0:
                return d * (w + x)
        x -= x0
        w = 0.0
    c = gamma + beta
    if c > 0.0:
        k = math.sqrt(c)
        th = math.tanh(k * x)
        return d * (k * w + th) / (1.0 + k * w * th) / k
    return d * (w + x)


@dataclass
class _Segment:
    """A stretch of smooth input: ``a_g(t)`` and ``a_v(t)`` from ``t0`` to ``t1``."""

    t0: float
    t1: float
    kind: str  # "linear" (record interval or zero tail) or "sine"
    a0: float = 0.0  # linear: a_g(t0); sine: amplitude
    a1: float = 0.0  # linear: slope; sine: circular frequency
    v0: float = 0.0  # vertical a_v(t0)
    v1: float = 0.0  # vertical slope

    def ag(self, t: float) -> float:
        if self.kind == "sine":
            return self.a0 * math.sin(self.a1 * t)
        return self.a0 + self.a1 * (t - self.t0)

    def ge(self, t: float) -> float:
        return G + self.v0 + self.v1 * (t - self.t0)


def _segments(excitation, vertical, tail: float) -> list[_Segment]:
    """The input cut at its kinks and jumps, then the free tail."""
    segs: list[_Segment] = []
    if isinstance(excitation, Pulse):
        if vertical is not None:
            raise ValueError("a vertical acceleration goes with a GroundMotion only")
        a0 = excitation.amp * G
        if excitation.shape == "rect":
            segs.append(_Segment(0.0, excitation.td, "linear", a0, 0.0))
        else:
            segs.append(_Segment(0.0, excitation.duration, "sine", a0, math.pi / excitation.td))
        end = excitation.duration
    elif isinstance(excitation, GroundMotion):
        acc = np.asarray(excitation.acc, dtype=float)
        dt = float(excitation.dt)
        av = np.zeros_like(acc) if vertical is None else np.asarray(vertical, dtype=float)
        if av.shape != acc.shape:
            raise ValueError(f"vertical has shape {av.shape}, the record {acc.shape}")
        for k in range(acc.size - 1):
            segs.append(
                _Segment(
                    k * dt,
                    (k + 1) * dt,
                    "linear",
                    float(acc[k]),
                    float(acc[k + 1] - acc[k]) / dt,
                    float(av[k]),
                    float(av[k + 1] - av[k]) / dt,
                )
            )
        end = (acc.size - 1) * dt
    else:
        raise TypeError(f"not an excitation: {excitation!r}")
    segs.append(_Segment(end, end + tail, "linear"))
    return segs


@dataclass
class _Oracle:
    system: System
    mu: float
    rtol: float
    atol: float
    regime: int = STICK
    sigma: float = 0.0
    u0: float = 0.0  # Bouc-Wen anchor
    z0: float = 0.0
    n_slips: int = 0
    n_reversals: int = 0
    t_first_slip: float | None = None
    peak_s: float = 0.0
    peak_u: float = 0.0
    events: list = field(default_factory=list)

    def __post_init__(self) -> None:
        iso = self.system.isolation
        self.kind = iso.kind
        self.rho = iso.rho
        self.kappa = self.system.kappa
        self.kb = self.system.kb
        self.cb = self.system.cb
        if self.kind == "fp":
            self.mu_b, self.Y, self.bw_beta, self.bw_gamma = iso.mu_b, iso.Y, iso.beta, iso.gamma

    # ---------------------------------------------------------------- model
    def z(self, u: float) -> float:
        return bouc_wen_z(u - self.u0, self.z0, self.Y, self.bw_beta, self.bw_gamma)

    def fb(self, u: float, ud: float, ge: float) -> float:
        if self.kind == "linear":
            return self.kb * u + self.cb * ud
        if self.kind == "fp":
            return (ge / G) * (self.kb * u + self.mu_b * G * self.z(u))
        return 0.0

    def a_stick(self, seg: _Segment, t: float, y) -> float:
        """Base acceleration if the object moves with the base."""
        if self.kind == "none":
            return seg.ag(t)
        return -self.fb(y[0], y[1], seg.ge(t))

    def rhs(self, seg: _Segment, t: float, y) -> np.ndarray:
        ag, ge = seg.ag(t), seg.ge(t)
        u, ud, sd = y[0], y[1], y[3]
        gp = max(ge, 0.0)
        fb = self.fb(u, ud, ge)
        if self.regime == STICK:
            A = ag if self.kind == "none" else -fb
            sdd = 0.0
        else:
            A = ag if self.kind == "none" else -(1.0 + self.rho) * fb + self.mu * self.rho * gp * self.sigma
            sdd = -self.mu * gp * self.sigma - A
        udd = 0.0 if self.kind == "none" else A - ag
        wg = ag * (ud + self.kappa * sd)
        return np.array([ud, udd, sd, sdd, self.mu * gp * abs(sd), A * sd, wg, fb * ud])

    def event_values(self, seg: _Segment, t: float, y) -> list[float]:
        """[slip onset +, slip onset -, s' back to 0, u' = 0] (nan where not armed)."""
        nan = math.nan
        if self.regime == STICK:
            A, lim = self.a_stick(seg, t, y), self.mu * seg.ge(t)
            ev = [A - lim, -A - lim, nan]
        else:
            ev = [nan, nan, self.sigma * y[3]]
        ev.append(y[1] if self.kind != "none" else nan)
        return ev

    # ---------------------------------------------------------------- events
    @staticmethod
    def crossed(i: int, g0: float, g1: float) -> bool:
        if math.isnan(g0) or math.isnan(g1):
            return False
        if i < 2:  # slip onset: rising through 0
            return g0 < 0.0 <= g1
        if i == 2:  # sigma s' falling to 0
            return g0 > 0.0 >= g1
        return (g0 < 0.0 <= g1) or (g0 > 0.0 >= g1)  # u' = 0, either way

    def start_slip(self, t: float, A: float) -> None:
        self.regime, self.sigma = SLIP, (-1.0 if A > 0 else 1.0)
        self.n_slips += 1
        if self.t_first_slip is None:
            self.t_first_slip = t
        self.events.append((t, "slip", self.sigma))

    def check_stick(self, seg: _Segment, t: float, y) -> None:
        """At a segment start in STICK: slip at once if the (possibly jumped) input asks for it."""
        if self.regime == STICK:
            A = self.a_stick(seg, t, y)
            if abs(A) > self.mu * seg.ge(t) and A != 0.0:
                self.start_slip(t, A)

    def handle(self, i: int, seg: _Segment, t: float, y: np.ndarray) -> np.ndarray:
        y = y.copy()
        if i < 2:
            self.start_slip(t, self.a_stick(seg, t, y))
        elif i == 2:
            y[3] = 0.0
            self.peak_s = max(self.peak_s, abs(y[2]))
            A = self.a_stick(seg, t, y)
            if abs(A) <= self.mu * seg.ge(t):
                self.regime, self.sigma = STICK, 0.0
                self.events.append((t, "stick", 0.0))
            else:
                self.sigma = -1.0 if A > 0 else 1.0
                self.n_reversals += 1
                self.events.append((t, "reverse", self.sigma))
        else:
            if self.kind == "fp":
                self.z0 = self.z(y[0])
                self.u0 = y[0]
            y[1] = 0.0
            self.peak_u = max(self.peak_u, abs(y[0]))
        return y

    # ---------------------------------------------------------------- integration
    def run_segment(self, seg: _Segment, y: np.ndarray, h: float) -> tuple[np.ndarray, float]:
        t, t1 = seg.t0, seg.t1
        self.check_stick(seg, t, y)
        n_same = 0
        while t1 - t > 1e-13 * max(1.0, abs(t1)):
            fun = lambda tt, yy: self.rhs(seg, tt, yy)  # noqa: E731
            solver = DOP853(
                fun,
                t,
                y,
                t1,
                max_step=min(MAX_STEP, t1 - t),
                rtol=self.rtol,
                atol=self.atol,
                first_step=min(h, t1 - t),
            )
            g_old = self.event_values(seg, t, y)
            hit = None
            while solver.status == "running":
                solver.step()
                if solver.status == "failed":
                    raise RuntimeError(f"DOP853 failed at t={solver.t}")
                h = solver.step_size or h
                g_new = self.event_values(seg, solver.t, solver.y)
                idx = [i for i in range(4) if self.crossed(i, g_old[i], g_new[i])]
                if not idx and self.regime == SLIP and g_old[2] == 0.0 and g_new[2] < 0.0:
                    idx = [2]  # slipped and came back inside the first step
                if idx:
                    sol = solver.dense_output()
                    ta, tb = solver.t_old, solver.t
                    roots = []
                    for i in idx:
                        roots.append((self._root(seg, sol, i, ta, tb, g_old[i], g_new[i]), i))
                    hit = min(roots)
                    break
                g_old = g_new
            if hit is None:
                return solver.y.copy(), h
            te, i = hit
            ye = sol(te)
            n_same = n_same + 1 if te - t <= 1e-13 * max(1.0, abs(t1)) else 0
            if n_same > 50:
                raise RuntimeError(f"event loop at t={te}")
            y = self.handle(i, seg, te, ye)
            t = te
        return y, h

    def _root(self, seg, sol, i: int, ta: float, tb: float, ga: float, gb: float) -> float:
        def g(tt: float) -> float:
            return self.event_values(seg, tt, sol(tt))[i]

        if gb == 0.0:
            return tb
        if ga == 0.0:  # s' went positive and back inside one step: bracket the return
            ts = np.linspace(ta, tb, 33)[1:-1]
            pos = [tt for tt in ts if g(tt) > 0.0]
            if not pos:
                return ta
            ta = pos[0]
        return brentq(g, ta, tb, xtol=1e-14, rtol=4.0 * np.finfo(float).eps, maxiter=200)


def simulate_sliding(
    system: System,
    excitation,
    mu: float,
    vertical=None,
    rtol: float = 1e-10,
    atol: float = 1e-12,
) -> dict:
    """Sliding response of the object (friction ``mu`` on its base) from rest.

    Parameters
    ----------
    system : System
        Block and isolation (NoIsolation, LinearIsolation or FPIsolation); the block's shape is unused.
    excitation : Pulse | GroundMotion
        Horizontal ground acceleration; the run lasts its duration plus ``system.tail``.
    mu : float
        Friction coefficient of the object on its base [-].
    vertical : array, optional
        Vertical ground acceleration samples [m/s^2] (positive up) at the record's ``dt``.
    rtol, atol : float
        DOP853 tolerances.

    Returns
    -------
    dict
        ``sliding_peak_m`` (max |s|), ``sliding_residual_m`` (s at the end), ``n_slips`` (STICK->SLIP
        transitions), ``n_reversals``, ``max_base_disp_m`` (max |u|), ``t_first_slip_s`` (None if
        none), ``friction_work`` (``int mu g+ |s'| dt`` [m^2/s^2]), ``base_work`` (``int A s' dt``),
        ``final`` (the end state: ``u, ud, s, sd``), ``at_excitation_end`` (the same at the end of the
        input), ``t_end_s``, ``events`` ((t, kind, sigma) for each slip, stick and reversal).
    """
    if vertical is not None and not isinstance(excitation, GroundMotion):
        raise ValueError("a vertical acceleration goes with a GroundMotion only")
    o = _Oracle(system, float(mu), rtol, atol)
    segs = _segments(excitation, vertical, system.tail)
    y = np.zeros(N_STATE)
    h = MAX_STEP
    at_end = None
    for seg in segs:
        if seg is segs[-1]:
            at_end = dict(zip(("u", "ud", "s", "sd"), map(float, y[:4]), strict=True))
        y, h = o.run_segment(seg, y, h)
    o.peak_s = max(o.peak_s, abs(y[2]))
    o.peak_u = max(o.peak_u, abs(y[0]))
    return {
        "sliding_peak_m": float(o.peak_s),
        "sliding_residual_m": float(y[2]),
        "n_slips": o.n_slips,
        "n_reversals": o.n_reversals,
        "max_base_disp_m": float(o.peak_u),
        "t_first_slip_s": o.t_first_slip,
        "friction_work": float(y[4]),
        "base_work": float(y[5]),
        "ground_work": float(y[6]),
        "isolator_work": float(y[7]),
        "final": dict(zip(("u", "ud", "s", "sd"), map(float, y[:4]), strict=True)),
        "at_excitation_end": at_end,
        "t_end_s": segs[-1].t1,
        "events": o.events,
    }
