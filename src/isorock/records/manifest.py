"""The manifest of a records directory: what each file is, and how to add records to it.

A records directory holds record files and a ``manifest.csv`` with one row per file: the file name,
the catalog row it belongs to (``table1_id``) or, for the user's own records, its record ``id``, its
format, units, time step and component, and the file's sha256. :func:`read_manifest` reads and
checks it; :func:`add_records` (``isorock records add``) copies files into a directory and registers
them, so that the workflow runs them beside the records already there.

A records directory is a boundary: the ``file`` of a manifest row is a path relative to the directory
that stays inside it. :func:`read_manifest` refuses an absolute path, a path whose ``..`` leaves the
directory and a path that leads out of it through a symbolic link (a link inside the directory to a
file inside it is fine); :func:`add_records` copies the content of every file it registers into the
directory (the content of a symbolic link's target, never the link).
"""

from __future__ import annotations

import csv
import math
import os
import posixpath
import re
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path, PureWindowsPath
from typing import Any, Literal

import isorock.resources as resources
from isorock.errors import CatalogError, RecordError
from isorock.io import FORMATS, normalize_units
from isorock.records.catalog import load_catalog, read_csv
from isorock.records.directory import (
    FileCheck,
    check_file,
)
from isorock.records.metadata import METADATA_COLUMNS, RecordMetadata
from isorock.store import atomic_path

__all__ = [
    "MANIFEST_COLUMNS",
    "METADATA_COLUMNS",
    "RECORD_ID",
    "ManifestEntry",
    "RowStatus",
    "read_manifest",
    "outside_problem",
    "write_manifest",
    "check_manifest_files",
    "catalog_status",
]

#: the columns of a manifest; the last ones are the optional metadata columns (:data:`METADATA_COLUMNS`,
#: from PEER's ``_SearchResults.csv``: :class:`isorock.records.metadata.RecordMetadata`): a manifest
#: without them (one written before) reads as before, its records without metadata
MANIFEST_COLUMNS: tuple[str, ...] = (
    "file", "table1_id", "id", "event", "station", "component", "azimuth_deg", "format", "units", "dt_s",
    "column", "note", "sha256", *METADATA_COLUMNS,
)  # fmt: skip

#: a record id (the workflow's wildcard, the HDF5 group name): letters, digits, ``_ . + -``
RECORD_ID = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.+-]*$")
_MANIFEST_REQUIRED = ("file", "table1_id", "format", "units", "dt_s", "column")


