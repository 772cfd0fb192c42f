"""The site's hazard curve read from the files the field produces: OpenQuake's and the USGS service's.

Four sources of ``assessment.hazard`` (exactly one): ``openquake`` (a hazard-curve CSV of the
OpenQuake engine), ``usgs`` (the JSON of the USGS hazard service), ``file`` (a CSV with the columns
``level,annual_rate``) and ``points`` (``[[level, annual_rate], ...]``). Each gives a
:class:`~isorock.assessment.hazard.HazardCurve` that names its intensity measure (``imt``, OpenQuake's
canonical string: :func:`isorock.processing.imt.parse_imt`), its component definition (RotD50 unless
``component_definition`` says otherwise: the current ground-motion models and the USGS maps give
RotD50), its statistic and its site.

OpenQuake
    The engine writes one CSV per measure and statistic (``hazard_curve-mean-PGA_*.csv``,
    ``hazard_curve-mean_SA(0.2)_*.csv``, ``quantile_curve-0.84-PGA_*.csv``). Its first line is a ``#``
    metadata line, in one of two styles: the engine 3.x since 2019 writes one CSV row whose last cell
    is quoted, ``#,,,,"generated_by='OpenQuake engine 3.7.0', ..., kind='mean',
    investigation_time=50.0, imt='SA(0.2)'"``; older engines ``# source_model_tree_path=('b1',), ...,
    investigation_time=1.0,imt="PGA"``. The ``imt`` and ``investigation_time`` are read there, the
    ``kind`` too (else from the file's name; empty if neither says). The header then names the columns
    (``custom_site_id`` and ``depth`` are optional, read by name) and the levels
    ``poe-0.0050000, ...``; one row per site, numbered from 0 as OpenQuake numbers them. The values
    are probabilities of exceedance in the investigation time ``T`` [yr]; with Poisson occurrences the
    annual rate is

        lambda = -ln(1 - poe) / T ,

    (a poe of 1 is an infinite rate and is refused). ``site: N`` takes row ``N``; ``site: [lon,
    lat]`` the nearest row by great-circle distance, refused beyond ``max_distance_km``
    (:data:`DEFAULT_MAX_DISTANCE_KM`) or where several rows lie at the same distance (one location
    computed for several site classes). An ``imt`` given in the configuration must be the file's.

USGS
    The legacy layout of the USGS hazard service (nshmp-haz-ws, ``/hazard/{edition}/{region}/
    {lon}/{lat}/{imt}/{vs30}`` with ``any`` measure): ``{"response": [{"metadata": {"imt": {"value":
    "PGA"}, "vs30": {"value": "760"}, "latitude": .., "longitude": .., "xvalues": [...]}, "data":
    [{"component": "Total", "yvalues": [...]}, ...]}, ...]}``, annual frequencies of exceedance
    already. The response of the ``imt`` asked (``SA1P0`` or ``SA(1.0)``) is taken, its ``Total``
    component; the Vs30 and the location are kept. The current nshmp-haz layout (``response.
    hazardCurves[].data[].values.xs/ys``) is recognised and refused: no real response of it was at
    hand to test a reader against.

At either end a curve may hold levels that carry no information: OpenQuake writes a poe of 0 above the
largest motion its models reach, and the same poe at low levels where every rupture exceeds them. The
trailing levels whose value is 0 or does not decrease from the level below, and the leading levels
whose value equals the next one's (the curve is flat there: ``|dH| = 0``, nothing of the risk integral
is lost), are dropped, and :attr:`HazardCurve.notes` says how many and beyond which level. A curve left
with fewer than 3 levels, or that rises between two levels, is refused.

Every error is a :class:`~isorock.errors.ConfigError` of one line that names the file (with the line,
the site or the key) and the problem.
"""

from __future__ import annotations

