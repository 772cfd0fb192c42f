"""The oracle's integration: one analysis as a sequence of solve_ivp phases (full contact, rocking)
with terminal events, the impact map and the end-of-analysis decisions (docs/model.md §4-§10)."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, TypeVar

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from isorock.physics.engine.oracle.model import CONTACT, ROCKING, OracleModel, Segment, input_segments
from isorock.physics.excitation import GroundMotion, Pulse
from isorock.physics.model import System
from isorock.physics.result import Result

__all__ = ["Impact", "Trace", "OracleRun"]


_EPS = np.finfo(float).eps

# status codes of the end-of-analysis logic (docs/model.md §9)
_GO = 0  # outcome still open (or input still acting): keep integrating
_STOP = 1  # outcome decided and peaks complete: stop here
_STOP_OVERTURN = 2  # overturning certain, stop without reaching pi/2 (early_stop only)


# ----------------------------------------------------------------------------------------------
# trace
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Impact:
    """One impact at ``theta = 0`` (docs/model.md §7).

    Attributes
    ----------
    t : float
        Impact instant [s].
    side : int
        Side ``s`` before the impact.
    w_minus, w_plus : float
        ``theta'`` before / after [rad/s].
    v_minus, v_plus : float
        ``u'`` before / after [m/s].
    ceased : bool
        True if rocking ceased (full contact afterwards).
    """

    t: float
    side: int
    w_minus: float
    w_plus: float
    v_minus: float
    v_plus: float
    ceased: bool


@dataclass
class Trace:
    """Full record of an oracle run (for tests).

    Attributes
    ----------
    t : numpy.ndarray
        Instants [s]: integrator steps plus event instants (events appear twice: before and after the map).
    y : numpy.ndarray
        States ``(n, 5)``: u [m], u' [m/s], theta [rad], theta' [rad/s], Z [-].
    side : numpy.ndarray
        Rocking side (0 in full contact).
    regime : numpy.ndarray
        0 full contact, 1 rocking.
    impacts : list of Impact
        All impacts, in order.
    uplifts : list of tuple
        ``(t [s], side)`` of every start of rocking.
    """

    t: np.ndarray = field(default_factory=lambda: np.empty(0))
    y: np.ndarray = field(default_factory=lambda: np.empty((0, 5)))
    side: np.ndarray = field(default_factory=lambda: np.empty(0, dtype=int))
    regime: np.ndarray = field(default_factory=lambda: np.empty(0, dtype=int))
    impacts: list[Impact] = field(default_factory=list)
    uplifts: list[tuple[float, int]] = field(default_factory=list)


class _Recorder:
    """Accumulates peaks, counters and (optionally) histories."""

    def __init__(self, keep: bool) -> None:
        self.keep = keep
        self.max_th = 0.0
        self.max_u = 0.0
        self.n_steps = 0
        self._t: list[np.ndarray] = []
        self._y: list[np.ndarray] = []
        self._s: list[np.ndarray] = []
        self._r: list[np.ndarray] = []

    def peaks(self, y: np.ndarray) -> None:
        """Update peaks with states ``y`` of shape ``(5, n)`` or ``(5,)``."""
        y = np.asarray(y, dtype=float)
        if y.ndim == 1:
            y = y[:, None]
        if y.shape[1] == 0:
            return
        self.max_u = max(self.max_u, float(np.max(np.abs(y[0]))))
        self.max_th = max(self.max_th, float(np.max(np.abs(y[2]))))

    def add(self, t: np.ndarray, y: np.ndarray, s: int, regime: int) -> None:
        """Add history points ``t`` (n,), ``y`` (5, n)."""
        self.peaks(y)
        if self.keep and t.size:
            self._t.append(np.asarray(t, dtype=float))
            self._y.append(np.asarray(y, dtype=float).T.copy())
            self._s.append(np.full(t.size, s if regime == ROCKING else 0, dtype=int))
            self._r.append(np.full(t.size, regime, dtype=int))

    def trace(self, impacts: list[Impact], uplifts: list[tuple[float, int]]) -> Trace:
        if not self._t:
            return Trace(impacts=impacts, uplifts=uplifts)
        return Trace(
            t=np.concatenate(self._t),
            y=np.concatenate(self._y),
            side=np.concatenate(self._s),
            regime=np.concatenate(self._r),
            impacts=impacts,
            uplifts=uplifts,
        )


# ----------------------------------------------------------------------------------------------
# the run
# ----------------------------------------------------------------------------------------------
_F = TypeVar("_F", bound=Callable[..., Any])


def _event(*, terminal: bool = False, direction: float = 0.0) -> Callable[[_F], _F]:
    """Decorator: a ``solve_ivp`` event function with its ``terminal`` and ``direction`` attributes."""

    def mark(fn: _F) -> _F:
        ev: Any = fn  # solve_ivp reads them as attributes of the function object
        ev.terminal = terminal
        ev.direction = direction
        return fn

    return mark


def _never(t: float, y: np.ndarray) -> float:
    """Event function that never has a root."""
    return 1.0


def _guard_start(event: Callable, t0: float, y0: np.ndarray, slope: float) -> Callable:
    """Event function that is not exactly 0 at the start ``t0`` of an integrator call.

    An extremum event (``theta' = 0``, ``u' = 0``, ...) that is exactly 0 at ``t0`` is reported by
    ``solve_ivp`` as a sign change in the first step, and the root bracket can then fail with
    dense outputs that do not reproduce the start state to the last bit (LSODA). At ``t0`` the
    wrapped function returns the sign the event takes just after ``t0`` (``slope``, its derivative).
    """
    if event(t0, y0) != 0.0:
        return event

    sign0 = 1.0 if slope >= 0.0 else -1.0

    @_event(terminal=getattr(event, "terminal", False), direction=getattr(event, "direction", 0.0))
    def wrapped(t: float, y: np.ndarray) -> float:
        if t == t0:
            return sign0
        return event(t, y)

    wrapped.__name__ = getattr(event, "__name__", "event")
    return wrapped


@dataclass
class _PhaseEnd:
    """How one integrator call ended: time, state and reason."""

    t: float
    y: np.ndarray
    reason: str  # "bound" (segment end), "impact", "overturn", "uplift", "stop", "stop_overturn"
    side: int = 0


class OracleRun:
    """One analysis (state machine over regimes, segments and events)."""

    def __init__(
        self,
        system: System,
        excitation: Pulse | GroundMotion,
        *,
        rtol: float,
        atol: float,
        eta: float,
        early_stop: bool,
        max_extra: float,
        keep: bool,
        method: str | None = None,
    ) -> None:
        self.m = OracleModel(system)
        self.system = system
        self.rtol = rtol
        self.atol = atol
        self.eta = eta
        self.early_stop = early_stop
        self.t_in = float(excitation.duration)
        self.t1 = self.t_in + system.tail
        self.t_cap = self.t1 + max_extra
        segs = input_segments(excitation)
        segs.append(Segment(self.t_in, self.t1))
        segs.append(Segment(self.t1, self.t_cap))
        self.segs = [sg for sg in segs if sg.t1 > sg.t0]
        # Bouc-Wen is stiff (docs/model.md §10): LSODA (auto stiff/non-stiff switching) for FP
        self.method = method or ("LSODA" if self.m.kind == "fp" else "DOP853")
        # largest step: resolves the extrema of A (uplift detection) and of u, theta (peaks)
        scales = [2.0 * math.pi / self.m.p]
        if system.isolation.kind != "none":
            scales.append(system.isolation.Tb)
        self.h_free = min(scales) / 20.0
        self.h_input = self.h_free
        if isinstance(excitation, Pulse):
            self.h_input = min(self.h_free, excitation.td / 20.0)
        self.h_max = self.h_input
        self.rec = _Recorder(keep)
        self.impacts: list[Impact] = []
        self.uplifts: list[tuple[float, int]] = []

    # -- end-of-analysis logic (§9) ---------------------------------------------------------------
    def status(self, t: float, regime: int, y: np.ndarray, s: int, at_peak: bool = False) -> int:
        """Whether the analysis may stop at ``(t, y)``: ``_GO``, ``_STOP`` or ``_STOP_OVERTURN``."""
        if t < self.t_in:
            return _GO
        late = self.early_stop or t >= self.t1
        m = self.m
        if regime == ROCKING:
            e = m.energy(ROCKING, y, s)
            if e < m.e_alpha:
                if abs(y[2]) > m.alpha:
                    return _STOP_OVERTURN if self.early_stop else _GO
                if abs(y[2]) < m.alpha and late:
                    moving_away = (not at_peak) and s * y[3] > 0.0
                    return _GO if moving_away else _STOP
            return _GO
        # full contact
        if m.kind == "none":
            return _STOP if late else _GO
        if m.uplift_bound(y) < m.thr:
            return _STOP if late else _GO
        if m.kind == "fp" and t >= self.t1:
            # docs/model.md §9 extends full contact only for the linear isolator
            return _STOP
        return _GO

    # -- one integrator call ---------------------------------------------------------------------
    def _solve(
        self,
        fun: Callable,
        t0: float,
        t_end: float,
        y0: np.ndarray,
        events: list[Callable],
        first_step: float | None,
    ):
        if first_step is not None:
            first_step = min(first_step, t_end - t0, self.h_max)
            if not first_step > 0:
                first_step = None
        kw = dict(
            rtol=self.rtol,
            atol=self.atol,
            events=events,
            dense_output=True,
            max_step=self.h_max,
            first_step=first_step,
        )
        try:
            sol = solve_ivp(fun, (t0, t_end), y0, method=self.method, **kw)
        except ValueError as exc:
            # an event root that the dense output cannot bracket (LSODA's interpolant does not
            # reproduce the step end points exactly): redo this call with Radau
            if self.method == "Radau" or "different signs" not in str(exc):
                raise
            sol = solve_ivp(fun, (t0, t_end), y0, method="Radau", **kw)
        if sol.status < 0:
            raise RuntimeError(f"oracle: solve_ivp failed at t={sol.t[-1]:.9g} s: {sol.message}")
        self.rec.n_steps += max(len(sol.t) - 1, 0)
        return sol

    def _finish(self, sol, t_cut: float, y_cut: np.ndarray, s: int, regime: int, extra: list) -> None:
        """Record the steps of ``sol`` up to ``t_cut``, the end state and the extrema events ``extra``."""
        keep = sol.t < t_cut
        keep[0] = False  # the start point was recorded by the previous phase
        ts = [sol.t[keep], np.array([t_cut])]
        ys = [sol.y[:, keep], y_cut[:, None]]
        for te, ye in extra:  # exact extrema of theta and u (peaks)
            if te.size:
                sel = (te < t_cut) & (te > sol.t[0])
                ts.append(te[sel])
                ys.append(ye[sel].T)
        t_all = np.concatenate(ts)
        y_all = np.concatenate(ys, axis=1)
        order = np.argsort(t_all, kind="stable")
        self.rec.add(t_all[order], y_all[:, order], s, regime)

    def contact_phase(self, t0: float, y0: np.ndarray, seg: Segment) -> _PhaseEnd:
        m = self.m
        free = t0 >= self.t_in
        thr = m.thr

        def fun(t, y):
            return m.rhs_contact(t, y, seg)

        @_event(terminal=True, direction=1.0)
        def ev_uplift(t, y):
            return abs(m.total_acc_contact(t, y, seg)) - thr

        @_event(direction=-1.0)
        def ev_aext(t, y):  # maxima of |A|
            a = m.total_acc_contact(t, y, seg)
            return math.copysign(1.0, a) * m.total_jerk_contact(t, y, seg)

        def ev_uext(t, y):
            return y[1]

        @_event(direction=-1.0)
        def ev_bound(t, y):
            return m.uplift_bound(y) - thr

        iso = m.kind != "none"
        # events that are identically zero are replaced by a constant (no spurious roots):
        # non-isolated, A = x_g'' has no interior maximum on a constant or linear piece; u = 0.
        has_aext = iso or seg.amp != 0.0
        d0 = m.rhs_contact(t0, y0, seg)
        events = [
            ev_uplift,
            _guard_start(ev_aext, t0, y0, 1.0) if has_aext else _never,  # |A| grows from 0
            _guard_start(ev_uext, t0, y0, d0[1]) if iso else _never,
            ev_bound if (free and iso) else _never,
        ]
        sol = self._solve(fun, t0, seg.t1, y0, events, None)
        uext = [(sol.t_events[2], sol.y_events[2])]
        t_end = sol.t[-1]
        y_end = sol.y[:, -1].copy()
        up = None  # (crossing time, latest time up to which the dense output may be used)
        if sol.status == 1 and sol.t_events[0].size:
            up = (t_end, max(sol.sol.interpolants[-1].t_max, t_end))
        # an excursion of |A| above the threshold inside one step: start rocking at its crossing
        for tx, yx in zip(sol.t_events[1], sol.y_events[1], strict=True):
            if tx >= t_end:
                break
            if m.uplift_side(tx, yx, seg):
                ta = sol.t[max(np.searchsorted(sol.t, tx, side="right") - 1, 0)]

                def g(tt: float) -> float:
                    return abs(m.total_acc_contact(tt, sol.sol(tt), seg)) - thr

                tc = tx if g(ta) > 0 else brentq(g, ta, tx, xtol=1e-15, rtol=4 * _EPS)
                up = (tc, tx)
                break

        if up is not None:
            # make the uplift condition hold strictly (the root finder may land a hair early)
            tc, t_hi = up
            found = None
            for j in range(-1, 80):
                tt = tc if j < 0 else tc + 4.0 * _EPS * max(1.0, abs(tc)) * 2.0**j
                if tt > t_hi:
                    break
                side = m.uplift_side(tt, sol.sol(tt), seg)
                if side:
                    found = (tt, side)
                    break
            if found is None:  # grazing contact with the threshold: no uplift, carry on
                t_go = min(t_hi, seg.t1)
                y_go = sol.sol(t_go)
                self._finish(sol, t_go, y_go, 0, CONTACT, uext)
                return _PhaseEnd(t_go, y_go, "bound")
            t_end, side = found
            y_end = sol.sol(t_end)
            y_end[2] = y_end[3] = 0.0
            self._finish(sol, t_end, y_end, 0, CONTACT, uext)
            return _PhaseEnd(t_end, y_end, "uplift", side)

        reason = "bound"
        # decisions after the input (the only event that can change them in contact is the bound)
        if free:
            for te, ye in zip(sol.t_events[3], sol.y_events[3], strict=True):
                if te < t_end and self.status(te, CONTACT, ye, 0) == _STOP:
                    t_end, y_end, reason = te, ye, "stop"
                    break
        self._finish(sol, t_end, y_end, 0, CONTACT, uext)
        return _PhaseEnd(t_end, y_end, reason)

    def rocking_phase(self, t0: float, y0: np.ndarray, seg: Segment, s: int) -> _PhaseEnd:
        m = self.m
        free = t0 >= self.t_in

        def fun(t, y):
            return m.rhs_rocking(t, y, seg, s)

        @_event(terminal=True, direction=-1.0)
        def ev_impact(t, y):
            # positive constant while the block has not left theta = 0 (start of an excursion)
            if s * y[3] >= 0.0 and s * y[2] <= 0.0:
                return 1.0
            return s * y[2]

        @_event(terminal=True, direction=1.0)
        def ev_overturn(t, y):
            return s * y[2] - 0.5 * math.pi

        def ev_thext(t, y):
            return y[3]

        def ev_uext(t, y):
            return y[1]

        @_event(direction=-1.0)
        def ev_peak(t, y):  # peak of the excursion: s theta' from + to -
            return s * y[3]

        @_event(direction=-1.0)
        def ev_ealpha(t, y):
            return m.energy(ROCKING, y, s) - m.e_alpha

        def ev_alpha(t, y):
            return s * y[2] - m.alpha

        d = m.rhs_rocking(t0, y0, seg, s)
        events = [
            ev_impact,
            ev_overturn,
            _guard_start(ev_thext, t0, y0, d[3]),
            _guard_start(ev_uext, t0, y0, d[1]) if m.kind != "none" else _never,
        ]
        if free:
            events += [_guard_start(ev_peak, t0, y0, s * d[3]), ev_ealpha, ev_alpha]
        else:
            events += [_never, _never, _never]
        first = None
        if y0[3] != 0.0 and d[3] != 0.0:
            first = 0.05 * abs(y0[3] / d[3])  # resolve very short excursions (§10)
        sol = self._solve(fun, t0, seg.t1, y0, events, first)
        t_end = sol.t[-1]
        y_end = sol.y[:, -1].copy()
        reason = "bound"
        if sol.status == 1:
            if sol.t_events[1].size:
                reason = "overturn"
            elif sol.t_events[0].size:
                reason = "impact"
        peaks = [(sol.t_events[2], sol.y_events[2]), (sol.t_events[3], sol.y_events[3])]
        if free:
            cands = []
            for k, kind in ((4, "peak"), (5, "e"), (6, "a")):
                for te, ye in zip(sol.t_events[k], sol.y_events[k], strict=True):
                    if te < t_end:
                        cands.append((te, kind, ye))
            cands.sort(key=lambda c: c[0])
            for te, kind, ye in cands:
                st = self.status(te, ROCKING, ye, s, at_peak=(kind == "peak"))
                if st != _GO:
                    t_end, y_end = te, ye
                    reason = "stop" if st == _STOP else "stop_overturn"
                    break
        self._finish(sol, t_end, y_end, s, ROCKING, peaks)
        return _PhaseEnd(t_end, y_end, reason, s)

    # -- main loop -----------------------------------------------------------------------------
    def run(self, initial: Sequence[float] | None = None) -> tuple[Result, Trace]:
        m = self.m
        t = 0.0
        y = np.zeros(5)
        regime = CONTACT
        s = 0
        if initial is not None:
            y = np.array(initial, dtype=float)
            if y.shape != (5,):
                raise ValueError("initial must be [u, u', theta, theta', Z]")
            if m.kind == "none":
                y[0] = y[1] = 0.0
            if y[2] != 0.0 or y[3] != 0.0:
                regime = ROCKING
                s = int(np.sign(y[2])) if y[2] != 0.0 else int(np.sign(y[3]))
        started_rocking = regime == ROCKING
        t_uplift: float | None = None
        t_over: float | None = None
        overturned = False
        decided = True
        k = 0
        n_loop = 0
        n_stall = 0  # consecutive phases that advanced time by less than 1e-8 s
        t_prev = -1.0
        self.rec.add(np.array([t]), y[:, None], s, regime)
        while True:
            n_loop += 1
            n_stall = n_stall + 1 if t - t_prev < 1e-8 else 0
            t_prev = t
            if n_stall > 10_000 or n_loop > 5_000_000:
                raise RuntimeError(
                    f"oracle: no progress at t={t:.12g} s ({n_loop} phases, {len(self.impacts)} impacts): "
                    "the uplift/impact/cease sequence does not advance time"
                )
            while k < len(self.segs) and t >= self.segs[k].t1:
                k += 1
            if k == len(self.segs):  # hard cap reached
                st = self.status(t, regime, y, s)
                certain = regime == ROCKING and abs(y[2]) > m.alpha and m.energy(ROCKING, y, s) < m.e_alpha
                if st == _GO and certain:
                    st = _STOP_OVERTURN  # overturning certain, just not reached
                if st == _STOP_OVERTURN:
                    overturned, t_over = True, math.nan
                decided = st != _GO
                break
            seg = self.segs[k]
            self.h_max = self.h_input if seg.t0 < self.t_in else self.h_free
            if regime == CONTACT:
                side = m.uplift_side(t, y, seg)  # right-hand limit of the input at restarts
                if side:
                    regime, s = ROCKING, side
                    y[2] = y[3] = 0.0
                    self.uplifts.append((t, s))
                    if t_uplift is None:
                        t_uplift = t
                    continue
            st = self.status(t, regime, y, s)
            if st == _STOP:
                break
            if st == _STOP_OVERTURN:
                overturned, t_over = True, math.nan
                break
            if regime == CONTACT:
                end = self.contact_phase(t, y, seg)
            else:
                end = self.rocking_phase(t, y, seg, s)
            t, y = float(end.t), np.array(end.y, dtype=float)
            if end.reason == "bound":
                continue
            if end.reason == "stop":
                break
            if end.reason == "stop_overturn":
                overturned, t_over = True, math.nan
                break
            if end.reason == "overturn":
                overturned, t_over = True, t
                break
            if end.reason == "uplift":
                regime, s = ROCKING, end.side
                self.uplifts.append((t, s))
                if t_uplift is None:
                    t_uplift = t
                continue
            if end.reason == "impact":
                w_m, v_m = y[3], y[1]
                w_p = m.eps * w_m
                cease = m.eps <= 0.0 or abs(w_p) < self.eta * m.p * m.alpha
                y[2] = 0.0
                if cease:
                    y[3] = 0.0
                    y[1] = v_m + m.beta2 * w_m
                else:
                    y[3] = w_p
                    y[1] = v_m + m.beta1 * w_m
                if m.kind == "none":
                    y[1] = 0.0
                self.impacts.append(Impact(t, s, w_m, float(y[3]), v_m, float(y[1]), cease))
                if cease:
                    regime, s = CONTACT, 0
                else:
                    s = -s
                self.rec.add(np.array([t]), y[:, None], s, regime)
                continue
            raise AssertionError(end.reason)  # pragma: no cover

        if overturned:
            outcome = "overturn"
            max_th = 0.5 * math.pi / m.alpha
        else:
            rocked = t_uplift is not None or started_rocking
            outcome = "rocking" if rocked else "no_uplift"
            max_th = self.rec.max_th / m.alpha
        result = Result(
            outcome=outcome,
            max_theta_over_alpha=max_th,
            n_impacts=len(self.impacts),
            max_base_disp_m=self.rec.max_u if m.kind != "none" else 0.0,
            t_uplift_s=t_uplift,
            t_overturn_s=t_over,
            t_end_s=t,
            decided=decided,
            n_steps=self.rec.n_steps,
        )
        return result, self.rec.trace(self.impacts, self.uplifts)
