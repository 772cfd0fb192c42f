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

import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path
from typing import Any

from isorock.constants import ENV_RECORDS
from isorock.errors import ConfigError, IsorockError
from isorock.records import catalog as cat
from isorock.records.components import RecordFile, Target
from isorock.records.directory import (
    DEFAULT_RECORDS_DIR,
    SampleRecord,
    default_records_dir,
    records_dir,
    sample_records,
)
from isorock.records.manifest import ManifestEntry, catalog_status, read_manifest
from isorock.records.metadata import METADATA_COLUMNS, RecordMetadata
from isorock.store import file_sha256

__all__ = [
    "INCLUDE",
    "RecordFile",
    "RecordSpec",
    "RecordSet",
    "find_records",
    "catalog_record",
    "record_by_id",
    "resolve_path",
]


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


def _num(v: Any) -> float | None:
    try:
        x = float(v)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


def _text(v: Any) -> str:
    """A text cell of the catalog ("" for a missing one, which pandas gives as NaN)."""
    return v if isinstance(v, str) else ""


def resolve_path(p: str | None, basedir: Path) -> Path | None:
    """A path of the configuration: absolute, or relative to ``basedir``."""
    if p is None or str(p).strip() == "":
        return None
    q = Path(str(p)).expanduser()
    return q if q.is_absolute() else (basedir / q)


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
        table1 = _catalog_records(
            resolve_path(rc.get("catalog"), base),
            directory,
            manifest,
            row_warnings,
            use_substitutes=bool(rc.get("use_substitutes")),
        )
    added = _added_records(directory, manifest, {r.id for r in table1}, warn) if "added" in want else []
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
        found = _added_records(d, manifest, set(), warn, only=rid)
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
    for spec in _catalog_records(catalog_path, d, manifest, warn, use_substitutes=True):
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


def _added_records(
    directory: Path, manifest: list[ManifestEntry], taken: set[str], warn: list[str], only: str | None = None
) -> list[RecordSpec]:
    """The user's own records of a directory: manifest rows with an ``id`` and no catalog row; each
    with the vertical components registered beside it (rows without an id): those of its event and
    station, or, where the files name neither, those whose file name is its own up to the last ``-`` or
    ``_`` (``SET-UP.txt`` beside ``SET-hor1.txt``); a record of PEER's (a manifest ``rsn``) takes the
    verticals of its ``rsn`` and, as a ``partner`` file (the second component of a pair), its second
    horizontal (:data:`isorock.records.manifest.PAIRED_NOTE`). ``only``: that record alone."""
    from isorock.records.components import is_vertical
    from isorock.records.manifest import PAIRED_NOTE

    verticals = [
        e for e in manifest
        if not e.id and not e.table1_id and is_vertical(e.component) and (directory / e.file).is_file()
    ]  # fmt: skip

    def stem(name: str) -> str:
        cut = max(name.rfind("-"), name.rfind("_"))
        return name[: cut + 1] if cut > 0 else name

    def beside(e: ManifestEntry, v: ManifestEntry) -> bool:
        if e.metadata.rsn is not None and v.metadata.rsn is not None:
            return e.metadata.rsn == v.metadata.rsn
        same_station = bool(e.event or e.station) and (v.event, v.station) == (e.event, e.station)
        return same_station or stem(v.file) == stem(e.file)

    out = []
    for e in manifest:
        if not e.id or e.table1_id or (only is not None and e.id != only):
            continue
        if e.id in taken:
            raise ConfigError(f"{directory / 'manifest.csv'}:{e.line}: id {e.id!r} is also a catalog row")
        if not (directory / e.file).is_file():
            warn.append(f"record {e.id} skipped: {e.file} is not in {directory}")
            continue
        label = ", ".join(x for x in (e.event, " / ".join(y for y in (e.station, e.component) if y)) if x)
        rsn = e.metadata.rsn
        paired = [
            replace(RecordFile.from_entry(directory, p), partner=True)
            for p in manifest
            if rsn is not None and p.metadata.rsn == rsn and not p.id and not p.table1_id
            and PAIRED_NOTE in p.note and not is_vertical(p.component) and (directory / p.file).is_file()
        ]  # fmt: skip
        out.append(
            RecordSpec(
                id=e.id,
                label=label or e.file,
                event=e.event,
                station=e.station,
                component=e.component,
                files=(
                    RecordFile.from_entry(directory, e),
                    *(RecordFile.from_entry(directory, v) for v in verticals if beside(e, v)),
                    *paired,
                ),
                source="records directory",
                metadata=e.metadata,
            )
        )
    return out


