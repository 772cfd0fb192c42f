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
import shutil
from collections.abc import Callable
from dataclasses import asdict, dataclass, field, fields
from dataclasses import replace as _replace
from pathlib import Path, PureWindowsPath
from typing import Any, Literal

from isorock import resources
from isorock.errors import CatalogError, IsorockError, RecordError
from isorock.io import FORMATS, normalize_units, read_trace, trace_component, trace_station
from isorock.records.catalog import load_catalog, read_csv
from isorock.records.directory import (
    MAX_DURATION_S,
    MAX_SAMPLES,
    FileCheck,
    check_file,
    check_size,
    check_trace,
)
from isorock.records.metadata import METADATA_COLUMNS, RecordMetadata
from isorock.store import atomic_path, file_sha256, locked

__all__ = [
    "MANIFEST_COLUMNS",
    "METADATA_COLUMNS",
    "RECORD_ID",
    "ManifestEntry",
    "RowStatus",
    "read_manifest",
    "outside_problem",
    "write_manifest",
    "add_records",
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


def add_records(
    files: list[str | Path],
    directory: str | Path,
    *,
    ids: list[str] | None = None,
    table1_id: str = "",
    format: str | None = None,
    dt: float | None = None,
    units: str | None = None,
    component: str | None = None,
    event: str = "",
    station: str = "",
    note: str = "",
    azimuths: list[float | None] | None = None,
    metadata: list[dict[str, Any]] | None = None,
    replace: bool = False,
    notes: list[str] | None = None,
    waiting: Callable[[], None] | None = None,
    max_samples: int = MAX_SAMPLES,
    max_duration_s: float = MAX_DURATION_S,
) -> list[ManifestEntry]:
    """Copy record files into a records directory and register them in its ``manifest.csv``.

    The manifest names each file by its name in the directory (a relative path); the directory holds
    the file's content: a file given through a symbolic link is copied (its target's content), and
    a file already in the directory under its name is registered where it is (a symbolic link there
    that leads out of the directory is replaced by the content it points to).

    Every file is read first (the same reader and checks as every analysis, so that a file that
    cannot be analysed is refused before anything is copied); the manifest row keeps what the reader
    found: format, units, time step when the file does not state it, component and sha256. A file
    whose header names no component takes the one its name states
    (:func:`isorock.records.components.component_from_name`: ``-E``, ``_fn``, ``090``, ``hor1`` ...),
    and its note says so.

    A record is one record: a file whose content (sha256) is already registered in the directory, or
    given twice, is not added again (said in ``notes``, no error). A different file under an id or a
    file name already registered is refused (``replace`` replaces it); a file of the same name and the
    same content already in the directory but not registered (what an addition killed before writing
    the manifest leaves) is registered where it is.

    An addition is one transaction: it holds the directory's lock (:data:`MANIFEST_LOCK`, an exclusive
    ``flock`` released by the kernel when the process ends, ``kill -9`` included) from reading the
    manifest to renaming the new one into place, so that additions to one directory run one after the
    other and none loses another's rows; every file is copied under a temporary name and renamed, and
    the manifest is written last, atomically. A killed addition leaves the manifest as it was (the
    files it had copied are registered by the same command run again, and its temporary files are
    removed).

    Parameters
    ----------
    files : list of path-like
        Record files.
    directory : path-like
        The records directory (created with its manifest when absent).
    ids : list of str, optional
        Record ids, one per file; default: the file names without their extension. Ignored for a
        file registered as a catalog row (``table1_id``).
    table1_id : str
        The catalog row the file provides (a record of a Table 1 station), instead of an id of its own.
    format, dt, units, component
        How to read the files (see :func:`isorock.io.read_record`).
    event, station, note : str
        Descriptions written in the manifest (default: what the file's header says).
    azimuths : list of float or None, optional
        Azimuth of each file's component [deg clockwise from north], for names that do not state
        it (two components of a Table 1 station are rotated to its SN/SP direction).
    metadata : list of dict, optional
        Per file, values of its manifest row that replace what the file says: any of
        :data:`METADATA_COLUMNS`, ``event``, ``station``, ``note``, and ``id`` ("" registers the file
        without a record of its own, e.g. the second horizontal of a record:
        :func:`isorock.records.peer_search.add_peer_search`).
    replace : bool
        Replace a registered file or id of the same name.
    notes : list of str, optional
        Receives one line per file not added because its content is already registered, and one when
        the temporary files of a stopped addition were removed.
    waiting : callable, optional
        Called once when another addition holds the directory's lock, before waiting for it.
    max_samples, max_duration_s : int, float
        The longest record accepted, in samples and seconds (a file too large for ``max_samples`` is
        refused unread: :func:`isorock.records.directory.check_size`).

    Returns
    -------
    list of ManifestEntry
        The rows added.

    Raises
    ------
    IsorockError
        A file cannot be read or fails its checks, an id is invalid or taken, or a different file of
        the same name is already in the directory.
    """
    directory = Path(directory)
    mpath = directory / "manifest.csv"
    existing = read_manifest(mpath) if mpath.is_file() else []
    ids = list(ids) if ids is not None else [_default_id(Path(f)) for f in files]
    if len(ids) != len(files):
        raise IsorockError(f"{len(files)} files but {len(ids)} ids: give one id per file")
    azimuths = list(azimuths) if azimuths is not None else [None] * len(files)
    if len(azimuths) != len(files):
        raise IsorockError(f"{len(files)} files but {len(azimuths)} azimuths: give one azimuth per file")
    for az in azimuths:
        if az is not None and not (math.isfinite(az) and 0.0 <= az <= 360.0):
            raise IsorockError(f"azimuth {az!r}: an angle in 0-360 deg clockwise from north")
    if table1_id:
        catalog_ids = set(load_catalog()["id"])
        if table1_id not in catalog_ids:
            raise IsorockError(f"--table1-id {table1_id!r} is not a row of the Table 1 catalog")
    new = [
        _replace(
            _entry(
                Path(f),
                rid,
                table1_id,
                format,
                dt,
                units,
                component,
                event,
                station,
                note,
                (max_samples, max_duration_s),
            ),
            azimuth_deg=az,
        )
        for f, rid, az in zip(files, ids, azimuths, strict=True)
    ]
    if metadata is not None:
        if len(metadata) != len(files):
            raise IsorockError(f"{len(files)} files but {len(metadata)} metadata: give one per file")
        allowed = {*METADATA_COLUMNS, "event", "station", "note", "id"}
        for m in metadata:
            bad = sorted(set(m) - allowed)
            if bad:
                raise IsorockError(f"metadata {bad}: not a manifest column of metadata")
        new = [
            _replace(
                e,
                metadata=_replace(e.metadata, **{k: v for k, v in m.items() if k in METADATA_COLUMNS}),
                **{k: v for k, v in m.items() if k not in METADATA_COLUMNS},
            )
            for e, m in zip(new, metadata, strict=True)
        ]
    new = [_as_vertical(e) for e in new]
    _check_ids(new)
    directory.mkdir(parents=True, exist_ok=True)
    with locked(directory / MANIFEST_LOCK, waiting):
        # from here on no other addition writes in the directory: what it holds is read afresh
        _clear_leftovers(directory, notes)
        existing = read_manifest(mpath) if mpath.is_file() else []
        new = _drop_known(new, files, existing, directory, notes)
        if not new:
            return []
        source = {Path(f).name: Path(f) for f in files}
        kept = _check_new(new, existing, directory, replace, source)
        for e in new:
            _copy_in(source[e.file], directory / e.file, directory, e.sha256)
        write_manifest(mpath, kept + new)
    return new


#: the lock file of a records directory: held by :func:`add_records` from reading the manifest to
#: renaming the new one into place, so that two additions to one directory run one after the other
MANIFEST_LOCK = ".manifest.csv.lock"

#: the temporary files :func:`isorock.store.atomic_path` writes (``.<name>.<random>.tmp``)
_TEMPORARY = re.compile(r"^\..+\.[A-Za-z0-9_]+\.tmp$")


def _clear_leftovers(directory: Path, notes: list[str] | None) -> None:
    """Remove the temporary files an addition killed in the directory left behind (a copy or a
    manifest written under a temporary name, never renamed); called holding :data:`MANIFEST_LOCK`, when
    no addition is writing any."""
    left = [p for p in directory.iterdir() if _TEMPORARY.match(p.name) and p.is_file()]
    for p in left:
        p.unlink(missing_ok=True)
    if left and notes is not None:
        notes.append(
            f"{directory}: removed {len(left)} unfinished cop{'y' if len(left) == 1 else 'ies'} left by an "
            "addition that was stopped"
        )


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


def _as_vertical(e: ManifestEntry) -> ManifestEntry:
    """A vertical component is no record to analyse: registered without an id, as the vertical of the
    records of its event and station (``records.vertical``, ``simulate --vertical auto``)."""
    from isorock.records.components import is_vertical  # components imports this module

    if e.table1_id or not is_vertical(e.component):
        return e
    return _replace(e, id="", note="; ".join(x for x in (e.note, VERTICAL_NOTE) if x))


def _copy_in(src: Path, target: Path, directory: Path, sha256: str = "") -> None:
    """Put the content of the record file ``src`` at ``target`` in the records ``directory``.

    Nothing is copied when ``target`` already is that file inside the directory (the file itself, or
    a symbolic link inside the directory to it), or a file (not a link) of that content (``sha256``).
    Otherwise the content (a symbolic link's target's, never the link) is copied to a temporary file and
    renamed to ``target``: a symbolic link at ``target`` is replaced, never written through.
    """
    if target.resolve() == src.resolve() and target.resolve().is_relative_to(directory.resolve()):
        return
    if sha256 and _same_content(target, sha256):
        return
    with atomic_path(target) as tmp:
        shutil.copy2(src, tmp)


def _same_content(target: Path, sha256: str) -> bool:
    """True when ``target`` is a file (not a symbolic link) whose sha256 is ``sha256``."""
    return target.is_file() and not target.is_symlink() and file_sha256(target) == sha256


def _default_id(path: Path) -> str:
    stem = path.name.split(".")[0]
    rid = re.sub(r"[^A-Za-z0-9_.+-]", "_", stem).strip("_.+-")
    return rid or "record"


def _entry(
    path: Path,
    rid: str,
    table1_id: str,
    fmt,
    dt,
    units,
    component,
    event: str,
    station: str,
    note: str,
    limits: tuple[int, float] = (MAX_SAMPLES, MAX_DURATION_S),
) -> ManifestEntry:
    """The manifest row of one file, from what the reader finds in it; ``limits``: the most samples and
    seconds of a record."""
    if not table1_id and not RECORD_ID.match(rid):
        raise IsorockError(
            f"record id {rid!r}: use letters, digits and _ . + - (starting with one of the first two)"
        )
    from isorock.records.components import component_from_name  # components imports this module

    big = check_size(path, limits[0])
    if big:
        raise RecordError(str(path), big.split(": ", 1)[-1])
    tr = read_trace(path, fmt, dt=dt, units=units, component=component)
    fc = check_trace(tr, str(path), max_samples=limits[0], max_duration_s=limits[1])
    if not fc.ok:
        raise RecordError(str(path), fc.problem.split(": ", 1)[-1])
    info = tr.stats.isorock
    multi = info.get("format") == "bbp"
    named = component_from_name(path) if component is None and not trace_component(tr) else None
    if named:
        _select_component(tr, named)
        note = "; ".join(x for x in (note, NAMED_COMPONENT_NOTE) if x)
    return ManifestEntry(
        file=path.name,
        table1_id=table1_id,
        id="" if table1_id else rid,
        event=event or str(info.get("event", "")),
        station=station or trace_station(tr),
        component=trace_component(tr),
        format=str(info.get("format")),
        units=str(info.get("units")),
        dt_s=float(tr.stats.delta) if info.get("dt_source") == "given" else None,
        column=trace_component(tr) if multi else "",
        note=note,
        sha256=file_sha256(path),
    )


#: the note of a manifest row whose component comes from the file name
NAMED_COMPONENT_NOTE = "component from the file name"


def _select_component(tr, name: str) -> None:
    """Give a trace without a component name the one its file name states."""
    from isorock.io._common import seed_code

    tr.stats.isorock.component = name
    tr.stats.channel = seed_code(name, 3)


def _drop_known(
    new: list[ManifestEntry],
    files: list[str | Path],
    existing: list[ManifestEntry],
    directory: Path,
    notes: list[str] | None,
) -> list[ManifestEntry]:
    """The new rows whose file content (sha256) is not registered yet, nor given before in ``new``;
    one line in ``notes`` for each one dropped."""
    known: dict[str, str] = {}
    for e in existing:
        sha = e.sha256
        if not sha and (directory / e.file).is_file():
            sha = file_sha256(directory / e.file)
        if sha:
            what = _what(e)
            known.setdefault(sha, f"{what} ({e.file}, manifest line {e.line})")
    out = []
    for f, e in zip(files, new, strict=True):
        if e.sha256 in known:
            if notes is not None:
                notes.append(f"{f}: already registered as {known[e.sha256]}, same sha256: not added again")
            continue
        what = _what(e)
        known[e.sha256] = f"{what} ({e.file}, given above)"
        out.append(e)
    return out


def _what(e: ManifestEntry) -> str:
    """What a manifest row is, in words: a Table 1 row, a record, or a file beside a record."""
    if e.table1_id:
        return f"Table 1 row {e.table1_id}"
    if e.id:
        return f"record {e.id}"
    rsn = e.metadata.rsn
    return f"a component of record RSN{rsn}" if rsn is not None else "a file without a record id"


def _check_ids(new: list[ManifestEntry]) -> None:
    """Refuses a file or id given twice, and a record id that is a Table 1 id."""
    catalog_ids = set(load_catalog()["id"])
    names = [e.file for e in new]
    rids = [e.id for e in new if e.id]
    for dup in {x for x in names if names.count(x) > 1} | {x for x in rids if rids.count(x) > 1}:
        raise IsorockError(f"{dup!r} is given twice")
    for rid in rids:
        if rid in catalog_ids:
            raise IsorockError(
                f"record id {rid!r} is a Table 1 id: choose another, or register with --table1-id"
            )


def _check_new(
    new: list[ManifestEntry],
    existing: list[ManifestEntry],
    directory: Path,
    replace: bool,
    sources: dict[str, Path] | None = None,
) -> list[ManifestEntry]:
    """The existing rows to keep; refuses clashes of ids and of file names (unless ``replace``).

    ``sources`` maps each new file name to the file given: a file already in the directory under its
    name (that very file, or a link to it) is registered where it is, not refused as a clash.
    """
    _check_ids(new)
    names = [e.file for e in new]
    rids = [e.id for e in new if e.id]
    kept = []
    for e in existing:
        clash = e.file in names or (e.id and e.id in rids)
        if clash and not replace:
            what = f"file {e.file!r}" if e.file in names else f"id {e.id!r}"
            other = f" for {e.file}" if e.file not in names else ""
            raise IsorockError(
                f"{directory / 'manifest.csv'}: {what} is already registered (line {e.line}){other} "
                "with another content (a different sha256): choose another --id or file name, or "
                "--replace replaces it"
            )
        if not clash:
            kept.append(e)
    for e in new:
        target = directory / e.file
        here = sources is not None and target.exists() and target.samefile(sources[e.file])
        here = here or _same_content(target, e.sha256)  # copied by an addition killed before its manifest
        if target.exists() and not here and not replace and e.file not in {k.file for k in existing}:
            raise IsorockError(
                f"{target}: a file of this name is already in the directory; --replace replaces it"
            )
    return kept


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
