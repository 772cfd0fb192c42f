"""The site's hazard curve read from the files the field produces: OpenQuake's and the USGS service's.

Four sources of ``assessment.hazard`` (exactly one): ``openquake`` (a hazard-curve CSV of the
OpenQuake engine), ``usgs`` (the JSON of the USGS hazard service), ``file`` (a CSV with the columns
``level,annual_rate``) and ``points`` (``[[level, annual_rate], ...]``). Each gives a
:class:`~isorock.assessment.hazard.HazardCurve` that names its intensity measure (``imt``, OpenQuake's
canonical string: :func:`isorock.processing.imt.parse_imt`), its component definition (RotD50 unless
``component_definition`` says otherwise, and then stated as assumed: the current ground-motion models,
and the USGS hazard curves made with them, give RotD50), its statistic and its site.

At either end a curve may hold levels that carry no information: OpenQuake writes a poe of 0 above the
largest motion its models reach, and the same poe at low levels where every rupture exceeds them. The
trailing levels whose value is 0 or does not decrease from the level below, and the leading levels
whose value equals the next one's (the curve is flat there: ``|dH| = 0``, nothing of the risk integral
is lost), are dropped, and :attr:`HazardCurve.notes` says how many and beyond which level. A curve left
with fewer than 3 levels, or that rises between two levels, is refused.

Every error is a :class:`~isorock.errors.ConfigError` of one line that names the file (with the line,
the site or the key) and the problem.

The readers of the two formats are :mod:`isorock.assessment.hazard_openquake` and
:mod:`isorock.assessment.hazard_usgs` (one format each, as ObsPy's ``io/<format>`` plugins), what they
share is :mod:`isorock.assessment.hazard_common`; their functions are re-exported here.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path

import numpy as np

from isorock.assessment.hazard import HazardCurve
from isorock.assessment.hazard_common import (
    _WHERE,
    DEFAULT_MAX_DISTANCE_KM,
    EARTH_RADIUS_KM,
    _component,
    _imt_str,
    _max_distance,
    _resolve,
    great_circle_km,
    trim_ends,
)
from isorock.assessment.hazard_openquake import openquake_metadata, poe_to_rate, read_openquake
from isorock.assessment.hazard_usgs import read_usgs
from isorock.errors import ConfigError

__all__ = [
    "SOURCES",
    "DEFAULT_MAX_DISTANCE_KM",
    "EARTH_RADIUS_KM",
    "curve_from_config",
    "read_openquake",
    "read_usgs",
    "read_level_rate_csv",
    "from_points",
    "openquake_metadata",
    "poe_to_rate",
    "great_circle_km",
    "trim_ends",
]

#: the keys of ``assessment.hazard`` that give the curve (exactly one)
SOURCES: tuple[str, ...] = ("openquake", "usgs", "file", "points")
_KEYS = frozenset(SOURCES) | {"site", "max_distance_km", "imt", "component_definition"}


def read_level_rate_csv(
    path: str | Path, imt: str = "PGA", component_definition: str = "RotD50"
) -> HazardCurve:
    """A CSV with the header ``level,annual_rate`` (levels in the measure's unit, rates [1/yr]), as
    :meth:`HazardCurve.from_csv`, naming its measure and component definition."""
    curve = HazardCurve.from_csv(path)
    return replace(
        curve, imt=_imt_str(imt, f"{_WHERE}.imt"), component_definition=_component(component_definition)
    )


def from_points(points: object, imt: str = "PGA", component_definition: str = "RotD50") -> HazardCurve:
    """A curve given inline: ``[[level, annual_rate], ...]`` (levels in the measure's unit, rates
    [1/yr]; at least 3, levels increasing, rates decreasing)."""
    try:
        pts = np.asarray(points, dtype=float)
    except (TypeError, ValueError):
        pts = np.empty((0,))
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise ConfigError(f"{_WHERE}.points: give pairs [level, annual_rate]")
    return HazardCurve(
        pts[:, 0],
        pts[:, 1],
        "inline",
        imt=_imt_str(imt, f"{_WHERE}.imt"),
        component_definition=_component(component_definition),
        origin="inline",
    )


def curve_from_config(d: Mapping, basedir: str | Path | None = None) -> HazardCurve:
    """The curve ``assessment.hazard`` names.

    Parameters
    ----------
    d : Mapping
        Exactly one of ``openquake``, ``usgs``, ``file`` (paths) or ``points``; optionally ``site``
        (integer >= 0 or [lon, lat] in degrees; openquake and usgs), ``max_distance_km`` [km],
        ``imt`` and ``component_definition``.
    basedir : str or Path or None
        Where a relative path is (None: as given).

    Returns
    -------
    HazardCurve

    Raises
    ------
    ConfigError
        None or several sources, an unknown key, a site for a source without sites, and what the readers
        refuse.
    """
    if not isinstance(d, Mapping):
        raise ConfigError(f"{_WHERE}: give a mapping with one of {', '.join(SOURCES)}")
    unknown = sorted(set(map(str, d)) - _KEYS)
    if unknown:
        raise ConfigError(f"{_WHERE}: unknown key {unknown[0]!r} (valid: {', '.join(sorted(_KEYS))})")
    given = [k for k in SOURCES if d.get(k) is not None]
    if len(given) != 1:
        said = f" (given: {', '.join(given)})" if given else ""
        raise ConfigError(f"{_WHERE}: give exactly one of {', '.join(SOURCES)}{said}")
    src = given[0]
    site = d.get("site")
    if (site is not None or d.get("max_distance_km") is not None) and src not in ("openquake", "usgs"):
        k = "site" if site is not None else "max_distance_km"
        raise ConfigError(f"{_WHERE}.{k}: only with openquake or usgs (a {src} curve is already one site's)")
    dmax = (
        _max_distance(d["max_distance_km"])
        if d.get("max_distance_km") is not None
        else DEFAULT_MAX_DISTANCE_KM
    )
    comp = str(d["component_definition"]) if d.get("component_definition") is not None else "RotD50"
    imt = str(d["imt"]) if d.get("imt") is not None else None
    stated = d.get("component_definition") is not None
    if src == "openquake":
        curve = read_openquake(_resolve(d[src], basedir), site, imt, comp, dmax)
    elif src == "usgs":
        curve = read_usgs(_resolve(d[src], basedir), imt, comp, site, dmax)
    elif src == "file":
        curve = read_level_rate_csv(_resolve(d[src], basedir), imt if imt is not None else "PGA", comp)
    else:
        curve = from_points(d["points"], imt if imt is not None else "PGA", comp)
    return replace(curve, component_stated=stated)
