"""The grid entries of the configuration (a list, or ``{start, stop, num[, spacing]}``): their values,
their number and their ends, for the configuration (:mod:`~.config`), its bounds (:mod:`~.bounds`) and
the cost estimate (:mod:`~.cost`)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from isorock.errors import ConfigError

__all__ = ["grid_values", "grid_size", "grid_ends"]


def grid_values(spec: Sequence[float] | Mapping) -> list[float]:
    """The values of a grid entry of the configuration.

    Parameters
    ----------
    spec : list of float or mapping
        A list, or ``{start, stop, num[, spacing]}`` (``spacing`` ``linear`` (default) or ``log``).

    Returns
    -------
    list of float
    """
    if isinstance(spec, Mapping):
        start, stop, num = float(spec["start"]), float(spec["stop"]), int(spec["num"])
        if spec.get("spacing", "linear") == "log":
            if not (start > 0 and stop > 0):
                raise ConfigError(f"log grid {dict(spec)} needs start and stop > 0")
            vals = np.geomspace(start, stop, num)
        else:
            vals = np.linspace(start, stop, num)
        return [float(v) for v in vals]
    return [float(v) for v in spec]


def grid_size(spec: Sequence[float] | Mapping) -> int:
    """The number of values of a grid entry (:func:`grid_values`), without making them: ``num`` of a
    ``{start, stop, num}`` entry, else the length of the list."""
    return int(spec["num"]) if isinstance(spec, Mapping) else len(spec)


def grid_ends(spec: Sequence[float] | Mapping) -> list[float]:
    """The values that bound a grid entry, without making them all: ``[start, stop]`` of a
    ``{start, stop, num}`` entry (linear and log spacing are monotone between them), else the list."""
    if isinstance(spec, Mapping):
        return [float(spec["start"]), float(spec["stop"])] if int(spec["num"]) > 1 else [float(spec["start"])]
    return [float(v) for v in spec]
