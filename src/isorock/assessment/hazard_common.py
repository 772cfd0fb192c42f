"""What the readers of a hazard curve share (:mod:`isorock.assessment.hazard_files`): the checks of the
measure and of the component definition, the great-circle distance, the site's ``[lon, lat]``, and the
trimming of the levels that carry no information (:func:`trim_ends`).

At either end a curve may hold levels that carry no information: OpenQuake writes a poe of 0 above the
largest motion its models reach, and the same poe at low levels where every rupture exceeds them. The
trailing levels whose value is 0 or does not decrease from the level below, and the leading levels
whose value equals the next one's (the curve is flat there: ``|dH| = 0``, nothing of the risk integral
is lost), are dropped, and :attr:`~isorock.assessment.hazard.HazardCurve.notes` says how many and beyond
which level. A curve left with fewer than 3 levels, or that rises between two levels, is refused.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from isorock.errors import ConfigError, ParameterError
from isorock.processing.imt import component_definition as _component_definition
from isorock.processing.imt import parse_imt

__all__ = ["DEFAULT_MAX_DISTANCE_KM", "EARTH_RADIUS_KM", "great_circle_km", "trim_ends"]

#: how far [km] the nearest site of a file may lie from the ``[lon, lat]`` asked
DEFAULT_MAX_DISTANCE_KM = 5.0
#: the mean radius of the Earth [km] (IUGG), for the great-circle distance
EARTH_RADIUS_KM = 6371.0088
_WHERE = "assessment.hazard"


def _imt_str(text: object, where: str) -> str:
    """The canonical string of an intensity measure; a ConfigError naming ``where`` otherwise."""
    try:
        return str(parse_imt(text, where))
    except ParameterError as exc:
        raise ConfigError(str(exc)) from None


def _component(text: object) -> str:
    try:
        return _component_definition(text, f"{_WHERE}.component_definition")
    except ParameterError as exc:
        raise ConfigError(str(exc)) from None


def _unit(imt: str) -> str:
    return "cm/s" if imt == "PGV" else "g"


def _read_text(path: Path) -> str:
    try:
        return path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise ConfigError(f"{path}: not a text file (not UTF-8): not a hazard-curve file") from None
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read the hazard curve: {exc.strerror or exc}") from None


def _resolve(value: object, basedir: str | Path | None) -> Path:
    p = Path(str(value))
    if not p.is_absolute() and basedir is not None:
        p = Path(basedir) / p
    return p


def great_circle_km(lon1: float, lat1: float, lon2: float, lat2: float) -> float:
    """The great-circle distance [km] between two points given in degrees (haversine, on a sphere of
    radius :data:`EARTH_RADIUS_KM`)."""
    p1, p2 = math.radians(lat1), math.radians(lat2)
    dp, dl = p2 - p1, math.radians(lon2 - lon1)
    a = math.sin(dp / 2) ** 2 + math.cos(p1) * math.cos(p2) * math.sin(dl / 2) ** 2
    return 2.0 * EARTH_RADIUS_KM * math.asin(min(1.0, math.sqrt(a)))


def trim_ends(
    levels: np.ndarray, values: np.ndarray, unit: str, what: str
) -> tuple[np.ndarray, np.ndarray, tuple[str, ...]]:
    """Drop the levels of a curve that carry no information, and say so.

    At the top: the trailing levels whose value is 0 or does not decrease from the level below. At the
    bottom: the leading levels whose value equals the next one's, where the curve is flat.

    Parameters
    ----------
    levels : numpy.ndarray
        Increasing levels, in ``unit``.
    values : numpy.ndarray
        The curve at the levels (poe [-] or annual rate [1/yr]), meant to decrease.
    unit : str
        The levels' unit, for the notes (``g``, ``cm/s``).
    what : str
        The values' name in the notes (``poe``, ``annual rate``).

    Returns
    -------
    levels, values : numpy.ndarray
        What is left (possibly fewer than 3 levels: the caller refuses those).
    notes : tuple of str
        One note per end trimmed: how many levels, and beyond which level.
    """
    n = values.size
    zeros = repeats = 0
    while n > 1 and (values[n - 1] <= 0.0 or values[n - 1] >= values[n - 2]):
        if values[n - 1] <= 0.0:
            zeros += 1
        else:
            repeats += 1
        n -= 1
    if n == 1 and values[0] <= 0.0:
        zeros, repeats, n = zeros + 1, repeats, 0
    notes = []
    dropped = zeros + repeats
    if dropped and n > 0:
        why = (
            f"of {what} 0"
            if not repeats
            else f"not below the {what} of the level under them"
            if not zeros
            else f"of {what} 0 or not below the level under them"
        )
        plural = "s" if dropped > 1 else ""
        notes.append(f"{dropped} trailing level{plural} {why} dropped (above {levels[n - 1]:.4g} {unit})")
    first = 0
    while first < n - 1 and values[first] == values[first + 1]:
        first += 1
    if first and n - first >= 1:
        notes.append(
            f"{first} leading level{'s' if first > 1 else ''} of the same {what} as the next dropped "
            f"(the curve is flat below {levels[first]:.4g} {unit})"
        )
    return levels[first:n], values[first:n], tuple(notes)


def _check_decreasing(levels: np.ndarray, values: np.ndarray, where: str, unit: str) -> None:
    rise = np.flatnonzero(np.diff(values) >= 0.0)
    if rise.size:
        i = int(rise[0])
        raise ConfigError(
            f"{where}: the curve does not decrease from {levels[i]:.4g} to {levels[i + 1]:.4g} {unit} "
            f"({values[i]:.4g} then {values[i + 1]:.4g}): not a hazard curve"
        )


def _enough(levels: np.ndarray, where: str, notes: tuple[str, ...]) -> None:
    if levels.size < 3:
        after = f" after {'; '.join(notes)}" if notes else ""
        raise ConfigError(
            f"{where}: {levels.size} level{'s' if levels.size != 1 else ''} with a nonzero, decreasing "
            f"value left{after}: at least 3 are needed (no hazard at this site in the file?)"
        )


def _lonlat(value: object, key: str) -> tuple[float, float]:
    """``[lon, lat]`` in degrees, checked."""
    if not isinstance(value, Sequence) or isinstance(value, str) or len(value) != 2:
        raise ConfigError(f"{key}: {value!r}: give a site index (integer >= 0) or [lon, lat] in degrees")
    try:
        lon, lat = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ConfigError(f"{key}: {value!r}: [lon, lat] must be two numbers (degrees)") from None
    if not (-180.0 <= lon <= 180.0 and -90.0 <= lat <= 90.0):
        raise ConfigError(f"{key}: {value!r}: lon must lie in [-180, 180] and lat in [-90, 90] degrees")
    return lon, lat


def _max_distance(value: object) -> float:
    key = f"{_WHERE}.max_distance_km"
    try:
        d = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ConfigError(f"{key}: {value!r} is not a number (km)") from None
    if isinstance(value, bool) or not (math.isfinite(d) and d > 0.0):
        raise ConfigError(f"{key}: {value!r}: give a positive distance in km")
    return d


def _is_number(s: str) -> bool:
    try:
        float(s)
    except ValueError:
        return False
    return True
