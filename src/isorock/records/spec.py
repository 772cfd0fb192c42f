"""What the lookup answers: the files that may provide a record, with how to read them
(:class:`RecordFile`), the direction its catalog row asks for (:class:`Target`), the record
(:class:`RecordSpec`) and the records of a configuration (:class:`RecordSet`)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path
from typing import Any

from isorock.records.manifest import ManifestEntry
from isorock.records.metadata import METADATA_COLUMNS, RecordMetadata
from isorock.records.naming import parse_azimuth, provided_orientation

__all__ = [
    "RecordFile",
    "Target",
    "RecordSpec",
    "RecordSet",
]


@dataclass(frozen=True)
class RecordFile:
    """One file that may provide a record, with how to read it.

    Parameters
    ----------
    path : str
        Absolute path of the file.
    format : str or None
        Manifest format name (None: detect).
    dt_s : float or None
        Time step [s] for files that do not state it.
    units : str or None
        Units of the values in the file.
    component : str or None
        Component of a multi-component file (None: the file's only one, or all its horizontals).
    substitute : bool
        The file stands in for the catalog row (another station).
    note : str
        Manifest note.
    station : str
        Station as the manifest names it (files of one station may be rotated together).
    component_name : str
        Component as the manifest names it (``230``, ``FN``, ``N-S`` ...).
    azimuth_deg : float or None
        Azimuth of that component [deg] when the manifest states it.
    partner : bool
        The file belongs to another catalog row of the same station and event (the other horizontal
        component of the recording): it serves only as the second component of a rotation, never as
        the component analysed on its own.
    """

    path: str
    format: str | None = None
    dt_s: float | None = None
    units: str | None = None
    component: str | None = None
    substitute: bool = False
    note: str = ""
    station: str = ""
    component_name: str = ""
    azimuth_deg: float | None = None
    partner: bool = False

    @classmethod
    def from_entry(cls, directory: Path, e: ManifestEntry) -> RecordFile:
        """The file of a manifest row of ``directory``, with how to read it."""
        kw = e.read_kwargs()
        return cls(
            path=str((directory / e.file).resolve()),
            format=kw["format"],
            dt_s=kw["dt"],
            units=kw["units"],
            component=kw["component"],
            substitute=e.is_substitute,
            note=e.note,
            station=e.station,
            component_name=e.component,
            azimuth_deg=e.azimuth_deg,
        )


@dataclass(frozen=True)
class Target:
    """The direction a catalog row asks for.

    Parameters
    ----------
    label : str
        The row's component: ``SN``, ``SP``, an azimuth (``090``) or a name (``Long``); "" for a
        record without a catalog row.
    azimuth_deg : float or None
        Its azimuth [deg, in [0, 360)] when known (``SN``: strike + 90, ``SP``: strike).
    strike_deg : float or None
        Fault strike [deg] of an ``SN``/``SP`` row.
    strike_source : str
        Where the strike comes from.
    """

    label: str = ""
    azimuth_deg: float | None = None
    strike_deg: float | None = None
    strike_source: str = ""

    @classmethod
    def of(cls, label: str | None, strike_deg: float | None = None, strike_source: str = "") -> Target:
        """The target of a catalog row from its ``component``, ``strike_deg`` and ``strike_source``."""
        lab = str(label or "").strip()
        from isorock.processing.orientation import fault_azimuth

        orient = provided_orientation(lab)
        strike = None if strike_deg is None or not math.isfinite(float(strike_deg)) else float(strike_deg)
        if orient is not None:
            az = fault_azimuth(strike, orient) if strike is not None else None
            return cls(orient, az, strike, strike_source or "")
        return cls(lab, parse_azimuth(lab), None, "")

    def describe(self) -> str:
        """``"SN (azimuth 053.0 deg, fault strike 323 deg)"`` and the like."""
        if not self.label:
            return "no catalog direction"
        if self.label in ("SN", "SP") and self.strike_deg is not None:
            return (
                f"{self.label} (azimuth {self.azimuth_deg:05.1f} deg, fault strike {self.strike_deg:g} deg)"
            )
        if self.azimuth_deg is not None:
            return f"azimuth {self.azimuth_deg:05.1f} deg"
        return f"{self.label} (azimuth not known)"


@dataclass(frozen=True)
class RecordSpec:
    """A record the workflow runs: identity, catalog values and the files that may provide it.

    Parameters
    ----------
    id : str
        Record id (catalog id or sample name): the wildcard, the HDF5 group name.
    label : str
        Human-readable name.
    event, station : str
        Descriptions.
    component : str
        The catalog row's component (``SN``, ``SP``, ``090`` ...), or the file's for a record
        without a row.
    strike_deg : float or None
        Fault strike [deg] defining the row's SN/SP direction.
    strike_source : str
        Its citation.
    tp_source : str
        Source of the catalog's Tp (its definition: Mavroeidis & Papageorgiou fit or Bray &
        Rodriguez-Marek).
    catalog_id : str
        Catalog row ("" for a sample record).
    table1_pga_g, table1_pgv_m_s, table1_tp_s : float or None
        Catalog values [g, m/s, s].
    files : tuple of RecordFile
        Candidate files, in manifest order; then the files of the other catalog rows of the same
        event and station (``partner``: second components for a rotation only).
    source : str
        "records directory" or "pyslammer samples".
    metadata : RecordMetadata
        The recording's metadata: the year of the earthquake (the catalog row's, the sample's or the
        manifest's: :attr:`year`) and, from its manifest row (``records add --peer-search``), PEER's
        values (its ``luf_hz`` raises the processing's high-pass corner:
        :func:`isorock.processing.with_lowest_usable_frequency`).
    """

    id: str
    label: str
    event: str = ""
    station: str = ""
    component: str = ""
    strike_deg: float | None = None
    strike_source: str = ""
    tp_source: str = ""
    catalog_id: str = ""
    table1_pga_g: float | None = None
    table1_pgv_m_s: float | None = None
    table1_tp_s: float | None = None
    files: tuple[RecordFile, ...] = ()
    source: str = "records directory"
    metadata: RecordMetadata = RecordMetadata()

    @property
    def year(self) -> int | None:
        """Year of the earthquake (None when not known)."""
        return self.metadata.year

    def to_dict(self) -> dict:
        """JSON-ready form (Snakemake params): the fields, ``year`` after ``tp_source``, then the
        metadata known (the parameters, and their hash, of a record without metadata are those of
        before the metadata)."""
        d: dict[str, Any] = {}
        for f in fields(self):
            if f.name == "catalog_id":
                d["year"] = self.year
            if f.name != "metadata":
                d[f.name] = getattr(self, f.name)
        d["files"] = [asdict(f) for f in self.files]
        d.update({k: v for k, v in self.metadata.to_dict().items() if k != "year"})
        return d

    @classmethod
    def from_dict(cls, d: Mapping) -> RecordSpec:
        """The record of its :meth:`to_dict` form."""
        rest = {k: v for k, v in d.items() if k not in METADATA_COLUMNS}
        rest["files"] = tuple(RecordFile(**f) for f in d.get("files", ()))
        return cls(**rest, metadata=RecordMetadata.from_mapping(d))

    @property
    def target(self) -> Target:
        """The direction the catalog row asks for (none for a record without a row)."""
        if not self.catalog_id:
            return Target()
        return Target.of(self.component, self.strike_deg, self.strike_source)


@dataclass
class RecordSet:
    """The records a run finds: see :func:`find_records`.

    Attributes
    ----------
    records : list of RecordSpec
        The records, in catalog order, then the added ones.
    source : str
        Where they come from ("records directory DIR", "pyslammer samples", "none").
    warnings : list of str
        One line per skipped catalog row or other problem.
    """

    records: list[RecordSpec]
    source: str
    warnings: list[str] = field(default_factory=list)
