"""Read-only access to a store: tables, regime maps and records, each read once.

:class:`Store` is the one reader of ``results/isorock.h5`` (and of any file with the same layout,
such as a map written by ``isorock map --out``): the figures and the report tables use it. The map
index is ``/summary/maps`` when the merge wrote it, else computed from the map groups with the same
function (:func:`isorock.store.maps.map_index`). :func:`processing_steps` is the one place that reads an
older layout (:data:`isorock.store.layout.LAYOUT_HISTORY`).
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import h5py
import pandas as pd

from isorock.errors import IsorockError
from isorock.physics.result import RegimeMap
from isorock.store.hdf import attr, attrs_dict, read_table
from isorock.store.maps import map_index, read_map

__all__ = ["Store", "MapInfo", "StoreNotFound", "processing_steps"]


class StoreNotFound(IsorockError):
    """The store file does not exist."""


@dataclass(frozen=True)
class MapInfo:
    """A regime map of the store, described by its row of the map index.

    Attributes
    ----------
    path : str
        HDF5 path of the map group.
    kind : {"lambda-R", "Tb-xi"}
        Map axes.
    source, source_kind : str
        Record id or ``pulse-<shape>-td<td>``; ``"record"`` or ``"pulse"``.
    case, isolation : str
        Isolation case name and kind (``none``, ``linear``, ``fp``).
    Tb_s, xi_b, rho, mu_b, R_b_m : float
        Isolation parameters [s, -, -, -, m] (NaN where they do not apply).
    lam, R_m : float
        The block of a Tb-xi map: slenderness [-] and size [m] (NaN for lambda-R maps).
    pulse : str
        Pulse shape of a pulse map ("" for records).
    td_s : float
        Pulse half-cycle duration [s].
    amp_g : float
        Excitation PGA [g].
    """

    path: str
    kind: str
    source: str
    source_kind: str
    case: str
    isolation: str
    Tb_s: float
    xi_b: float
    rho: float
    mu_b: float
    R_b_m: float
    lam: float
    R_m: float
    pulse: str
    td_s: float
    amp_g: float

    @classmethod
    def from_row(cls, row: dict[str, Any]) -> MapInfo:
        def num(k: str) -> float:
            v = row.get(k, math.nan)
            try:
                return float(v)
            except (TypeError, ValueError):
                return math.nan

        def text(k: str) -> str:
            v = row.get(k, "")
            return "" if v is None or (isinstance(v, float) and math.isnan(v)) else str(v)

        return cls(
            path=text("path"),
            kind=text("kind"),
            source=text("source"),
            source_kind=text("source_kind"),
            case=text("case"),
            isolation=text("isolation"),
            Tb_s=num("Tb_s"),
            xi_b=num("xi_b"),
            rho=num("rho"),
            mu_b=num("mu_b"),
            R_b_m=num("R_b_m"),
            lam=num("lambda_"),
            R_m=num("R_m"),
            pulse=text("pulse"),
            td_s=num("td_s"),
            amp_g=num("amp_g"),
        )


def processing_steps(group: h5py.Group) -> list:
    """The processing steps of a ``/records/<id>`` group, from any layout version: the compatibility
    function of the store.

    Layout 3 and later: the JSON attribute ``processing_json``. Layout 2 (no such attribute): the steps
    parsed from the lines of the dataset ``processing`` (:func:`isorock.processing.parse_history`:
    parameters as printed, 6 significant digits; the line of a rotation of two components is not a
    step and is left out, as in layout 3). No other reader of the store looks at the lines.

    Parameters
    ----------
    group : h5py.Group
        A ``/records/<id>`` group.

    Returns
    -------
    list of isorock.processing.AppliedStep
        In the order applied; empty when the record has neither.
    """
    from isorock.processing.history import steps_from_json  # obspy: only when asked
    from isorock.processing.legacy import parse_history

    if "processing_json" in group.attrs:
        return steps_from_json(attr(group, "processing_json"))
    if "processing" in group:
        return parse_history(x.decode() if isinstance(x, bytes) else str(x) for x in group["processing"][()])
    return []


def _path_of(h5: Any) -> Path:
    """Path of the store, given a path or an open h5py object."""
    if hasattr(h5, "file") and hasattr(h5.file, "filename"):
        return Path(h5.file.filename)
    return Path(os.fspath(h5))


class Store:
    """Read-only access to a store file.

    Parameters
    ----------
    h5 : path-like or h5py object
        The store.

    Raises
    ------
    StoreNotFound
        The file does not exist.
    """

    def __init__(self, h5: Any):
        self.path = _path_of(h5)
        if not self.path.is_file():
            raise StoreNotFound(f"no store at {self.path}")
        self._keys: set[str] = set()
        with h5py.File(self.path, "r") as f:
            f.visit(self._keys.add)
            self.root_attrs = attrs_dict(f)
        self._maps: list[MapInfo] | None = None
        self._tables: dict[str, pd.DataFrame | None] = {}

    def has(self, key: str) -> bool:
        """Whether the store holds the group or dataset ``key``."""
        return key.strip("/") in self._keys

    def table(self, key: str) -> pd.DataFrame | None:
        """A pandas table of the store, or None when it is absent."""
        key = key.strip("/")
        if key not in self._tables:
            df = read_table(self.path, key) if self.has(key) else None
            if df is not None and key.startswith("assessment/") and "pga_g" in df and "level" not in df:
                # layout 6 or older: the level of the stripes (PGA of the analysed component) was pga_g
                df = df.rename(columns={"pga_g": "level"})
            self._tables[key] = df
        return self._tables[key]

    def overturn(self) -> pd.DataFrame | None:
        """All record overturn tables stacked (``/summary/overturn``, else the ``/overturn/<id>`` tables)."""
        df = self.table("summary/overturn")
        if df is not None:
            return df
        parts = []
        for k in sorted(self._keys):
            m = re.fullmatch(r"overturn/([^/]+)", k)
            if m:
                t = self.table(k)
                if t is not None:
                    t = t.copy()
                    if "record" not in t.columns:
                        t["record"] = m.group(1)
                    parts.append(t)
        return pd.concat(parts, ignore_index=True) if parts else None

    # ------------------------------------------------------------------ maps
    def map_index(self) -> pd.DataFrame:
        """The map index: ``/summary/maps``, else computed from the map groups."""
        df = self.table("summary/maps")
        if df is not None:
            return df
        with h5py.File(self.path, "r") as f:
            return map_index(f)

    def maps(self) -> list[MapInfo]:
        """Every regime map of the store, described by its index row."""
        if self._maps is None:
            self._maps = [MapInfo.from_row(r) for r in self.map_index().to_dict("records")]
        return self._maps

    def read_map(self, info: MapInfo | str) -> RegimeMap:
        """The map of an index row (or of an HDF5 path)."""
        path = info.path if isinstance(info, MapInfo) else info
        with h5py.File(self.path, "r") as f:
            return read_map(f[path])

    # ------------------------------------------------------------------ records
    def record_ids(self) -> list[str]:
        """Ids of the records with a ``/records/<id>`` group, sorted."""
        return sorted(k.split("/")[1] for k in self._keys if re.fullmatch(r"records/[^/]+", k))

    def record_sources(self) -> list[str]:
        """Ids of records present anywhere in the store (records, overturn tables, maps)."""
        ids = set(self.record_ids())
        ids |= {k.split("/")[1] for k in self._keys if re.fullmatch(r"overturn/[^/]+", k)}
        ids |= {m.source for m in self.maps() if m.source_kind == "record"}
        return sorted(ids)

    def record_attrs(self, rid: str) -> dict[str, Any]:
        """The attributes of ``/records/<rid>`` as plain values (empty when absent)."""
        if not self.has(f"records/{rid}"):
            return {}
        with h5py.File(self.path, "r") as f:
            return attrs_dict(f[f"records/{rid}"])

    def record_processing(self, rid: str) -> list:
        """The processing steps of ``/records/<rid>`` (:func:`processing_steps`; empty when absent).

        Returns
        -------
        list of isorock.processing.AppliedStep
            ``step`` (name), ``parameters`` (dict, units of the step), ``note`` (text), in the order applied.
        """
        if not self.has(f"records/{rid}"):
            return []
        with h5py.File(self.path, "r") as f:
            return processing_steps(f[f"records/{rid}"])

    @property
    def layout_version(self) -> int:
        """The store's ``layout_version`` (2 for a file that does not say)."""
        return int(self.root_attrs.get("layout_version", 2))

    def record_series(self, rid: str) -> dict[str, Any]:
        """The arrays of ``/records/<rid>`` and its pulse.

        Returns
        -------
        dict
            ``acc`` (processed ground acceleration [m/s^2]), ``dt_s`` [s], ``velocity``,
            ``pulse_velocity``, ``mp_velocity`` (ground velocity, wavelet pulse and MP fit [m/s]; None
            when the record has no pulse group), ``attrs`` and ``pulse_attrs`` (plain values).
        """
        out: dict[str, Any] = {"acc": None, "dt_s": math.nan, "attrs": {}, "pulse_attrs": {}}
        for k in ("velocity", "pulse_velocity", "mp_velocity"):
            out[k] = None
        with h5py.File(self.path, "r") as f:
            g = f[f"records/{rid}"]
            out["attrs"] = attrs_dict(g)
            if "acc" in g:
                out["acc"] = g["acc"][()].astype(float)
                out["dt_s"] = float(g["acc"].attrs.get("dt_s", out["attrs"].get("dt_s", math.nan)))
            if "pulse" in g:
                out["pulse_attrs"] = attrs_dict(g["pulse"])
                for k in ("velocity", "pulse_velocity", "mp_velocity"):
                    if k in g["pulse"]:
                        out[k] = g["pulse"][k][()]
        return out
