"""The hazard curve of one site of an OpenQuake hazard-curve CSV (:func:`read_openquake`).

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
"""

from __future__ import annotations

import csv
import math
import re
from collections.abc import Mapping, Sequence
from pathlib import Path

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

__all__ = ["read_openquake", "openquake_metadata", "poe_to_rate"]

_META = re.compile(r"""(\w+)\s*=\s*('[^']*'|"[^"]*"|\([^)]*\)|[^,]*)""")
_KIND_FROM_NAME = (
    re.compile(r"^(?:hazard_curve|hcurves?)-(mean|max|rlz-\d+)(?=[-_.(]|$)", re.IGNORECASE),
    re.compile(r"^quantile_curve-([0-9]*\.?[0-9]+)(?=[-_])", re.IGNORECASE),
)


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