import csv
import json
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ConfigError, ParameterError
from ..processing.imt import component_definition as _component_definition
from ..processing.imt import parse_imt
from .hazard import HazardCurve

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
#: how far [km] the nearest site of a file may lie from the ``[lon, lat]`` asked
DEFAULT_MAX_DISTANCE_KM = 5.0
#: the mean radius of the Earth [km] (IUGG), for the great-circle distance
EARTH_RADIUS_KM = 6371.0088
_WHERE = "assessment.hazard"
_META = re.compile(r"""(\w+)\s*=\s*('[^']*'|"[^"]*"|\([^)]*\)|[^,]*)""")
_KIND_FROM_NAME = (
    re.compile(r"^(?:hazard_curve|hcurves?)-(mean|max|rlz-\d+)(?=[-_.(]|$)", re.IGNORECASE),
    re.compile(r"^quantile_curve-([0-9]*\.?[0-9]+)(?=[-_])", re.IGNORECASE),
)


# --------------------------------------------------------------------------------------------- helpers


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


def poe_to_rate(poe: np.ndarray, investigation_time_yr: float) -> np.ndarray:
    """Annual rates of exceedance [1/yr] from probabilities of exceedance in ``investigation_time_yr``.

    Poisson occurrences: ``lambda = -ln(1 - poe) / T``.

    Parameters
    ----------
    poe : numpy.ndarray
        Probabilities of exceedance in the investigation time, in ``[0, 1)`` [-].
    investigation_time_yr : float
        OpenQuake's ``investigation_time`` [yr], > 0.

    Returns
    -------
    numpy.ndarray
        The annual rates [1/yr] (0 where the poe is 0).
    """
    return -np.log1p(-np.asarray(poe, dtype=float)) / float(investigation_time_yr)


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


# ------------------------------------------------------------------------------------------- OpenQuake


def openquake_metadata(line: str, path: str | Path = "") -> dict[str, str]:
    """The ``key=value`` pairs of an OpenQuake CSV's first line (both styles), quotes removed.

    Raises
    ------
    ConfigError
        The line does not start with ``#`` or holds no ``key=value``.
    """
    s = line.strip().lstrip("\ufeff")
    if not s.startswith("#"):
        raise ConfigError(
            f"{path}:1: expected OpenQuake's metadata line starting with '#' (#,,,\"generated_by=..., "
            f'investigation_time=..., imt=..."), got {s[:60]!r}'
        )
    body = s.lstrip("#").lstrip(", \t")
    if len(body) >= 2 and body[0] == body[-1] == '"':
        body = body[1:-1].replace('""', '"')
    meta = {}
    for m in _META.finditer(body):
        v = m.group(2).strip()
        if len(v) >= 2 and v[0] == v[-1] and v[0] in "'\"":
            v = v[1:-1]
        meta[m.group(1)] = v
    if not meta:
        raise ConfigError(f"{path}:1: the metadata line holds no key=value pair: {s[:60]!r}")
    return meta


def _kind_from_name(name: str) -> str:
    m = _KIND_FROM_NAME[0].match(name)
    if m:
        return m.group(1).lower()
    m = _KIND_FROM_NAME[1].match(name)
    return f"quantile-{m.group(1)}" if m else ""


def _is_number(s: str) -> bool:
    try:
        float(s)
    except ValueError:
        return False
    return True


def _oq_time_imt(meta: Mapping[str, str], p: Path, imt: object) -> tuple[float, str]:
    """The investigation time [yr] and the measure of an OpenQuake file, checked against ``imt``."""
    if "investigation_time" not in meta:
        raise ConfigError(
            f"{p}:1: the metadata line gives no investigation_time (the poes are over it): "
            "not an OpenQuake hazard-curve file?"
        )
    t_yr = float(meta["investigation_time"]) if _is_number(meta["investigation_time"]) else math.nan
    if not (math.isfinite(t_yr) and t_yr > 0.0):
        raise ConfigError(
            f"{p}:1: investigation_time={meta['investigation_time']!r}: not a positive number of years"
        )
    want = _imt_str(imt, f"{_WHERE}.imt") if imt is not None else None
    if "imt" not in meta:
        if want is None:
            raise ConfigError(f"{p}:1: the metadata line names no imt: give {_WHERE}.imt (PGA, SA(1.0), ...)")
        return t_yr, want
    file_imt = _imt_str(meta["imt"], f"{p}:1: imt")
    if want is not None and want != file_imt:
        raise ConfigError(
            f"{_WHERE}.imt: {want} but {p} holds the curves of {file_imt}: name the file of {want}, or "
            f"set imt to {file_imt}"
        )
    return t_yr, file_imt


