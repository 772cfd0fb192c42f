"""Adding records to a records directory (``isorock records add``): each file checked and copied in, its
manifest row written, under the directory's lock and atomically, so that a killed addition is
finished by running it again."""

from __future__ import annotations

import math
import re
import shutil
from collections.abc import Callable
from dataclasses import replace as _replace
from pathlib import Path
from typing import Any

from isorock.errors import IsorockError, RecordError
from isorock.io import read_trace, trace_component, trace_station
from isorock.records.catalog import load_catalog
from isorock.records.directory import MAX_DURATION_S, MAX_SAMPLES, check_size, check_trace
from isorock.records.manifest import RECORD_ID, VERTICAL_NOTE, ManifestEntry, read_manifest, write_manifest
from isorock.records.metadata import METADATA_COLUMNS
from isorock.records.naming import component_from_name, is_vertical
from isorock.store import atomic_path, file_sha256, locked

__all__ = ["add_records", "MANIFEST_LOCK", "NAMED_COMPONENT_NOTE"]


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


def _as_vertical(e: ManifestEntry) -> ManifestEntry:
    """A vertical component is no record to analyse: registered without an id, as the vertical of the
    records of its event and station (``records.vertical``, ``simulate --vertical auto``)."""

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
