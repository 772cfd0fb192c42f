"""The hazard curve of a response of the USGS hazard service (:func:`read_usgs`).

USGS
    The legacy layout of the USGS hazard service (nshmp-haz-ws, ``/hazard/{edition}/{region}/
    {lon}/{lat}/{imt}/{vs30}`` with ``any`` measure): ``{"response": [{"metadata": {"imt": {"value":
    "PGA"}, "vs30": {"value": "760"}, "latitude": .., "longitude": .., "xvalues": [...]}, "data":
    [{"component": "Total", "yvalues": [...]}, ...]}, ...]}``, annual frequencies of exceedance
    already. The response of the ``imt`` asked (``SA1P0`` or ``SA(1.0)``) is taken, its ``Total``
    component; the Vs30 and the location are kept. The current nshmp-haz layout (``response.
    hazardCurves[].data[].values.xs/ys``) is recognised and refused: no real response of it was at
    hand to test a reader against.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from isorock.assessment.hazard import HazardCurve
from isorock.assessment.hazard_common import (
    _WHERE,
    DEFAULT_MAX_DISTANCE_KM,
    _check_decreasing,
    _component,
    _enough,
    _imt_str,
    _is_number,
    _lonlat,
    _read_text,
    _unit,
    great_circle_km,
    trim_ends,
)
from isorock.errors import ConfigError

__all__ = ["read_usgs"]


def _get(d: Any, keys: tuple[str | int, ...], p: Path, what: str, at: str = "") -> Any:
    """``d[k0][k1]...``, or a ConfigError naming the JSON path (after ``at``) and the file."""
    cur = d
    for k in keys:
        try:
            cur = cur[k]
        except (KeyError, IndexError, TypeError):
            name = at + "".join(f"[{k}]" if isinstance(k, int) else f".{k}" for k in keys)
            name = name.lstrip(".")
            raise ConfigError(
                f"{p}: {name}: missing ({what}): not the USGS hazard service's layout?"
            ) from None
    return cur


def _usgs_responses(p: Path) -> list[Any]:
    """The list ``response`` of a legacy nshmp-haz-ws JSON (other layouts refused)."""
    try:
        doc = json.loads(_read_text(p))
    except json.JSONDecodeError as exc:
        raise ConfigError(f"{p}:{exc.lineno}: not JSON: {exc.msg}") from None
    if not isinstance(doc, Mapping):
        raise ConfigError(f"{p}: not the USGS hazard service's JSON (an object with 'response')")
    if doc.get("status") not in (None, "success"):
        msg = str(doc.get("message") or "").strip().splitlines()
        raise ConfigError(
            f"{p}: the service answered status {doc.get('status')!r}{': ' + msg[0][:100] if msg else ''}"
        )
    resp = doc.get("response")
    if isinstance(resp, Mapping) and "hazardCurves" in resp:
        raise ConfigError(
            f"{p}: the current nshmp-haz layout (response.hazardCurves) is not read: isorock reads the "
            "legacy nshmp-haz-ws layout (response: [{metadata, data}]); give the curve as file or points"
        )
    if not isinstance(resp, list) or not resp:
        raise ConfigError(
            f"{p}: no 'response' list of curves (the legacy nshmp-haz-ws layout): not a USGS hazard file?"
        )
    return resp


def _usgs_pick(resp: list[Any], p: Path, imt: object) -> tuple[int, str]:
    """The response of the measure asked, and its canonical string."""
    imts = [
        _imt_str(
            _get(r, ("metadata", "imt", "value"), p, "the measure", f"response[{i}]"),
            f"{p}: response[{i}].metadata.imt",
        )
        for i, r in enumerate(resp)
    ]
    key, have = f"{_WHERE}.imt", ", ".join(dict.fromkeys(imts))
    if imt is None:
        if len(set(imts)) != 1:
            raise ConfigError(f"{key}: {p} holds the curves of {len(set(imts))} measures ({have}): name one")
        want = imts[0]
    else:
        want = _imt_str(imt, key)
    hits = [i for i, s in enumerate(imts) if s == want]
    if not hits:
        raise ConfigError(f"{key}: {want}: {p} holds no curve of it (it has {have})")
    if len(hits) > 1:
        raise ConfigError(f"{key}: {want}: {p} holds {len(hits)} curves of it (responses {hits}): keep one")
    return hits[0], want


def _usgs_total(r: Any, p: Path, i: int, where: str) -> tuple[np.ndarray, np.ndarray]:
    """The levels and the annual rates of the ``Total`` component of one response."""
    data = _get(r, ("data",), p, "the components", f"response[{i}]")
    comps = (
        [str(c.get("component")) if isinstance(c, Mapping) else "?" for c in data]
        if isinstance(data, list)
        else []
    )
    total = [c for c, name in zip(data or [], comps, strict=False) if name == "Total"]
    if not total:
        raise ConfigError(f"{where}: no 'Total' component (it has {', '.join(comps) or 'none'})")
    try:
        xs = np.asarray(_get(r, ("metadata", "xvalues"), p, "the levels", f"response[{i}]"), dtype=float)
        ys = np.asarray(
            _get(total[0], ("yvalues",), p, "the annual rates", f"response[{i}].data[Total]"), dtype=float
        )
    except (TypeError, ValueError):
        raise ConfigError(f"{where}: xvalues and yvalues must be lists of numbers") from None
    if xs.ndim != 1 or xs.shape != ys.shape:
        raise ConfigError(f"{where}: {xs.size} xvalues but {ys.size} yvalues of the Total component")
    if not (np.all(np.isfinite(xs)) and np.all(xs > 0) and np.all(np.diff(xs) > 0)):
        raise ConfigError(f"{where}: the xvalues must be positive and increase")
    if not (np.all(np.isfinite(ys)) and np.all(ys >= 0)):
        raise ConfigError(f"{where}: the yvalues must be annual rates >= 0")
    return xs, ys


def _usgs_location(md: Any, where: str) -> tuple[float, float, float | None]:
    """Longitude, latitude [deg] and Vs30 [m/s] (None where not given) of a response's metadata."""
    try:
        lon, lat = float(md["longitude"]), float(md["latitude"])
    except (KeyError, TypeError, ValueError):
        raise ConfigError(f"{where}: the metadata give no longitude and latitude") from None
    v = md.get("vs30")
    raw = v.get("value") if isinstance(v, Mapping) else v
    if raw is None:
        return lon, lat, None
    if not _is_number(str(raw)):
        raise ConfigError(f"{where}: metadata.vs30 {raw!r} is not a velocity (m/s)")
    return lon, lat, float(raw)


