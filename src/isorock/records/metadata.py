"""A recording's metadata: the one definition of what PEER's search table tells of a record.

:class:`RecordMetadata` is what a manifest row (:class:`isorock.records.manifest.ManifestEntry`), a
record of a run (:class:`isorock.records.lookup.RecordSpec`) and a row of a PEER search
(:class:`isorock.records.peer_search.PeerRow`) carry; it reads and writes the manifest's metadata
columns (:data:`METADATA_COLUMNS`), gives the JSON of ``records status`` and ``records add
--peer-search`` and the attributes the workflow stores with a processed record.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import Any

from isorock.errors import CatalogError

__all__ = ["METADATA_COLUMNS", "RecordMetadata"]


@dataclass(frozen=True)
class RecordMetadata:
    """The metadata of a recording (``records add --peer-search``, from PEER's ``_SearchResults.csv``).

    Every field is optional: None (or "" for ``mechanism``) when not known. The earthquake and the
    station are not here: they are the ``event`` and ``station`` of the manifest row or the record.

    Parameters
    ----------
    rsn : int or None
        PEER's record sequence number (an integer >= 1).
    mw : float or None
        Moment magnitude.
    mechanism : str
        Fault mechanism ("" when not known).
    rjb_km, rrup_km : float or None
        Joyner-Boore and rupture distances [km] (>= 0).
    vs30_m_s : float or None
        Vs30 of the station [m/s] (> 0).
    luf_hz : float or None
        Lowest usable frequency [Hz] (> 0): the processing's high-pass corner is raised to it
        (:func:`isorock.processing.with_lowest_usable_frequency`).
    year : int or None
        Year of the earthquake.
    """

    rsn: int | None = None
    mw: float | None = None
    mechanism: str = ""
    rjb_km: float | None = None
    rrup_km: float | None = None
    vs30_m_s: float | None = None
    luf_hz: float | None = None
    year: int | None = None

    def to_dict(self) -> dict[str, Any]:
        """The values known (unknowns left out), in :data:`METADATA_COLUMNS` order."""
        return {k: v for k, v in asdict(self).items() if v is not None and v != ""}

    def with_names(self, earthquake: str, station: str) -> dict[str, Any]:
        """Every value (None or "" when not known) with the earthquake and the station: ``rsn``, ``mw``,
        ``mechanism``, ``rjb_km``, ``rrup_km``, ``vs30_m_s``, ``luf_hz``, ``earthquake``, ``year``,
        ``station`` (the ``metadata`` of ``records status --json`` and ``records add --peer-search
        --json``)."""
        out = asdict(self)
        year = out.pop("year")
        return {**out, "earthquake": earthquake, "year": year, "station": station}

    def store_attrs(self) -> dict[str, Any]:
        """The attributes stored with a processed record (all but ``year``, which every record has):
        ``rsn`` -1, a number NaN and ``mechanism`` "" when not known."""
        out: dict[str, Any] = {}
        for k, v in asdict(self).items():
            if k == "year":
                continue
            if k == "rsn":
                out[k] = -1 if v is None else v
            elif k == "mechanism":
                out[k] = v
            else:
                out[k] = math.nan if v is None else float(v)
        return out

    @classmethod
    def from_mapping(cls, values: Mapping[str, Any]) -> RecordMetadata:
        """The metadata of the keys of ``values`` that are fields (the others ignored; a missing key is
        not known)."""
        return cls(**{k: values[k] for k in METADATA_COLUMNS if k in values})

    @classmethod
    def from_cells(cls, cell: Mapping[str, str], path: str | Path, line: int) -> RecordMetadata:
        """The metadata of a manifest row from its cells (stripped text; an empty or missing cell is
        not known).

        Raises
        ------
        CatalogError
            A cell that is not what its column holds (``luf_hz='-1' is not a frequency > 0 Hz``), with
            the manifest and the line.
        """
        out: dict[str, Any] = {"mechanism": cell.get("mechanism", "")}
        for name, what, ok in _NUMBERS:
            text = cell.get(name, "")
            if not text:
                continue
            try:
                x = float(text)
            except ValueError:
                x = math.nan
            if not (math.isfinite(x) and ok(x)):
                raise CatalogError(Path(path), f"{name}={text!r} is not {what}", line)
            out[name] = int(x) if name in _INTEGERS else x
        return cls(**out)

    def cells(self) -> dict[str, str]:
        """The manifest cells of the metadata ("" when not known), by column."""
        out: dict[str, str] = {}
        for f in fields(self):
            v = getattr(self, f.name)
            out[f.name] = "" if v is None else str(v) if f.name in (*_INTEGERS, "mechanism") else f"{v:.10g}"
        return out


#: the optional metadata columns of a manifest (:class:`RecordMetadata`'s fields, in their order)
METADATA_COLUMNS: tuple[str, ...] = tuple(f.name for f in fields(RecordMetadata))

#: the numeric metadata columns: (name, what it must be, its test)
_NUMBERS: tuple[tuple[str, str, Callable[[float], bool]], ...] = (
    ("rsn", "a record sequence number (an integer >= 1)", lambda x: x >= 1 and x == int(x)),
    ("mw", "a magnitude (a number)", lambda x: True),
    ("rjb_km", "a distance >= 0 km", lambda x: x >= 0),
    ("rrup_km", "a distance >= 0 km", lambda x: x >= 0),
    ("vs30_m_s", "a velocity > 0 m/s", lambda x: x > 0),
    ("luf_hz", "a frequency > 0 Hz", lambda x: x > 0),
    ("year", "a year (an integer)", lambda x: x == int(x)),
)
_INTEGERS = ("rsn", "year")
