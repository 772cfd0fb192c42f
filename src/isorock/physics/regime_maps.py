"""Response-regime maps: the outcome of a grid of blocks or isolators under one excitation
(paper Figs 6, 9, 10, 13), run in parallel threads by the engine's batch interface
(:func:`isorock.physics.engine.run_many`)."""

from __future__ import annotations

import time
from collections.abc import Sequence

import numpy as np
from tqdm import tqdm

from isorock.physics.engine import run_many
from isorock.physics.excitation import Excitation
from isorock.physics.model import Block, Isolation, LinearIsolation, System, isolation_params
from isorock.physics.result import RegimeMap

__all__ = ["RegimeMap", "run_grid", "regime_map_lambda_R", "regime_map_Tb_xi"]


def run_grid(
    systems: Sequence[System],
    excitation: Excitation,
    amp_g: float,
    *,
    threads: int | None = None,
    progress: bool = False,
    chunk: int = 256,
) -> np.ndarray:
    """Outcome and peak rotation of many systems under one excitation scaled to ``amp_g`` [g].

    Runs the compiled kernel in parallel threads (``threads``, default all cores), chunk by chunk so
    that a progress bar can follow. Analyses stop as soon as their outcome is certain.

    Returns
    -------
    numpy.ndarray, shape (n, 2)
        Column 0 the outcome code (0 no uplift, 1 rocking, 2 overturn), column 1 ``max|theta|/alpha``.
    """
    if not len(systems):
        return np.zeros((0, 2))
    unit = excitation.with_pga(1.0)
    with tqdm(total=len(systems), disable=not progress, unit="analysis", desc="regime map") as bar:
        res = run_many(
            systems, unit, amp_g, early_stop=True, threads=threads, chunk=chunk, progress=bar.update
        )
    return np.column_stack([res.outcome_code.astype(float), res.max_theta_over_alpha])


def regime_map_lambda_R(
    excitation: Excitation,
    isolation: Isolation,
    lambdas: Sequence[float],
    Rs: Sequence[float],
    amp_g: float,
    **kw,
) -> RegimeMap:
    """Regime map in the slenderness-size plane (paper Figs 6, 9, 10, 13).

    Parameters
    ----------
    excitation : Pulse or GroundMotion
        Input shape (rescaled to ``amp_g``).
    isolation : NoIsolation, LinearIsolation or FPIsolation
        Base, the same for every block.
    lambdas : sequence of float
        Slenderness values ``h/b`` [-].
    Rs : sequence of float
        Block sizes (half-diagonal) [m].
    amp_g : float
        Pulse amplitude or record PGA [g].
    **kw
        ``threads``, ``progress`` for :func:`run_grid`.
    """
    x = np.asarray(lambdas, dtype=float)
    y = np.asarray(Rs, dtype=float)
    systems = [System(Block.from_lambda_R(lam, R), isolation) for lam in x for R in y]
    fixed = {"isolation": isolation.kind, **isolation_params(isolation)}
    return _grid_map("lambda-R", "lambda", "R_m", x, y, systems, excitation, amp_g, fixed, **kw)


def regime_map_Tb_xi(
    excitation: Excitation,
    block: Block,
    Tbs: Sequence[float],
    xis: Sequence[float],
    rho: float,
    amp_g: float,
    **kw,
) -> RegimeMap:
    """Regime map in the isolation period-damping plane for a linear isolator (paper Figs 11, 12).

    Parameters
    ----------
    excitation : Pulse or GroundMotion
        Input shape (rescaled to ``amp_g``).
    block : Block
        The block.
    Tbs : sequence of float
        Isolation periods [s].
    xis : sequence of float
        Isolation damping ratios [-].
    rho : float
        Block-to-base mass ratio [-].
    amp_g : float
        Pulse amplitude or record PGA [g].
    """
    x = np.asarray(Tbs, dtype=float)
    y = np.asarray(xis, dtype=float)
    systems = [System(block, LinearIsolation(Tb=Tb, xi_b=xi, rho=rho)) for Tb in x for xi in y]
    fixed = {"isolation": "linear", "lambda": block.lam, "R_m": block.R, "rho": rho}
    return _grid_map("Tb-xi", "Tb_s", "xi_b", x, y, systems, excitation, amp_g, fixed, **kw)


def _grid_map(
    kind: str,
    x_name: str,
    y_name: str,
    x: np.ndarray,
    y: np.ndarray,
    systems: list[System],
    excitation: Excitation,
    amp_g: float,
    fixed: dict,
    **kw,
) -> RegimeMap:
    """Run the systems of an ``x`` by ``y`` grid (x-major order) and shape the result as a map."""
    t0 = time.perf_counter()
    out = run_grid(systems, excitation, amp_g, **kw)
    secs = time.perf_counter() - t0
    shape = (x.size, y.size)
    return RegimeMap(
        kind,
        x_name,
        y_name,
        x,
        y,
        out[:, 0].reshape(shape).astype(np.int8),
        out[:, 1].reshape(shape),
        amp_g,
        fixed,
        len(systems),
        secs,
    )
