"""Independent reference integrator of the rocking model (tests only).

This module integrates the model of ``docs/model.md`` with plain
:func:`scipy.integrate.solve_ivp` and terminal events.  It is written for
clarity, not speed, and shares nothing with :mod:`isorock.physics.engine` except the
formulas of the specification, so that each path checks the other.

State vector (both regimes) ``y = [u, u', theta, theta', Z]``:

* ``u`` [m], ``u'`` [m/s]: base displacement / velocity relative to the ground
  (identically 0 for the non-isolated block);
* ``theta`` [rad], ``theta'`` [rad/s]: block rotation (0 in full contact);
* ``Z`` [-]: Bouc-Wen hysteretic variable of the FP isolator (0 otherwise).

The rocking side ``s`` (+1: pivot ``O``, theta > 0; -1: pivot ``O'``) is a
discrete state of the rocking phase, set at uplift and flipped at impacts; it is
never recomputed from the sign of ``theta`` (docs/model.md §10).

Regimes, events and maps (docs/model.md §4-§9):

* full contact: ``u'' = -x_g'' - f_b``; terminal event ``|A| = g tan(alpha)``
  with ``A = -f_b`` (``A = x_g''`` non-isolated).  Maxima of ``|A|`` are
  located as well, so that an excursion of ``|A|`` above the threshold that
  starts and ends inside one integrator step is not missed;
* rocking: the 2x2 system of §6; terminal events impact (``s theta`` down to 0,
  with the start-at-zero guard of §10) and overturn (``|theta| = pi/2``);
* impact map of §7 and cease rule of §8; after a cease the uplift condition is
  evaluated again at once;
* the integrator is restarted at every discontinuity of the input (pulse ends,
  every sample of a record), and uplift is then evaluated with the right-hand
  limit of the input.

Typical use::

    from isorock import Block, NoIsolation, Pulse, System
    from isorock.physics.engine.oracle import simulate

    res = simulate(System(Block.from_lambda_R(10, 1.0), NoIsolation()), Pulse("halfsine", 0.5, 0.3))
"""

from __future__ import annotations

from collections.abc import Sequence

from isorock.physics.engine.oracle.model import OracleModel, energy
from isorock.physics.engine.oracle.run import Impact, OracleRun, Trace
from isorock.physics.excitation import GroundMotion, Pulse
from isorock.physics.model import System
from isorock.physics.result import Result

__all__ = ["simulate", "simulate_trace", "Trace", "Impact", "energy", "OracleModel"]


def simulate_trace(
    system: System,
    excitation: Pulse | GroundMotion,
    *,
    histories: bool = False,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    eta: float = 1e-4,
    early_stop: bool = False,
    max_extra: float = 100.0,
    initial: Sequence[float] | None = None,
    method: str | None = None,
) -> tuple[Result, Trace]:
    """Run the oracle and return the result and the full trace (states, impacts, uplifts).

    Same parameters as :func:`simulate`, plus

    Parameters
    ----------
    initial : sequence of float, optional
        Initial state ``[u (m), u' (m/s), theta (rad), theta' (rad/s), Z (-)]`` instead of rest.
        A non-zero ``theta`` (or ``theta'``) starts in the rocking regime on side ``sgn theta``
        (``sgn theta'`` if ``theta = 0``). ``t_uplift_s`` then refers to later uplifts only.
    method : str, optional
        ``solve_ivp`` method; default DOP853, LSODA for the FP isolator.

    Returns
    -------
    result : Result
        As :func:`simulate`.
    trace : Trace
        States at every step and event, impacts with pre/post velocities, uplifts.
    """
    run = OracleRun(
        system,
        excitation,
        rtol=rtol,
        atol=atol,
        eta=eta,
        early_stop=early_stop,
        max_extra=max_extra,
        keep=True,
        method=method,
    )
    result, trace = run.run(initial)
    if histories:
        result.t = trace.t.copy()
        result.u = trace.y[:, 0].copy()
        result.theta = trace.y[:, 2].copy()
        result.regime = trace.regime.copy()
    return result, trace


def simulate(
    system: System,
    excitation: Pulse | GroundMotion,
    *,
    histories: bool = False,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    eta: float = 1e-4,
    early_stop: bool = False,
    max_extra: float = 100.0,
) -> Result:
    """Rocking response of a block on its (isolated) base, by plain ``solve_ivp`` (reference path).

    Parameters
    ----------
    system : System
        Block and isolation (docs/model.md §1-§3).
    excitation : Pulse or GroundMotion
        Ground acceleration (docs/model.md §11).
    histories : bool
        Return the time histories ``t`` [s], ``u`` [m], ``theta`` [rad], ``regime`` (0/1) at the
        integrator steps and events.
    rtol, atol : float
        Tolerances of ``solve_ivp`` (DOP853; LSODA for the stiff FP isolator) [-], [state units].
    eta : float
        Cease-rocking parameter of §8: rocking stops when ``|theta'+| < eta p alpha`` [-].
    early_stop : bool
        Stop as soon as the outcome is certain after the input has ended: overturn certain
        (rocking with ``|theta| > alpha`` and ``e < e_alpha``; then ``t_overturn_s`` is NaN), or
        no overturn possible (rocking with ``|theta| < alpha``, ``e < e_alpha``, after the peak of the
        current excursion; full contact with the no-further-uplift bound). The outcome is exact;
        ``n_impacts``, ``max_base_disp_m`` and, for the overturn case, ``t_overturn_s`` may be incomplete.
    max_extra : float
        Extra time beyond ``duration + system.tail`` allowed while the outcome is undecided [s];
        when it is exhausted, ``Result.decided`` is False.

    Returns
    -------
    Result
        Outcome and peaks over the whole analysis (docs/model.md §9).

    Notes
    -----
    The analysis covers the excitation plus ``system.tail`` (2 Tb isolated, 5 s otherwise), then
    continues while undecided: rocking with ``e >= e_alpha`` or ``|theta| > alpha``, full contact on a
    linear isolator (or an FP isolator, before the tail ends) while the no-further-uplift bound fails;
    a block moving away from ``theta = 0`` is followed to the peak of its excursion.
    Accuracy: the local error of every step is bounded by ``rtol``/``atol``; events are located to
    machine precision on the dense output.
    """
    run = OracleRun(
        system,
        excitation,
        rtol=rtol,
        atol=atol,
        eta=eta,
        early_stop=early_stop,
        max_extra=max_extra,
        keep=histories,
    )
    result, trace = run.run(None)
    if histories:
        result.t = trace.t
        result.u = trace.y[:, 0]
        result.theta = trace.y[:, 2]
        result.regime = trace.regime
    return result
