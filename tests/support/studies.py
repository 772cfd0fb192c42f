"""Small computations behind the paper's qualitative claims (``tests/analysis/test_paper_claims.py``).

Each helper compares the isolated block with the same block on the ground, or inspects a regime map:

* :func:`uplift_ratio` -- uplift amplitude isolated / non-isolated (above 1: isolation delays rocking);
* :func:`overturn_ratio` -- minimum overturning amplitude isolated / non-isolated (above 1: isolation
  improves the stability);
* :func:`min_overturn_norm` -- minimum overturning amplitude in units of ``g tan(alpha)``;
* :func:`osc_columns` -- sizes ``R`` at which, in a lambda-R map, overturning at some ``lambda`` is
  followed by no overturning at a larger ``lambda``: the stability boundary is not single-valued.

The parameter studies that feed the figures are run by the workflow (:mod:`isorock.pipeline`).
Amplitudes are in g (pulse amplitude ``A_g0/g`` or record PGA).
"""

from __future__ import annotations

import math

import numpy as np

from isorock.physics.excitation import Excitation
from isorock.physics.model import Block, Isolation, NoIsolation, System
from isorock.physics.overturning import min_overturn_amplitude, uplift_amplitude

__all__ = ["uplift_ratio", "overturn_ratio", "min_overturn_norm", "osc_columns"]


# ------------------------------------------------------------------------------------ claim helpers
def uplift_ratio(block: Block, isolation: Isolation, excitation: Excitation) -> float:
    """Uplift amplitude of the isolated block over that of the same block on the ground [-].

    Above 1: isolation raises the acceleration needed to start rocking.

    Parameters
    ----------
    block : Block
        The block.
    isolation : LinearIsolation or FPIsolation
        The isolator.
    excitation : Pulse or GroundMotion
        Input shape.
    """
    a_iso, _ = uplift_amplitude(System(block, isolation), excitation)
    a_ground, _ = uplift_amplitude(System(block, NoIsolation()), excitation)
    return a_iso / a_ground


def min_overturn_norm(
    block: Block,
    isolation: Isolation,
    excitation: Excitation,
    *,
    amp_max: float = 40.0,
    growth: float = 1.005,
) -> float:
    """Minimum overturning amplitude over ``g tan(alpha)`` [-] (NaN if nothing up to ``amp_max`` g overturns).

    Parameters
    ----------
    block : Block
        The block.
    isolation : NoIsolation, LinearIsolation or FPIsolation
        The base.
    excitation : Pulse or GroundMotion
        Input shape.
    amp_max : float
        Largest amplitude searched [g].
    growth : float
        Ratio of the scan grid [-].
    """
    m = min_overturn_amplitude(System(block, isolation), excitation, amp_max=amp_max, growth=growth)
    return math.nan if m.min_overturn_g is None else m.min_overturn_g / block.tan_alpha


def overturn_ratio(
    block: Block,
    isolation: Isolation,
    excitation: Excitation,
    *,
    amp_max: float = 40.0,
    growth: float = 1.005,
) -> float:
    """Minimum overturning amplitude of the isolated block over that of the block on the ground [-].

    Above 1: isolation improves the stability. ``inf`` when only the block on the ground overturns up
    to ``amp_max``, ``0`` in the opposite case, NaN when neither does.

    Parameters
    ----------
    block : Block
        The block.
    isolation : LinearIsolation or FPIsolation
        The isolator.
    excitation : Pulse or GroundMotion
        Input shape.
    amp_max : float
        Largest amplitude searched [g].
    growth : float
        Ratio of the scan grid [-].
    """
    kw = {"amp_max": amp_max, "growth": growth}
    a_iso = min_overturn_amplitude(System(block, isolation), excitation, **kw).min_overturn_g
    a_ground = min_overturn_amplitude(System(block, NoIsolation()), excitation, **kw).min_overturn_g
    if a_iso is None and a_ground is None:
        return math.nan
    if a_iso is None:
        return math.inf
    if a_ground is None:
        return 0.0
    return a_iso / a_ground


def osc_columns(codes: np.ndarray) -> np.ndarray:
    """Sizes at which overturning at some slenderness does not imply overturning at larger slenderness.

    Parameters
    ----------
    codes : numpy.ndarray, shape (n_lambda, n_R)
        Regime codes (0 no uplift, 1 rocking, 2 overturn) of a lambda-R map, ``lambda`` increasing
        along axis 0.

    Returns
    -------
    numpy.ndarray of bool, shape (n_R,)
        True where, at that ``R``, some ``lambda_1 < lambda_2`` give overturn at ``lambda_1`` and no
        overturn at ``lambda_2``: the rocking/overturning boundary is not single-valued in ``lambda``.
    """
    ov = np.asarray(codes) == 2
    out = np.zeros(ov.shape[1], dtype=bool)
    for j in range(ov.shape[1]):
        idx = np.flatnonzero(ov[:, j])
        if idx.size:
            out[j] = bool(np.any(~ov[idx[0] :, j]))
    return out
