"""Many analyses under one excitation, in parallel threads: the engine's batch interface.

:func:`run_many` packs one parameter vector per (system, scale), runs them with the compiled kernel's
parallel loop (:func:`isorock.physics.engine.kernel.run_many`) and decodes the result vectors into a
:class:`BatchResult` of named arrays. It is the only place outside :func:`isorock.physics.engine.simulate`
that
reads the kernel's result vector, and the only place that sets numba's thread count: the regime maps,
the overturning searches and the assessment's stripes call it instead of the kernel.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

import isorock.physics.engine.kernel as K
from isorock.constants import OUTCOMES
from isorock.physics.excitation import Excitation
from isorock.physics.model import System

__all__ = ["BatchResult", "run_many", "set_threads"]


@dataclass(frozen=True)
class BatchResult:
    """The decoded results of a batch of analyses, one entry per analysis, in input order.

    Attributes
    ----------
    outcome_code : numpy.ndarray of int
        0 no uplift, 1 rocking, 2 overturn (:data:`isorock.constants.OUTCOMES`).
    max_theta_over_alpha : numpy.ndarray
        Peak ``|theta| / alpha`` [-].
    n_impacts : numpy.ndarray of int
        Impacts counted.
    max_base_disp_m : numpy.ndarray
        Peak isolator displacement ``|u|`` [m].
    t_uplift_s, t_overturn_s, t_end_s : numpy.ndarray
        First uplift, overturn (NaN if none) and end of the analysis [s].
    decided : numpy.ndarray of bool
        The outcome is certain (docs/model.md §9).
    n_steps, stalls : numpy.ndarray of int
        Integrator steps and uplift tests refused by the zero-progress guard.
    mu_required : numpy.ndarray
        Peak ``|H| / N`` of the contact force: the friction the block needs not to slide [-]
        (``inf`` where the block jumps: ``H / N`` is not defined there).
    min_normal_over_weight : numpy.ndarray
        Least normal contact force over the weight ``N / (m g)`` [-] (<= 0: the block would jump).
    jumps : numpy.ndarray of bool
        The normal contact force vanishes (``N <= 0``): the block would jump, which the model
        excludes (docs/model.md §15).
    n_slips : numpy.ndarray of int
        Sliding mode (docs/model.md §16): slips counted (0 in the rocking mode).
    sliding_peak_m, sliding_residual_m : numpy.ndarray
        Sliding mode: peak ``|s|`` and final ``s`` of the slip [m] (0 in the rocking mode).
    """

    outcome_code: np.ndarray
    max_theta_over_alpha: np.ndarray
    n_impacts: np.ndarray
    max_base_disp_m: np.ndarray
    t_uplift_s: np.ndarray
    t_overturn_s: np.ndarray
    t_end_s: np.ndarray
    decided: np.ndarray
    n_steps: np.ndarray
    stalls: np.ndarray
    mu_required: np.ndarray
    min_normal_over_weight: np.ndarray
    jumps: np.ndarray
    n_slips: np.ndarray
    sliding_peak_m: np.ndarray
    sliding_residual_m: np.ndarray

    def __len__(self) -> int:
        return int(self.outcome_code.size)

    @property
    def outcome(self) -> list[str]:
        """The outcomes by name (``no_uplift``, ``rocking``, ``overturn``)."""
        return [OUTCOMES[int(c)] for c in self.outcome_code]

    @classmethod
    def decode(cls, res: np.ndarray) -> BatchResult:
        """From the kernel's result vectors (rows x ``NRES``)."""
        res = np.asarray(res, dtype=float).reshape(-1, K.NRES)
        return cls(
            outcome_code=res[:, K.R_OUTCOME].astype(np.int64),
            max_theta_over_alpha=res[:, K.R_MAXTH].copy(),
            n_impacts=res[:, K.R_NIMP].astype(np.int64),
            max_base_disp_m=res[:, K.R_MAXU].copy(),
            t_uplift_s=res[:, K.R_TUP].copy(),
            t_overturn_s=res[:, K.R_TOV].copy(),
            t_end_s=res[:, K.R_TEND].copy(),
            decided=res[:, K.R_DECIDED].astype(bool),
            n_steps=res[:, K.R_NSTEPS].astype(np.int64),
            stalls=res[:, K.R_STALLS].astype(np.int64),
            mu_required=res[:, K.R_MUREQ].copy(),
            min_normal_over_weight=res[:, K.R_NMIN].copy(),
            jumps=res[:, K.R_JUMPS] != 0.0,
            n_slips=res[:, K.R_NSLIP].astype(np.int64),
            sliding_peak_m=res[:, K.R_SPEAK].copy(),
            sliding_residual_m=res[:, K.R_SRES].copy(),
        )


def set_threads(threads: int | None) -> None:
    """Use ``threads`` parallel threads in the batch runs (None or 0: leave numba's setting)."""
    if threads:
        import numba

        # numba.config sets its NUMBA_* attributes at import, from the environment
        top = numba.config.NUMBA_NUM_THREADS  # type: ignore[attr-defined]
        numba.set_num_threads(max(1, min(int(threads), top)))


def run_many(
    systems: Sequence[System],
    excitation: Excitation,
    scales: float | Sequence[float],
    *,
    early_stop: bool = False,
    threads: int | None = None,
    chunk: int | None = None,
    progress: Callable[[int], None] | None = None,
    friction: float | None = None,
) -> BatchResult:
    """Run one analysis per system (full runs unless ``early_stop``) under one excitation, in parallel.

    Parameters
    ----------
    systems : sequence of System
        Block and isolation of each analysis.
    excitation : Pulse or GroundMotion
        The input shared by all the analyses (pulse amplitude in g; record samples in m/s^2).
    scales : float or sequence of float
        Factor multiplying the excitation, one for all or one per system [-].
    early_stop : bool
        Stop each analysis as soon as its outcome is certain (docs/model.md §9): peaks are then partial.
        False: full runs, peaks and reactions over the whole motion and its free vibration.
    threads : int, optional
        Parallel threads (default: numba's setting, all cores).
    chunk : int, optional
        Run the batch in chunks of this many analyses, calling ``progress(n_done_in_chunk)`` after each.
    progress : callable, optional
        Called with the number of analyses finished after each chunk.
    friction : float, optional
        The object's friction coefficient on its base [-]: systems with ``tan(alpha)`` above it are
        analysed in the sliding mode (docs/model.md §16). None: rocking only.

    Returns
    -------
    BatchResult
        The decoded results, in the order of ``systems``.
    """
    from isorock.physics.engine.params import pack_parameters

    n = len(systems)
    sc = np.asarray(scales, dtype=float)
    if sc.ndim == 0:
        sc = np.full(n, float(sc))
    if sc.shape != (n,):
        raise ValueError(f"scales: {sc.size} values for {n} systems (give one for all or one per system)")
    if n == 0:
        return BatchResult.decode(np.zeros((0, K.NRES)))
    rows = []
    ekind, acc = 0, None
    for system, s in zip(systems, sc, strict=True):
        P, ekind, acc = pack_parameters(
            system, excitation, scale=float(s), early_stop=early_stop, friction=friction
        )
        rows.append(P)
    Ps = np.ascontiguousarray(np.array(rows))
    set_threads(threads)
    step = n if not chunk else int(chunk)
    out = np.empty((n, K.NRES))
    for i in range(0, n, step):
        out[i : i + step] = K.run_many(Ps[i : i + step], ekind, acc)
        if progress is not None:
            progress(min(step, n - i))
    return BatchResult.decode(out)
