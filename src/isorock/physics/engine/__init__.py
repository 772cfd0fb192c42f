"""The fast rocking engine: a validating Python wrapper around the private compiled kernel.

:func:`simulate` checks and packs the parameters, runs :func:`isorock.physics.engine.kernel.run` (numba, no
Python in the time loop) and returns a :class:`~isorock.physics.result.Result`.
:mod:`isorock.physics.engine.oracle`
is the independent scipy integrator the tests compare the kernel with.

Example
-------
>>> from isorock import Block, LinearIsolation, System, Pulse
>>> from isorock.physics.engine import simulate
>>> sysm = System(Block.from_lambda_R(4.0, 3.0), LinearIsolation(Tb=3.0, xi_b=0.35, rho=0.5))
>>> res = simulate(sysm, Pulse("fullsine", td=0.5, amp=0.6))
>>> res.outcome in ("no_uplift", "rocking", "overturn")
True
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

import isorock.physics.engine._cache as _cache
import isorock.physics.engine.kernel as K
from isorock.constants import OUTCOMES
from isorock.physics.engine._filter import second_order_filter as _second_order_filter
from isorock.physics.engine.batch import BatchResult, run_many, set_threads
from isorock.physics.engine.params import DEFAULT_ATOL, DEFAULT_RTOL, pack_parameters
from isorock.physics.excitation import Excitation, Pulse
from isorock.physics.model import System
from isorock.physics.result import Result

# the compiled code in the cache is that of these sources, and a first compilation says so on stderr
_cache.refresh(K.run_linear)
_cache.announce(K.run_linear)

__all__ = [
    "simulate",
    "run_many",
    "BatchResult",
    "set_threads",
    "pack_parameters",
    "max_contact_acceleration",
    "DEFAULT_RTOL",
    "DEFAULT_ATOL",
    "warm_up",
    "recursive_filter",
]


def simulate(
    system: System,
    excitation: Excitation,
    *,
    scale: float = 1.0,
    histories: bool = False,
    early_stop: bool = False,
    rtol: float = DEFAULT_RTOL,
    atol: float = DEFAULT_ATOL,
    eta: float = 1e-4,
    max_extra: float = 100.0,
    stop_at_uplift: bool = False,
    theta0: float = 0.0,
    omega0: float = 0.0,
    friction: float | None = None,
) -> Result:
    """Rocking response of a block on its base to one excitation (compiled fast path).

    Parameters
    ----------
    system : System
        Block and isolation.
    excitation : Pulse or GroundMotion
        Ground acceleration (pulse amplitude in g; record samples in m/s^2).
    scale : float
        Factor multiplying the excitation [-].
    histories : bool
        Also return the time histories ``t, u, theta, regime`` at the integrator's steps.
    early_stop : bool
        Stop as soon as the outcome is certain (docs/model.md §9); peaks and counts are then partial
        and ``t_overturn_s`` is NaN for a certain-but-not-yet-reached overturn.
    rtol, atol : float
        Tolerances of the Runge-Kutta error control.
    eta : float
        Cease-rocking threshold: rocking ceases when ``|theta'+| < eta p alpha`` (docs/model.md §8).
    max_extra : float
        Longest time simulated beyond the excitation plus its tail while the outcome is open [s].
    stop_at_uplift : bool
        Stop at the first uplift (used by the uplift-amplitude search).
    theta0, omega0 : float
        Initial rotation [rad] and angular velocity [rad/s]; a non-zero ``theta0`` starts the analysis in
        the rocking regime (free-rocking studies).
    friction : float, optional
        The object's friction coefficient on its base [-]. Below ``tan(alpha)`` the object slides and
        never rocks, and the sliding mode is analysed (docs/model.md §16: ``mode == "sliding"``); at or
        above it the rocking analysis runs as without it (compare ``mu_required`` with it). None: the
        rocking analysis, no sliding check.

    A vertical input rides on the record (``GroundMotion.vertical``, docs/model.md §17).

    Returns
    -------
    Result
    """
    P, ekind, acc = pack_parameters(
        system,
        excitation,
        scale=scale,
        rtol=rtol,
        atol=atol,
        eta=eta,
        early_stop=early_stop,
        stop_at_uplift=stop_at_uplift,
        max_extra=max_extra,
        theta0=theta0,
        omega0=omega0,
        friction=friction,
    )
    out = K.run(P, ekind, acc, histories)
    return _result(*out, histories=histories, sliding=P[K.P_SLIDE] != 0.0)


def max_contact_acceleration(system: System, excitation: Excitation, *, scale: float = 1.0) -> float:
    """Peak total base acceleration ``max |A(t)|`` of the full-contact system, uplift disabled [m/s^2].

    For the linear isolator this is the exact ``max |A_1|`` of docs/model.md §13 (over the excitation and
    the free vibration after it); for the non-isolated block it is the PGA.
    """
    P, ekind, acc = pack_parameters(system, excitation, scale=scale, no_uplift=True)
    res, *_ = K.run(P, ekind, acc, False)
    return float(res[K.R_MAXA])


def _result(res, ht, hu, hth, hrg, hv, hom, *, histories: bool, sliding: bool = False) -> Result:
    b = BatchResult.decode(res)
    outcome = OUTCOMES[int(b.outcome_code[0])]
    t_up = float(b.t_uplift_s[0])
    t_ov = float(b.t_overturn_s[0])
    return Result(
        outcome=outcome,
        max_theta_over_alpha=float(b.max_theta_over_alpha[0]),
        n_impacts=int(b.n_impacts[0]),
        max_base_disp_m=float(b.max_base_disp_m[0]),
        t_uplift_s=None if math.isnan(t_up) or sliding else t_up,
        t_overturn_s=(t_ov if outcome == "overturn" else None),
        t_end_s=float(b.t_end_s[0]),
        decided=bool(b.decided[0]),
        n_steps=int(b.n_steps[0]),
        stalls=int(b.stalls[0]),
        mu_required=float(b.mu_required[0]),
        min_normal_over_weight=float(b.min_normal_over_weight[0]),
        jumps=bool(b.jumps[0]),
        t=ht if histories else None,
        u=hu if histories else None,
        theta=hth if histories and not sliding else None,
        regime=hrg if histories else None,
        u_dot=hv if histories else None,
        theta_dot=hom if histories and not sliding else None,
        mode="sliding" if sliding else "rocking",
        sliding_peak_m=float(b.sliding_peak_m[0]) if sliding else None,
        sliding_residual_m=float(b.sliding_residual_m[0]) if sliding else None,
        n_slips=int(b.n_slips[0]) if sliding else None,
        t_first_slip_s=None if math.isnan(t_up) or not sliding else t_up,
        slip=hth if histories and sliding else None,
        slip_dot=hom if histories and sliding else None,
    )


def warm_up(
    *, batch: bool = True, isolations: tuple[str, ...] = ("linear", "fp", "none"), sliding: bool = True
) -> dict:
    """Compile the engine now (or load it from the cache): one short analysis per entry point.

    :func:`simulate` has one compiled entry point per isolation model and mode (rocking, sliding) and
    compiles only the one it uses (the first analysis after an install compiles one); this compiles
    them all, and the parallel batch kernel, as an install script or a workflow run does before its
    jobs start.

    Parameters
    ----------
    batch : bool
        Also the parallel batch kernel (:func:`run_many`), which the workflow's maps and assessment use
        (for every isolation model and mode).
    isolations : tuple of str
        The isolation models of the entry points of :func:`simulate` (``linear``, ``fp``, ``none``).
    sliding : bool
        Also their sliding mode (``simulate(..., friction=...)`` below ``tan(alpha)``).

    Returns
    -------
    dict
        ``simulate_s``: seconds for the entry points of :func:`simulate`, ``run_many_s``: for the batch
        kernel [s] (0 without ``batch``); ``seconds``: per entry point (``"linear"``, ``"linear
        sliding"``, ...); ``cache``: the directory.
    """
    import time

    from isorock.physics.model import Block, FPIsolation, LinearIsolation, NoIsolation

    make: dict[str, Callable[[], NoIsolation | LinearIsolation | FPIsolation]] = {
        "linear": lambda: LinearIsolation(Tb=3.0, xi_b=0.2, rho=0.5),
        "fp": lambda: FPIsolation.from_period(mu_b=0.1, Tb=3.0, rho=0.5),
        "none": NoIsolation,
    }
    pulse = Pulse("rect", td=0.2, amp=0.5)
    block = Block.from_lambda_R(4.0, 1.0)
    out: dict = {"cache": str(_cache._cache_dir(K.run_linear) or ""), "seconds": {}, "run_many_s": 0.0}

    def entry(kind: str, friction: float | None) -> None:
        t0 = time.perf_counter()
        simulate(System(block, make[kind]()), pulse, friction=friction)
        out["seconds"][kind if friction is None else f"{kind} sliding"] = time.perf_counter() - t0

    for kind in isolations:
        entry(kind, None)
    if batch:
        t0 = time.perf_counter()
        run_many([System(block, make["linear"]())] * 2, pulse, 1.0)
        out["run_many_s"] = time.perf_counter() - t0
    if sliding:
        # after the batch kernel, which compiled the sliding loop: an entry point each, about 1 s
        for kind in isolations:
            entry(kind, 0.1)  # 0.1 < tan(alpha) = 0.25: the sliding mode
    t0 = time.perf_counter()
    recursive_filter(np.array([1.0, 0.5, 0.25]), np.array([1.0, -0.5, 0.1]), np.ones(4), np.zeros(2))
    out["seconds"]["recursive_filter"] = time.perf_counter() - t0
    out["simulate_s"] = sum(v for k, v in out["seconds"].items() if k != "recursive_filter")
    return out


def recursive_filter(b: np.ndarray, a: np.ndarray, x: np.ndarray, zi: np.ndarray) -> np.ndarray:
    """``scipy.signal.lfilter(b, a, x, zi=zi)[0]`` for a filter of three coefficients with ``a[0] == 1``:
    the same numbers (the same operations in the same order, :mod:`isorock.physics.engine._filter`),
    without importing scipy.signal.

    Parameters
    ----------
    b, a : numpy.ndarray, shape (3,)
        Numerator and denominator coefficients (``a[0]`` = 1).
    x : numpy.ndarray, 1-D
        The input.
    zi : numpy.ndarray, shape (2,)
        The initial state of the delays (:func:`scipy.signal.lfiltic`).

    Returns
    -------
    numpy.ndarray
        The output, as long as ``x``.
    """
    b = np.ascontiguousarray(b, dtype=float)
    a = np.ascontiguousarray(a, dtype=float)
    x = np.ascontiguousarray(x, dtype=float)
    zi = np.asarray(zi, dtype=float)
    if b.shape != (3,) or a.shape != (3,) or zi.shape != (2,) or x.ndim != 1:
        raise ValueError("recursive_filter: b and a of 3 coefficients, zi of 2, x 1-D")
    if a[0] != 1.0:
        raise ValueError(f"recursive_filter: a[0] = {a[0]!r}, not 1")
    return _second_order_filter(b, a, x, float(zi[0]), float(zi[1]))
