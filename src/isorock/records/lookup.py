"""The record lookup: which records a run has, and one record by its id.

* :func:`find_records` gives the records of a configuration's ``records`` section, from up to three
  record sets (``records.include``, :data:`INCLUDE`): the built-in pyslammer samples
  (:func:`isorock.records.directory.sample_records`), the rows of the record catalog (Table 1 by
  default) that have a file in the records directory (``records.dir``, else ``$ISOROCK_RECORDS``, else
  ``./records`` when ``isorock records add`` put records there), described by the directory's
  ``manifest.csv``, and the records added to it with ``isorock records add``; rows without a file are
  skipped with one warning line each. By default the user's added records run with the records the
  user already had: the Table 1 files of the directory, or the samples when it holds none; with no
  records directory the samples run.
* :func:`catalog_record` (also :func:`record_by_id`) gives one record by its id, as the workflow
  would run it (``--id`` of the command line, :func:`isorock.records.table1.load_table1`): a catalog
  row with its files, a record added to the directory (read as its manifest row says), or a sample.

Relative paths are relative to ``basedir``, the working directory of a run (Snakemake's convention).
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import isorock.records.catalog as cat
from isorock.constants import ENV_RECORDS
from isorock.errors import ConfigError, IsorockError
from isorock.records.directory import (
    DEFAULT_RECORDS_DIR,
    SampleRecord,
    default_records_dir,
    records_dir,
    sample_records,
)
from isorock.records.manifest import ManifestEntry, read_manifest
from isorock.records.metadata import RecordMetadata
from isorock.records.rows import added_records, catalog_records
from isorock.records.spec import RecordFile, RecordSet, RecordSpec
from isorock.store import file_sha256

__all__ = [
    "INCLUDE",
    "find_records",
    "catalog_record",
    "record_by_id",
    "resolve_path",
]


def resolve_path(p: str | None, basedir: Path) -> Path | None:
    """A path of the configuration: absolute, or relative to ``basedir``."""
    if p is None or str(p).strip() == "":
        return None
    q = Path(str(p)).expanduser()
    return q if q.is_absolute() else (basedir / q)


#: the values of ``records.include``: the record sets a run may take
INCLUDE: tuple[str, ...] = ("samples", "table1", "added")


def find_records(rc: Mapping, basedir: str | Path | None = None) -> RecordSet:
    """The records of a ``records`` configuration section.

    The record sets (``records.include``, :data:`INCLUDE`):

    * ``samples``: the built-in pyslammer sample records (:func:`isorock.records.directory.sample_records`);
    * ``table1``: the catalog rows (Table 1 by default) with a file in the records directory;
    * ``added``: the records added to the records directory with ``isorock records add``.

    The records directory is ``dir``, else ``$ISOROCK_RECORDS``, else ``./records`` (relative to
    ``basedir``) when it holds a manifest (where ``isorock records add`` puts records by default).
    Without ``include`` a run takes what is there: the Table 1 rows with a file and the added records
    of the directory; the samples when there is no directory, and beside the added records when the
    directory holds no Table 1 file (the user's records run with the records the user already had).
    An added record whose file is a sample's (same sha256) runs once, as the sample.

    Parameters
    ----------
    rc : mapping
        The validated ``records`` section: ``dir``, ``catalog``, ``include``, ``select``,
        ``max_records``, ``use_substitutes``.
    basedir : path-like, optional
        Directory against which its relative paths are resolved (default: the current directory).

    Returns
    -------
    RecordSet
        The samples or the catalog rows, then the added records; then the selection.

    Raises
    ------
    IsorockError
        A records directory is named but does not exist; the catalog or manifest is malformed; a
        record id is reserved.
    ConfigError
        No record is left; an added record's id is a catalog row or a sample's name (another file).
    """
    base = Path(basedir) if basedir is not None else Path.cwd()
    warn: list[str] = []
    named = resolve_path(rc.get("dir"), base)
    directory = records_dir(named)
    implicit = directory is None and default_records_dir(base) is not None
    if directory is None:
        directory = default_records_dir(base)
    if directory is not None:
        directory = directory.resolve()
    include = rc.get("include")
    want = set(include) if include is not None else set(INCLUDE)
    unknown = sorted(want - set(INCLUDE))
    if unknown:
        raise ConfigError(f"records.include: unknown {', '.join(unknown)}: valid {', '.join(INCLUDE)}")
    manifest: list[ManifestEntry] = []
    table1: list[RecordSpec] = []
    added: list[RecordSpec] = []
    if directory is not None:
        manifest, table1, added = _directory_records(directory, rc, base, want, include is not None, warn)
    elif include is not None and want & {"table1", "added"}:
        warn.append(
            f"records.include: {', '.join(sorted(want & {'table1', 'added'}))}: no records directory "
            f"(records.dir, ${ENV_RECORDS} or ./{DEFAULT_RECORDS_DIR})"
        )
    if include is not None:
        use_samples = "samples" in want
    else:
        use_samples = directory is None or (not table1 and bool(added))
    samples: list[RecordSpec] = []
    if use_samples:
        try:
            samples = [_sample_spec(s) for s in sample_records()]
        except IsorockError as exc:
            warn.append(
                f"the pyslammer samples do not run: {exc}" if added or table1 else f"no records run: {exc}"
            )
    if samples and added:
        added = _not_samples(added, samples, manifest, directory, warn)
    parts = ["pyslammer samples"] if samples else []
    if directory is not None and (table1 or added or not samples):
        where = " (the default place of 'isorock records add')" if implicit else ""
        parts.append(f"records directory {directory}{where}")
    source = " + ".join(parts) or "none"
    select = list(rc.get("select") or [])
    records = _selected(samples + table1 + added, select, rc.get("max_records"), warn)
    if not records:
        raise ConfigError(f"no records to run from {source}: {_why_none(directory, select, include)}")
    return RecordSet(records, source, warn)


def _directory_records(
    directory: Path, rc: Mapping, base: Path, want: set[str], explicit: bool, warn: list[str]
) -> tuple[list[ManifestEntry], list[RecordSpec], list[RecordSpec]]:
    """The manifest, the catalog rows with a file and the added records of a records directory
    (those of ``want``), with the warning lines."""
    manifest_path = directory / "manifest.csv"
    manifest = read_manifest(manifest_path) if manifest_path.is_file() else []
    if not manifest_path.is_file():
        warn.append(f"{directory}: no manifest.csv: only catalog rows with their own file can be found")
    row_warnings: list[str] = []
    table1: list[RecordSpec] = []
    if "table1" in want:
        table1 = catalog_records(
            resolve_path(rc.get("catalog"), base),
            directory,
            manifest,
            row_warnings,
            use_substitutes=bool(rc.get("use_substitutes")),
        )
    added = added_records(directory, manifest, {r.id for r in table1}, warn) if "added" in want else []
    if table1 or any(e.table1_id for e in manifest):
        warn += row_warnings  # a directory of catalog records: one line per row it lacks
    elif row_warnings and added:  # the user's own records only: one line for all the rows
        warn.append(
            f"{directory} holds no file of the {len(row_warnings)} catalog rows: its added records run"
            + ("" if explicit else " with the pyslammer samples")
        )
    return manifest, table1, added


def _selected(
    records: list[RecordSpec], select: list[str], max_records: Any, warn: list[str]
) -> list[RecordSpec]:
    """``records.select`` and ``records.max_records`` applied; reserved ids refused."""
    if select:
        have = {r.id for r in records}
        for rid in select:
            if rid not in have:
                warn.append(f"records.select: {rid!r} is not among the records present; skipped")
        records = [r for r in records if r.id in select]
    if max_records:
        records = records[: int(max_records)]
    for r in records:
        if r.id.startswith("pulse-"):
            raise IsorockError(f"record id {r.id!r}: ids starting with 'pulse-' are reserved for pulses")
    return records


def _sample_spec(s: SampleRecord) -> RecordSpec:
    """The record of a pyslammer sample."""
    return RecordSpec(
        id=s.name,
        label=f"{s.event} {s.year or ''}, {s.station} / {s.component}".replace("  ", " "),
        event=s.event,
        station=s.station,
        component=s.component,
        metadata=RecordMetadata(year=s.year),
        files=(RecordFile(path=str(s.path), format=s.format),),
        source="pyslammer samples",
    )


def _not_samples(
    added: list[RecordSpec],
    samples: list[RecordSpec],
    manifest: list[ManifestEntry],
    directory: Path | None,
    warn: list[str],
) -> list[RecordSpec]:
    """The added records that are not samples: one whose file is a sample's (same sha256) is the
    sample (one line said); another file under a sample's name is refused."""
    by_sha = {file_sha256(r.files[0].path): r.id for r in samples}
    names = {r.id for r in samples}
    entry = {e.id: e for e in manifest if e.id}
    out = []
    for r in added:
        e = entry.get(r.id)
        sha = (e.sha256 if e is not None else "") or file_sha256(r.files[0].path)
        if sha in by_sha:
            warn.append(
                f"record {r.id} ({Path(r.files[0].path).name}) is the pyslammer sample {by_sha[sha]} "
                "(same sha256): it runs once, as the sample"
            )
            continue
        if r.id in names:
            where = f"{directory / 'manifest.csv'}:{e.line}: " if e is not None and directory else ""
            raise ConfigError(
                f"{where}id {r.id!r} is also the name of a pyslammer sample record (another file): rename "
                "it, or leave the samples out with records.include: [table1, added]"
            )
        out.append(r)
    return out


def catalog_record(
    rid: str, directory: str | Path | None = None, *, catalog: str | Path | None = None
) -> RecordSpec:
    """One record by its id, as the workflow would run it: a catalog row with its files in a records
    directory, a record added to it with ``isorock records add``, or a pyslammer sample.

    Parameters
    ----------
    rid : str
        Catalog id (``NOR94-RRS``), added record id, or sample name.
    directory : path-like, optional
        Records directory; default ``$ISOROCK_RECORDS`` (:func:`isorock.records.directory.records_dir`),
        else ``./records`` when it holds a manifest.
    catalog : path-like, optional
        Catalog CSV; default the Table 1 catalog.

    Returns
    -------
    RecordSpec
        An added record's files carry the manifest's format, units, time step and component.

    Raises
    ------
    IsorockError
        No records directory for a catalog row, an unknown id, or no file of the record in the
        directory (a substitute file of a catalog row is used, and said so, when it is the only one).
    """
    d = records_dir(Path(directory) if directory is not None else None)
    if d is None:
        d = default_records_dir()
    manifest: list[ManifestEntry] = []
    if d is not None:
        d = d.resolve()
        mpath = d / "manifest.csv"
        manifest = read_manifest(mpath) if mpath.is_file() else []
    warn: list[str] = []
    mine = [e for e in manifest if e.id == rid and not e.table1_id]
    if d is not None and mine:
        # the whole manifest: the record's vertical is a row of its own (without an id)
        found = added_records(d, manifest, set(), warn, only=rid)
        if found:
            return found[0]
        raise IsorockError(warn[0].replace(" skipped: ", ": ", 1))
    ids = list(cat.load_catalog(catalog)["id"])
    if rid not in ids:
        sample = _sample_named(rid)
        if sample is not None:
            return sample
        added_ids = [e.id for e in manifest if e.id and not e.table1_id]
        nor = f" nor a record added to {d}" if d is not None else ""
        extra = f"; added: {', '.join(added_ids)}" if added_ids else ""
        raise IsorockError(f"record {rid!r} is not a catalog row{nor}: valid {', '.join(ids)}{extra}")
    if d is None:
        raise IsorockError(f"record {rid}: no records directory: give --records DIR or set $ISOROCK_RECORDS")
    catalog_path = Path(catalog) if catalog is not None else None
    for spec in catalog_records(catalog_path, d, manifest, warn, use_substitutes=True):
        if spec.id == rid:
            return spec
    why = next((w for w in warn if w.startswith(f"record {rid} ")), f"record {rid}: no file in {d}")
    raise IsorockError(why.replace(" skipped: ", ": ", 1))


#: another name of :func:`catalog_record`, which finds every kind of record
record_by_id = catalog_record


def _sample_named(rid: str) -> RecordSpec | None:
    """The pyslammer sample ``rid``, or None (also when pyslammer is not installed)."""
    try:
        samples = sample_records()
    except IsorockError:
        return None
    return next((_sample_spec(s) for s in samples if s.name == rid), None)


def _why_none(directory: Path | None, select: list[str], include: list[str] | None = None) -> str:
    """Why a run has no record, in words, with what to do."""
    if select:
        return f"records.select ({', '.join(select)}) names none of the records present"
    if include is not None:
        return (
            f"records.include ({', '.join(include) or 'empty'}) takes none of the records present; "
            f"valid {', '.join(INCLUDE)}, or leave it out for all of them"
        )
    if directory is None:
        return "no records directory, and the built-in samples need: pip install 'isorock[samples]'"
    return (
        "the directory holds no file of a catalog row and no record added with "
        f"'isorock records add FILE --records {directory}'"
    )