def read_usgs(
    path: str | Path,
    imt: str | None = None,
    component_definition: str = "RotD50",
    site: Sequence[float] | None = None,
    max_distance_km: float = DEFAULT_MAX_DISTANCE_KM,
) -> HazardCurve:
    """The ``Total`` curve of one measure from a JSON of the USGS hazard service (legacy nshmp-haz-ws
    layout; see the module docstring).

    Parameters
    ----------
    path : str or Path
        The JSON file, as the service returned it.
    imt : str or None
        The measure (``PGA``, ``SA1P0`` or ``SA(1.0)``); None only for a file of one measure.
    component_definition : str
        ``RotD50`` (default: the USGS maps'), ``RotD100`` or ``analysed``.
    site : [lon, lat] or None
        Where the curve is wanted [deg]: refused if the file's location is farther than
        ``max_distance_km``.
    max_distance_km : float
        [km].

    Returns
    -------
    HazardCurve
        Levels in the measure's unit (g), annual frequencies of exceedance [1/yr], ``kind="Total"``,
        the Vs30 [m/s] and the location kept, ``origin="usgs"``.

    Raises
    ------
    ConfigError
        Not JSON, another layout, no curve of the measure, no Total component, a measure not named where
        the file holds several, or fewer than 3 levels left.
    """
    p = Path(path)
    resp = _usgs_responses(p)
    i, want = _usgs_pick(resp, p, imt)
    where = f"{p}: response[{i}] ({want}, Total)"
    xs, ys = _usgs_total(resp[i], p, i, where)
    lon, lat, vs30 = _usgs_location(resp[i]["metadata"], where)
    site_words = f"lon {lon:g}, lat {lat:g}"
    if site is not None:
        if isinstance(site, int) and not isinstance(site, bool):
            raise ConfigError(
                f"{_WHERE}.site: {site}: a USGS file holds one location: give [lon, lat] or none"
            )
        lon0, lat0 = _lonlat(site, f"{_WHERE}.site")
        d = great_circle_km(lon0, lat0, lon, lat)
        if d > max_distance_km:
            raise ConfigError(
                f"{_WHERE}.site: [{lon0:g}, {lat0:g}]: {p} is computed at {site_words}, {d:.3g} km away, "
                f"beyond max_distance_km {max_distance_km:g} km"
            )
    unit = _unit(want)
    x, h, notes = trim_ends(xs, ys, unit, "annual rate")
    _enough(x, where, notes)
    _check_decreasing(x, h, where, unit)
    return HazardCurve(
        x,
        h,
        str(p),
        imt=want,
        component_definition=_component(component_definition),
        kind="Total",
        site=site_words,
        vs30_m_s=vs30,
        notes=notes,
        origin="usgs",
    )
