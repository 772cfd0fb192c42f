"""The records of a records directory, from its manifest: the paper's catalog rows that have a file
there (with the partner files of the same recording, the second component of a rotation) and the
records added with ``isorock records add``."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path
from typing import Any

import isorock.records.catalog as cat
from isorock.errors import ConfigError
from isorock.records.manifest import ManifestEntry, catalog_status
from isorock.records.metadata import RecordMetadata
from isorock.records.spec import RecordFile, RecordSpec

__all__ = ["added_records", "catalog_records"]


def _num(v: Any) -> float | None:
    try:
        x = float(v)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


def _text(v: Any) -> str:
    """A text cell of the catalog ("" for a missing one, which pandas gives as NaN)."""
    return v if isinstance(v, str) else ""


def added_records(
    directory: Path, manifest: list[ManifestEntry], taken: set[str], warn: list[str], only: str | None = None
) -> list[RecordSpec]:
    """The user's own records of a directory: manifest rows with an ``id`` and no catalog row; each
    with the vertical components registered beside it (rows without an id): those of its event and
    station, or, where the files name neither, those whose file name is its own up to the last ``-`` or
    ``_`` (``SET-UP.txt`` beside ``SET-hor1.txt``); a record of PEER's (a manifest ``rsn``) takes the
    verticals of its ``rsn`` and, as a ``partner`` file (the second component of a pair), its second
    horizontal (:data:`isorock.records.manifest.PAIRED_NOTE`). ``only``: that record alone."""
    from isorock.records.manifest import PAIRED_NOTE
    from isorock.records.naming import is_vertical

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


def catalog_records(
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