class _Sites:
    """The rows of an OpenQuake CSV: their line numbers, fields and the columns of the header."""

    def __init__(self, p: Path, lines: list[str]) -> None:
        self.p = p
        if len(lines) < 2:
            raise ConfigError(f"{p}:2: no header line (lon,lat,poe-...)")
        header = [c.strip() for c in next(csv.reader([lines[1]]))]
        self.poe_cols = [j for j, c in enumerate(header) if c.startswith("poe-")]
        if "lon" not in header or "lat" not in header or not self.poe_cols:
            raise ConfigError(
                f"{p}:2: the header must name lon, lat and the levels poe-<level> "
                f"(got {','.join(header)[:80]!r})"
            )
        bad = [header[j] for j in self.poe_cols if not _is_number(header[j][4:])]
        if bad:
            raise ConfigError(f"{p}:2: {bad[0]!r}: the level after 'poe-' is not a number")
        self.levels = np.array([float(header[j][4:]) for j in self.poe_cols])
        if not (
            np.all(np.isfinite(self.levels)) and np.all(self.levels > 0) and np.all(np.diff(self.levels) > 0)
        ):
            raise ConfigError(f"{p}:2: the levels of the header must be positive and increase")
        self.j_lon, self.j_lat = header.index("lon"), header.index("lat")
        self.j_id = header.index("custom_site_id") if "custom_site_id" in header else None
        self.rows: list[tuple[int, list[str]]] = []
        for ln, row in enumerate(csv.reader(lines[2:]), start=3):
            if not row or not "".join(row).strip():
                continue
            if len(row) != len(header):
                raise ConfigError(f"{p}:{ln}: {len(row)} fields, the header has {len(header)}")
            self.rows.append((ln, row))
        if not self.rows:
            raise ConfigError(f"{p}: no site: the file has a header but no row")

    def coords(self, k: int) -> tuple[float, float]:
        ln, row = self.rows[k]
        a, b = row[self.j_lon], row[self.j_lat]
        if not (_is_number(a) and _is_number(b)):
            raise ConfigError(f"{self.p}:{ln}: lon, lat {a!r}, {b!r}: not numbers")
        return float(a), float(b)

    def words(self, k: int) -> str:
        """``site 3 (lon 10.05, lat 45.2)``, with the ``custom_site_id`` where there is one."""
        lon, lat = self.coords(k)
        sid = self.rows[k][1][self.j_id].strip() if self.j_id is not None else ""
        return f"site {k}{f' {sid!r}' if sid else ''} (lon {lon:g}, lat {lat:g})"

    def pick(self, site: object, max_distance_km: float) -> tuple[int, str]:
        """The row ``site`` names and the site in words (with the distance to a [lon, lat] asked)."""
        key, n = f"{_WHERE}.site", len(self.rows)
        if site is None:
            if n != 1:
                raise ConfigError(
                    f"{key}: {self.p} holds {n} sites: give site: N (0 to {n - 1}, as OpenQuake numbers "
                    "them) or site: [lon, lat]"
                )
            return 0, self.words(0)
        if isinstance(site, int) and not isinstance(site, bool):
            if not 0 <= site < n:
                raise ConfigError(
                    f"{key}: {site}: {self.p} holds {n} site{'s' if n > 1 else ''} (0 to {n - 1})"
                )
            return site, self.words(site)
        lon0, lat0 = _lonlat(site, key)
        dist = np.array([great_circle_km(lon0, lat0, *self.coords(i)) for i in range(n)])
        k = int(np.argmin(dist))
        ties = np.flatnonzero(dist <= dist[k] + 1e-6)
        here = f"[{lon0:g}, {lat0:g}]"
        if ties.size > 1:
            named = ", ".join(self.words(int(i)) for i in ties)
            raise ConfigError(
                f"{key}: {here}: {ties.size} sites of {self.p} lie at the same distance ({named}): "
                "give site: N"
            )
        if dist[k] > max_distance_km:
            raise ConfigError(
                f"{key}: {here}: the nearest site of {self.p}, {self.words(k)}, is {dist[k]:.3g} km away, "
                f"beyond max_distance_km {max_distance_km:g} km"
            )
        return k, f"{self.words(k)}, {dist[k]:.3g} km from {here}"

    def poe(self, k: int, where: str, unit: str) -> np.ndarray:
        """The probabilities of exceedance of row ``k``, checked to lie in ``[0, 1)``."""
        ln, row = self.rows[k]
        bad = [row[j] for j in self.poe_cols if not _is_number(row[j])]
        if bad:
            raise ConfigError(f"{self.p}:{ln}: {bad[0]!r} is not a probability of exceedance")
        poe = np.array([float(row[j]) for j in self.poe_cols])
        out = np.flatnonzero(~(np.isfinite(poe) & (poe >= 0.0) & (poe <= 1.0)))
        if out.size:
            i = int(out[0])
            raise ConfigError(f"{where}: poe {poe[i]!r} at {self.levels[i]:.4g} {unit} is not a probability")
        return poe


