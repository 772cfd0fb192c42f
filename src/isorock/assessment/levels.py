"""The levels an assessment runs every record at: stripes, design levels and their maximum considered
earthquake (MCE) levels. A light module (no numerics): the workflow's planning reads it for every job."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

__all__ = ["MCE_FACTOR", "mce_levels", "run_levels_of"]

#: the default MCE level as a multiple of the design level (the MCE of ASCE/SEI 7-16 is 1.5 times the
#: design earthquake, §11.4.5: S_DS = 2/3 S_MS)
MCE_FACTOR = 1.5


def mce_levels(design_g: Sequence[float], mce_g: float | Sequence[float] | None = None) -> list[float]:
    """The MCE level of each design level [g]: ``mce_g`` (one value for all, or one per design level),
    by default :data:`MCE_FACTOR` times each design level."""
    design = [float(x) for x in design_g]
    if mce_g is None:
        return [MCE_FACTOR * x for x in design]
    if isinstance(mce_g, int | float):
        return [float(mce_g) for _ in design]
    return [float(x) for x in mce_g]


def run_levels_of(a: Mapping[str, Any]) -> list[float]:
    """Every level of an ``assessment`` section, sorted: stripes, design and MCE levels [g]."""
    design = a.get("design_g") or []
    return sorted({*map(float, a["stripes_g"]), *map(float, design), *mce_levels(design, a.get("mce_g"))})
