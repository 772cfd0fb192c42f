"""Closed-form and semi-analytic reference solutions of docs/model.md §14 (tests only).

Plain numpy/scipy: nothing here calls the engine or the oracle.  Every function states its
accuracy.  Angles in rad, times in s, accelerations in m/s^2 unless stated; ``alpha`` is the
slenderness angle ``atan(b/h)`` and ``p = sqrt(3 g / (4 R))`` the frequency parameter [rad/s].

Contents
--------
* §7  impact coefficients from the impulse-momentum balances (Eqs. 25, 26), solved numerically;
* (B) free rocking of the non-isolated block from rest at ``theta0``: exact impact velocities,
  amplitudes and impact times, and Housner's linearised times;
* (C) rectangular pulse, minimum overturning amplitude: exact semi-analytic and linearised;
* (D) half-sine pulse: linearised first-excursion overturning criterion and its minimal root;
* (D') full-sine pulse: linearised piecewise closed-form response and the scan/bisection minimum;
* (E) linear isolator: exact damped SDOF response to the three pulses, ``max |A1(t)|`` and the
  undamped closed forms of the uplift amplitude.
"""

from .isolator import (
    G,
    linear_max_A1,
    linear_uplift_ratio,
    linear_uplift_ratio_undamped,
    sdof_max_abs_u,
    sdof_pulse_response,
    sdof_total_acc,
)
from .rocking import (
    amplitude_after_impact,
    block_geometry,
    free_impact_velocity0,
    free_impact_velocity0_linear,
    free_period_linear,
    free_rocking_exact,
    free_rocking_linear,
    fullsine_min_overturn_linear,
    fullsine_response_linear,
    halfsine_criterion_linear,
    halfsine_impulse_limit,
    halfsine_min_overturn_linear,
    housner_eps,
    impact_coefficients_closed,
    impact_energy_loss,
    impact_map_numeric,
    next_impact_delay_linear,
    quarter_time_exact,
    quarter_time_linear,
    rect_min_overturn_exact,
    rect_min_overturn_linear,
    rect_overturns_exact,
)

__all__ = [
    "G",
    "sdof_pulse_response",
    "sdof_total_acc",
    "linear_max_A1",
    "linear_uplift_ratio",
    "linear_uplift_ratio_undamped",
    "sdof_max_abs_u",
    "block_geometry",
    "housner_eps",
    "impact_map_numeric",
    "impact_coefficients_closed",
    "impact_energy_loss",
    "free_impact_velocity0",
    "free_impact_velocity0_linear",
    "amplitude_after_impact",
    "quarter_time_exact",
    "quarter_time_linear",
    "free_period_linear",
    "next_impact_delay_linear",
    "free_rocking_exact",
    "free_rocking_linear",
    "rect_min_overturn_linear",
    "rect_overturns_exact",
    "rect_min_overturn_exact",
    "halfsine_criterion_linear",
    "halfsine_min_overturn_linear",
    "halfsine_impulse_limit",
    "fullsine_response_linear",
    "fullsine_min_overturn_linear",
]
