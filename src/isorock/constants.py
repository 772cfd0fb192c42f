"""Constants shared by every part of isorock: gravity, acceleration units, pulse shapes, outcome codes.

Each is defined here once; the physics (:mod:`isorock.physics.model`), the record readers (:mod:`isorock.io`),
the processing steps, the store and the command line import them from this module.
"""

from __future__ import annotations

__all__ = [
    "G",
    "UNIT_FACTORS",
    "UNITS",
    "PULSE_SHAPES",
    "OUTCOMES",
    "OUTCOME_CODES",
    "OUTCOME_LEGEND",
    "ISOLATION_KINDS",
    "ENV_RECORDS",
]

G = 9.81
"""Acceleration of gravity used throughout isorock [m/s^2]."""

UNIT_FACTORS: dict[str, float] = {"g": G, "m/s2": 1.0, "cm/s2": 0.01, "mm/s2": 1e-3}
"""Canonical acceleration unit -> factor to m/s^2 [m/s^2 per unit]."""

UNITS: tuple[str, ...] = tuple(UNIT_FACTORS)
"""Canonical names of the acceleration units isorock reads (aliases such as ``gal`` map onto them)."""

PULSE_SHAPES: tuple[str, ...] = ("rect", "halfsine", "fullsine")
"""The paper's pulses (Eqs. 36-38), in the order of their integer codes 0, 1, 2 in the engine."""

OUTCOMES: tuple[str, ...] = ("no_uplift", "rocking", "overturn")
"""Outcome categories, in the order of their integer codes 0, 1, 2."""

OUTCOME_CODES: dict[str, int] = {name: code for code, name in enumerate(OUTCOMES)}
"""Outcome name -> integer code."""

OUTCOME_LEGEND = "0 = no uplift, 1 = rocking, 2 = overturn"
"""Legend of the integer outcome codes, written beside every regime map."""

ISOLATION_KINDS: tuple[str, ...] = ("none", "linear", "fp")
"""Isolation models: the block on the ground, a linear visco-elastic isolator, a friction pendulum."""

ENV_RECORDS = "ISOROCK_RECORDS"
"""Environment variable naming the user's records directory."""