@dataclass(frozen=True)
class ManifestEntry:
    """One row of a records-directory manifest.

    Parameters
    ----------
    file : str
        File name relative to the directory (a path inside it: :func:`read_manifest` refuses others).
    table1_id : str
        Catalog id the file belongs to ("" if none).
    id : str
        Id of a record that is not a catalog row (added with ``isorock records add``; "" if none).
    format : str
        Manifest format name (see :data:`isorock.io.FORMATS`).
    units : str
        Units of the values in the file.
    dt_s : float or None
        Time step [s] when the file does not state it.
    column : str
        Component to read from a multi-component file ("" if one).
    event, station, component, note : str
        Descriptions.
    azimuth_deg : float or None
        Azimuth of the component [deg clockwise from north] when its name does not state it
        (optional column; see :func:`isorock.records.components.parse_azimuth`).
    sha256 : str
        sha256 of the file when it was registered ("" if not recorded).
    metadata : RecordMetadata
        The recording's metadata (the columns :data:`METADATA_COLUMNS`; none known by default).
    line : int
        Line of the manifest.
    """

    file: str
    table1_id: str = ""
    id: str = ""
    format: str = ""
    units: str = ""
    dt_s: float | None = None
    column: str = ""
    event: str = ""
    station: str = ""
    component: str = ""
    note: str = ""
    sha256: str = ""
    azimuth_deg: float | None = None
    metadata: RecordMetadata = RecordMetadata()
    line: int = 0

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form: the fields, the metadata's in its place (one key per manifest column, and
        ``line``)."""
        out: dict[str, Any] = {}
        for f in fields(self):
            if f.name == "metadata":
                out.update(asdict(self.metadata))
            else:
                out[f.name] = getattr(self, f.name)
        return out

    @property
    def is_substitute(self) -> bool:
        """The note says the file stands in for the catalog row (another station)."""
        return self.note.strip().lower().startswith("substitute")

    def read_kwargs(self) -> dict[str, Any]:
        """Keyword arguments for :func:`isorock.io.read_record`."""
        return {
            "format": self.format or None,
            "dt": self.dt_s,
            "units": self.units or None,
            "component": self.column or (self.component if self.format != "bbp" else None) or None,
        }


def read_manifest(path: str | Path, directory: str | Path | None = None) -> list[ManifestEntry]:
    """Read a manifest CSV (columns :data:`MANIFEST_COLUMNS`).

    Parameters
    ----------
    path : str or Path
        The manifest.
    directory : str or Path, optional
        The records directory its ``file`` paths are relative to (default: the manifest's directory).

    Raises
    ------
    CatalogError
        Missing columns, an unknown format or units, a bad ``dt_s``, a repeated file, a file path that
        is absolute or leaves the records directory (through ``..`` or a symbolic link), with the line.
    """
    path = Path(path)
    directory = Path(directory) if directory is not None else path.parent
    header, raw = read_csv(path, "manifest")
    missing = [c for c in _MANIFEST_REQUIRED if c not in header]
    if missing:
        raise CatalogError(
            path, f"missing columns {missing}: a manifest has {', '.join(MANIFEST_COLUMNS)}", 1
        )
    out: list[ManifestEntry] = []
    seen: dict[str, int] = {}
    ids: dict[str, int] = {}
    for k, row in enumerate(raw):
        line = k + 2
        cell = {c: (row.get(c) or "").strip() for c in MANIFEST_COLUMNS}
        if not cell["file"]:
            raise CatalogError(path, "empty file name", line)
        outside = outside_problem(cell["file"], directory)
        if outside:
            raise CatalogError(path, outside, line)
        # "good.AT2" and "./good.AT2" are one file: compared as normalised paths
        key = posixpath.normpath(cell["file"])
        if key in seen:
            raise CatalogError(path, f"file {cell['file']!r} listed twice (first on line {seen[key]})", line)
        seen[key] = line
        if cell["id"] and not RECORD_ID.match(cell["id"]):
            raise CatalogError(path, f"id {cell['id']!r}: use letters, digits and _ . + - only", line)
        if cell["id"] and cell["id"] in ids:
            raise CatalogError(path, f"id {cell['id']!r} given twice (first on line {ids[cell['id']]})", line)
        if cell["id"]:
            ids[cell["id"]] = line
        if cell["format"] not in FORMATS:
            raise CatalogError(path, f"unknown format {cell['format']!r}: valid {', '.join(FORMATS)}", line)
        if cell["units"]:
            try:
                normalize_units(cell["units"], path, line)
            except RecordError as exc:
                raise CatalogError(path, exc.problem, line) from None
        dt = None
        if cell["dt_s"]:
            try:
                dt = float(cell["dt_s"])
            except ValueError:
                dt = float("nan")
            if not (math.isfinite(dt) and dt > 0):
                raise CatalogError(path, f"dt_s={cell['dt_s']!r} is not a time step > 0 s", line)
        az = None
        if cell["azimuth_deg"]:
            try:
                az = float(cell["azimuth_deg"])
            except ValueError:
                az = float("nan")
            if not (math.isfinite(az) and 0.0 <= az <= 360.0):
                raise CatalogError(
                    path, f"azimuth_deg={cell['azimuth_deg']!r} is not an angle in 0-360 deg", line
                )
        meta = RecordMetadata.from_cells(cell, path, line)
        text: dict[str, Any] = {
            c: cell[c] for c in MANIFEST_COLUMNS if c not in ("dt_s", "azimuth_deg", *METADATA_COLUMNS)
        }
        out.append(ManifestEntry(dt_s=dt, azimuth_deg=az, line=line, metadata=meta, **text))
    return out


def outside_problem(name: str, directory: str | Path) -> str | None:
    """Why the manifest path ``name`` is not a file inside the records directory, or None when it is.

    A manifest path is relative to ``directory`` and stays inside it: an absolute path, a path whose
    ``..`` leaves the directory and a path that resolves (through symbolic links) outside it are
    refused. A symbolic link inside the directory to a file inside it is accepted; a path that does
    not exist is accepted here (the file checks report it missing).

    Parameters
    ----------
    name : str
        The ``file`` cell of a manifest row.
    directory : str or Path
        The records directory.

    Returns
    -------
    str or None
        The problem, in one line naming the path and the directory.
    """
    root = Path(directory).resolve()
    where = f"the records folder {root}"
    rule = "paths must be relative and inside it"
    if Path(name).is_absolute() or PureWindowsPath(name).is_absolute():
        full = Path(name).resolve()
        if full.is_relative_to(root):
            return f"file {name!r} is an absolute path: {rule} (write {str(full.relative_to(root))!r})"
        return f"file {name!r} is outside {where}: {rule}"
    norm = os.path.normpath(name)
    if norm == os.curdir:
        return f"file {name!r} names {where} itself, not a file in it"
    if Path(norm).parts[0] == os.pardir:
        return f"file {name!r} is outside {where} ('..' leaves it): {rule}"
    full = (root / name).resolve()
    if not full.is_relative_to(root):
        how = "is a symbolic link to" if (root / name).is_symlink() else "leads through a symbolic link to"
        return (
            f"file {name!r} {how} {full}, outside {where}: {rule} "
            "(copy the file into the folder, e.g. with 'isorock records add')"
        )
    return None


def write_manifest(path: str | Path, entries: list[ManifestEntry]) -> None:
    """Write a manifest (columns :data:`MANIFEST_COLUMNS`) atomically."""
    with atomic_path(path) as tmp, open(tmp, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(MANIFEST_COLUMNS)
        for e in entries:
            row = e.to_dict()
            row["dt_s"] = "" if e.dt_s is None else f"{e.dt_s:.10g}"
            row["azimuth_deg"] = "" if e.azimuth_deg is None else f"{e.azimuth_deg:g}"
            row.update(e.metadata.cells())
            w.writerow([row[c] for c in MANIFEST_COLUMNS])


#: the note of a manifest row that is the second horizontal of a record (``records add --peer-search``):
#: registered without an id, beside the record of its ``rsn`` (:func:`isorock.records.lookup.find_records`
#: gives it to the record as a ``partner`` file, the second component of a pair)
PAIRED_NOTE = (
    "second horizontal of the record of its rsn: no record of its own; kept to be paired and rotated "
    "with the first"
)

#: the note of a manifest row that is the vertical of the records of its event and station
VERTICAL_NOTE = (
    "vertical component: no record of its own; the vertical of the records of its event and station "
    "(or of its file name up to its last - or _)"
)


def check_manifest_files(directory: str | Path, manifest: list[ManifestEntry]) -> list[FileCheck]:
    """Check every file a manifest lists (missing files fail with 'no such file')."""
    directory = Path(directory)
    out = []
    for e in manifest:
        fc = check_file(directory / e.file, label=e.file, **e.read_kwargs())
        fc.table1_id = e.table1_id
        fc.id = e.id
        out.append(fc)
    return out


@dataclass
class RowStatus:
    """Whether a catalog row has a record file in a directory.

    Parameters
    ----------
    id : str
        Catalog id.
    status : {"present", "substituted", "missing"}
        ``present``: at least one file of that station; ``substituted``: only files of a stand-in
        station (manifest note starting with "substitute"); ``missing``: no usable file.
    files : list of str
        The files (present or substitute) for the row.
    failed : list of str
        Files listed for the row that are absent or fail :func:`check_file`.
    """

    id: str
    status: Literal["present", "substituted", "missing"]
    files: list[str] = field(default_factory=list)
    failed: list[str] = field(default_factory=list)

    def to_dict(self) -> dict:
        return asdict(self)


def catalog_status(
    directory: str | Path | None,
    manifest: list[ManifestEntry] | None = None,
    catalog=None,
    checks: list[FileCheck] | None = None,
) -> list[RowStatus]:
    """Which catalog rows are present, missing or substituted in a records directory.

    Parameters
    ----------
    directory : str or Path or None
        The records directory (None: only user-added rows with a ``file`` can be present).
    manifest : list of ManifestEntry, optional
        Default: ``directory/manifest.csv`` if it exists, else none.
    catalog : pandas.DataFrame, optional
        Default: :func:`load_catalog` (Table 1).
    checks : list of FileCheck, optional
        Results of :func:`check_manifest_files`; a file that failed does not count as present.
        Without them a file counts when it exists.

    Returns
    -------
    list of RowStatus
        In catalog order.
    """
    if catalog is None:
        catalog = load_catalog()
    directory = Path(directory) if directory is not None else None
    if manifest is None and directory is not None and (directory / "manifest.csv").is_file():
        manifest = read_manifest(directory / "manifest.csv")
    manifest = manifest or []
    failed = {c.file for c in (checks or []) if not c.ok}
    cat_dir = Path(catalog.attrs.get("path", resources.catalog_csv())).parent
    out: list[RowStatus] = []
    for row in catalog.to_dict("records"):
        rid = row["id"]
        good: list[str] = []
        subs: list[str] = []
        bad: list[str] = []
        for e in manifest:
            if e.table1_id != rid:
                continue
            exists = directory is not None and (directory / e.file).is_file()
            if not exists or e.file in failed:
                bad.append(e.file)
            elif e.is_substitute:
                subs.append(e.file)
            else:
                good.append(e.file)
        own = row.get("file")
        if isinstance(own, str) and own:
            p = Path(own) if Path(own).is_absolute() else cat_dir / own
            (good if p.is_file() and own not in failed else bad).append(own)
        if good:
            out.append(RowStatus(rid, "present", good + subs, bad))
        elif subs:
            out.append(RowStatus(rid, "substituted", subs, bad))
        else:
            out.append(RowStatus(rid, "missing", [], bad))
    return out
