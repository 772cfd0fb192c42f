"""Results of analyses: one run (:class:`Result`, shared by the compiled engine and the scipy oracle)
and a response-regime map over a parameter grid (:class:`RegimeMap`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from isorock.constants import OUTCOME_CODES, OUTCOMES

__all__ = ["Result", "RegimeMap", "OUTCOMES", "OUTCOME_CODES"]

REGIME_CONTACT = 0
REGIME_ROCKING = 1


@dataclass
class Result:
    """Outcome and peak response of one analysis.

    Attributes
    ----------
    outcome : {"no_uplift", "rocking", "overturn"}
        Response regime.
    max_theta_over_alpha : float
        Peak ``|theta| / alpha`` over the whole analysis [-] (``(pi/2)/alpha`` on overturn).
    n_impacts : int
        Number of impacts at ``theta = 0``, the final cease impact included.
    max_base_disp_m : float
        Peak ``|u|``, base displacement relative to the ground [m] (0 if non-isolated).
    t_uplift_s : float or None
        First uplift instant [s].
    t_overturn_s : float or None
        Instant at which ``|theta|`` reaches ``pi/2`` [s]; None if the block did not overturn, NaN if the
        analysis stopped as soon as overturning was certain (``early_stop``).
    t_end_s : float
        Time at which the analysis ended [s].
    decided : bool
        False if the analysis hit its time limit with the outcome still open.
    stalls : int
        Uplifts the engine's zero-progress guard skipped: after 1000 events at one instant (a block
        chattering at the uplift threshold) uplift is no longer tested there. 0 in a sound analysis;
        a positive count means the outcome may have missed an uplift and is reported with a warning.
    mu_required : float
        Peak ratio of the horizontal to the normal contact force between block and base over the
        whole motion, free vibration after the input included [-]: the friction coefficient the
        model's no-sliding assumption needs (``|A|_max / g`` over the intervals in full contact).
        ``inf`` when the block jumps (``H / N`` is not defined once ``N <= 0``; null in
        :meth:`to_dict`), NaN where not computed (the oracle). docs/model.md §15.
    min_normal_over_weight : float
        Least normal contact force over the block's weight [-]: 1 in full contact, below 0 the block
        would jump (the model's no-jumping assumption fails). Impact impulses are not forces and are
        left out of both (their horizontal-to-vertical ratio stays below ``tan(alpha)``, §15).
    jumps : bool or None
        The normal contact force vanishes somewhere (``min_normal_over_weight <= 0``): the block
        would jump and ``mu_required`` is not defined. None where not computed (the oracle).
    t, u, theta, regime, u_dot, theta_dot : numpy.ndarray or None
        Time histories [s, m, rad, 0 contact / 1 rocking / 2 slipping, m/s, rad/s] at the integrator's
        steps (values after the impact map at impact instants), if requested.
    mode : {"rocking", "sliding"}
        The motion analysed: rocking (the paper's model), or sliding for an object whose friction
        coefficient is below ``tan(alpha)`` (docs/model.md §16; its outcome is then ``no_uplift``).
    sliding_peak_m, sliding_residual_m : float or None
        Sliding mode: peak ``|s|`` and final ``s`` of the object's slip on its base [m].
    n_slips : int or None
        Sliding mode: number of slips (starts from sticking).
    t_first_slip_s : float or None
        Sliding mode: instant of the first slip [s].
    slip, slip_dot : numpy.ndarray or None
        Sliding mode: histories of the slip [m] and its rate [m/s], if requested.
    """

    outcome: str
    max_theta_over_alpha: float
    n_impacts: int
    max_base_disp_m: float
    t_uplift_s: float | None
    t_overturn_s: float | None
    t_end_s: float
    decided: bool = True
    n_steps: int = 0
    stalls: int = 0
    mu_required: float = math.nan
    min_normal_over_weight: float = math.nan
    jumps: bool | None = None
    t: np.ndarray | None = field(default=None, repr=False)
    u: np.ndarray | None = field(default=None, repr=False)
    theta: np.ndarray | None = field(default=None, repr=False)
    regime: np.ndarray | None = field(default=None, repr=False)
    u_dot: np.ndarray | None = field(default=None, repr=False)
    theta_dot: np.ndarray | None = field(default=None, repr=False)
    mode: str = "rocking"
    sliding_peak_m: float | None = None
    sliding_residual_m: float | None = None
    n_slips: int | None = None
    t_first_slip_s: float | None = None
    slip: np.ndarray | None = field(default=None, repr=False)
    slip_dot: np.ndarray | None = field(default=None, repr=False)

    @property
    def outcome_code(self) -> int:
        """0 no uplift, 1 rocking, 2 overturn."""
        return OUTCOME_CODES[self.outcome]

    def to_dict(self) -> dict:
        """JSON-ready summary (histories left out).

        ``mu_required`` is null where the block jumps (``jumps`` true) or where the reactions were
        not computed (``jumps`` null); a run that does not jump always has a number.
        """

        def num(x: float | None) -> float | None:
            return None if x is None or (isinstance(x, float) and math.isnan(x)) else float(x)

        out = {
            "mode": self.mode,
            "outcome": self.outcome,
            "max_theta_over_alpha": float(self.max_theta_over_alpha),
            "n_impacts": int(self.n_impacts),
            "max_base_disp_m": float(self.max_base_disp_m),
            "t_uplift_s": num(self.t_uplift_s),
            "t_overturn_s": num(self.t_overturn_s),
            "t_end_s": float(self.t_end_s),
            "decided": bool(self.decided),
            "stalls": int(self.stalls),
            "mu_required": None if self.jumps else num(self.mu_required),
            "min_normal_over_weight": num(self.min_normal_over_weight),
            "jumps": None if self.jumps is None else bool(self.jumps),
        }
        if self.mode == "sliding":
            out["sliding_peak_m"] = num(self.sliding_peak_m)
            out["sliding_residual_m"] = num(self.sliding_residual_m)
            out["n_slips"] = None if self.n_slips is None else int(self.n_slips)
            out["t_first_slip_s"] = num(self.t_first_slip_s)
        return out

    def outside_model(self, friction: float) -> bool:
        """The block would slide (``mu_required > friction`` [-]) or jump: the result is outside the model."""
        return bool(self.mu_required > friction or self.min_normal_over_weight <= 0.0)


@dataclass
class RegimeMap:
    """Response-regime map over a 2-D parameter grid.

    Attributes
    ----------
    kind : {"lambda-R", "Tb-xi"}
        Grid axes.
    x_name, y_name : str
        Axis names (``lambda`` and ``R_m``, or ``Tb_s`` and ``xi_b``).
    x, y : numpy.ndarray
        Axis values (units in the names).
    codes : numpy.ndarray of int8, shape (len(x), len(y))
        0 no uplift, 1 rocking, 2 overturn.
    max_theta_over_alpha : numpy.ndarray, shape (len(x), len(y))
        Peak ``|theta|/alpha`` (partial: the analyses stop as soon as the outcome is certain).
    amp_g : float
        Excitation amplitude (pulse amplitude or record PGA) [g].
    fixed : dict
        The parameters held fixed (isolation, lambda, R, rho...).
    n_analyses : int
        Engine runs.
    seconds : float
        Wall time of the analyses [s].
    """

    kind: str
    x_name: str
    y_name: str
    x: np.ndarray
    y: np.ndarray
    codes: np.ndarray
    max_theta_over_alpha: np.ndarray
    amp_g: float
    fixed: dict
    n_analyses: int
    seconds: float

    def counts(self) -> dict[str, int]:
        """Number of grid points in each regime."""
        return {name: int(np.sum(self.codes == k)) for k, name in enumerate(OUTCOMES)}