def _catalog_records(
    catalog_path: Path | None,
    directory: Path,
    manifest: list[ManifestEntry],
    warn: list[str],
    *,
    use_substitutes: bool,
) -> list[RecordSpec]:
    """The catalog rows with a file in ``directory`` (one warning line per row skipped).

    The files of a row are its manifest files (and its catalog ``file``), then, as ``partner`` files
    (second components for a rotation only, :mod:`isorock.records.components`), the manifest files
    of the other catalog rows of the same event and station (Table 1's GBZ/SN and GBZ/SP rows: one
    recording, a file each).
    """
    catalog = cat.load_catalog(catalog_path)
    status = {s.id: s for s in catalog_status(directory, manifest, catalog)}
    cat_dir = Path(catalog.attrs["path"]).parent
    rows = catalog.to_dict("records")
    out = []
    for row in rows:
        rid = row["id"]
        st = status[rid]
        desc = f"{row['event']} {row.get('year') or ''}, {row['station']} / {row['component']}"
        desc = " ".join(desc.split())
        files: list[RecordFile] = []
        for e in manifest:
            if e.table1_id != rid or not (directory / e.file).is_file():
                continue
            files.append(RecordFile.from_entry(directory, e))
        own = row.get("file")
        if isinstance(own, str) and own:
            p = Path(own) if Path(own).is_absolute() else cat_dir / own
            if p.is_file():
                files.append(
                    RecordFile(
                        path=str(p.resolve()),
                        format=_text(row.get("format")) or None,
                        dt_s=_num(row.get("dt_s")),
                        units=_text(row.get("units")) or None,
                        component=_text(row.get("column")) or None,
                    )
                )
        good = [f for f in files if not f.substitute]
        subs = [f for f in files if f.substitute]
        if not good and subs and not use_substitutes:
            names = ", ".join(Path(f.path).name for f in subs)
            warn.append(
                f"record {rid} ({desc}) skipped: only a substitute file ({names}); "
                "set records.use_substitutes: true to run it"
            )
            continue
        if not good and not subs:
            missing = f" (listed but absent: {', '.join(st.failed)})" if st.failed else ""
            warn.append(f"record {rid} ({desc}) skipped: no file in {directory}{missing}")
            continue
        out.append(
            RecordSpec(
                id=rid,
                label=desc,
                event=str(row["event"]),
                station=str(row["station"]),
                component=str(row["component"]),
                strike_deg=_num(row.get("strike_deg")),
                strike_source=_text(row.get("strike_source")),
                tp_source=_text(row.get("tp_source")),
                catalog_id=rid,
                table1_pga_g=_num(row.get("pga_g")),
                table1_pgv_m_s=_num(row.get("pgv_m_s")),
                table1_tp_s=_num(row.get("tp_s")),
                files=tuple(good or subs) + _partner_files(directory, manifest, rid, rows),
                source="records directory",
                metadata=RecordMetadata(year=_year(row.get("year"))),
            )
        )
    return out


def _year(v: Any) -> int | None:
    """The year of a catalog row (None when not given)."""
    return None if v is None or _num(v) is None else int(v)


def _recording(row: Mapping) -> tuple[str, str]:
    """The event and station of a catalog row, the recording its files come from."""
    return str(row["event"]).strip().lower(), str(row["station"]).strip().lower()


def _partner_files(
    directory: Path, manifest: list[ManifestEntry], rid: str, rows: list[dict]
) -> tuple[RecordFile, ...]:
    """The files of the other catalog rows of the recording of row ``rid`` (same event and station),
    marked ``partner``; substitutes left out."""
    mine = next(_recording(r) for r in rows if r["id"] == rid)
    others = {r["id"] for r in rows if r["id"] != rid and _recording(r) == mine}
    return tuple(
        replace(RecordFile.from_entry(directory, e), partner=True)
        for e in manifest
        if e.table1_id in others and not e.is_substitute and (directory / e.file).is_file()
    )