def read_openquake(
    path: str | Path,
    site: int | Sequence[float] | None = None,
    imt: str | None = None,
    component_definition: str = "RotD50",
    max_distance_km: float = DEFAULT_MAX_DISTANCE_KM,
) -> HazardCurve:
    """One site's curve from an OpenQuake hazard-curve CSV (see the module docstring).

    Parameters
    ----------
    path : str or Path
        The CSV file (``hazard_curve-mean-PGA_*.csv``, ``quantile_curve-0.84-SA(1.0)_*.csv``).
    site : int or [lon, lat] or None
        The row, counted from 0; or the point [deg] whose nearest row is taken; None for a file of one
        site.
    imt : str or None
        The measure expected (any spelling :func:`~isorock.processing.imt.parse_imt` reads): refused if
        the file's differs; it states the measure where the metadata line does not.
    component_definition : str
        ``RotD50`` (default), ``RotD100`` or ``analysed``.
    max_distance_km : float
        The farthest the nearest row may lie from ``site = [lon, lat]`` [km].

    Returns
    -------
    HazardCurve
        Levels in the measure's unit (g; PGV cm/s), annual rates [1/yr], ``origin="openquake"``.

    Raises
    ------
    ConfigError
        A file that is not such a CSV, a site out of range or too far, a measure that differs, a poe of
        1, or fewer than 3 levels left.
    """
    p = Path(path)
    lines = _read_text(p).splitlines()
    if not lines or not lines[0].strip():
        raise ConfigError(f"{p}:1: empty: expected OpenQuake's '#' metadata line")
    meta = openquake_metadata(lines[0], p)
    t_yr, file_imt = _oq_time_imt(meta, p, imt)
    unit = _unit(file_imt)
    sites = _Sites(p, lines)
    k, site_words = sites.pick(site, max_distance_km)
    where = f"{p}: {site_words}"
    poe = sites.poe(k, where, unit)
    if np.any(poe >= 1.0):
        i = int(np.flatnonzero(poe >= 1.0)[0])
        raise ConfigError(
            f"{where}: poe 1 at {sites.levels[i]:.4g} {unit}: an infinite annual rate (-ln(1 - poe) / "
            f"{t_yr:g} yr); a curve certain of exceedance is not a site's hazard"
        )
    x, q, notes = trim_ends(sites.levels, poe, unit, "poe")
    _enough(x, where, notes)
    _check_decreasing(x, q, where, unit)
    return HazardCurve(
        x,
        poe_to_rate(q, t_yr),
        str(p),
        imt=file_imt,
        component_definition=_component(component_definition),
        kind=meta.get("kind", "") or _kind_from_name(p.name),
        site=site_words,
        notes=notes,
        origin="openquake",
    )


# ------------------------------------------------------------------------------------------------ USGS


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


# ------------------------------------------------------------------------------------- file and points


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
    if src == "openquake":
        return read_openquake(_resolve(d[src], basedir), site, imt, comp, dmax)
    if src == "usgs":
        return read_usgs(_resolve(d[src], basedir), imt, comp, site, dmax)
    if src == "file":
        return read_level_rate_csv(_resolve(d[src], basedir), imt if imt is not None else "PGA", comp)
    return from_points(d["points"], imt if imt is not None else "PGA", comp)
