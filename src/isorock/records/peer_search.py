"""A PEER NGA-West2 search folder: its ``_SearchResults.csv`` read, its records added to a records
directory (``isorock records add --peer-search DIR``).

PEER's ground-motion database (https://ngawest2.berkeley.edu) hands out a search as a folder: the
``.AT2`` files of each record (two horizontals and the vertical) and ``_SearchResults.csv``, a report
whose table of records sits between a preamble (the search criteria) and a summary block (notes, the
scaled spectra). :func:`read_search_results` finds the table by its header line (the columns
``Record Sequence Number`` ... ``Horizontal-1 Acc. Filename``, with PEER's leading blanks), reads its
rows up to the first blank one and gives one :class:`PeerRow` per record: the record sequence number
(RSN), earthquake, year, station, magnitude, mechanism, Rjb, Rrup, Vs30, lowest usable frequency, scale
factor and the three file names (``-----``: no such file, e.g. a record without a vertical).

:func:`add_peer_search` adds every row whose files are in the folder as the record ``RSN<n>`` (e.g.
``RSN1063``), in one transaction (:func:`isorock.records.manifest.add_records`: one lock, the manifest
written once): its first horizontal registered under the id, its second horizontal beside it without an
id of its own (the same ``rsn``, station and format: the two can be paired and rotated,
:mod:`isorock.records.components`), its vertical as the vertical of the record; every row of the
manifest carries the row's metadata (:class:`isorock.records.metadata.RecordMetadata`). A row whose
file is not in the folder is skipped with one line saying which; the others are added. Run again (after
a stop, or with more files), files already registered are recognised by their sha256 and not added
twice.
"""

from __future__ import annotations

import csv
import io
import math
import re
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from isorock.errors import IsorockError
from isorock.records.adding import add_records
from isorock.records.directory import MAX_DURATION_S, MAX_SAMPLES
from isorock.records.manifest import PAIRED_NOTE, ManifestEntry
from isorock.records.metadata import RecordMetadata

__all__ = [
    "SEARCH_RESULTS",
    "PAIRED_NOTE",
    "PeerRow",
    "PeerSearchResult",
    "read_search_results",
    "add_peer_search",
    "record_id",
]

#: the name of PEER's table of the records of a search, in the search folder
SEARCH_RESULTS = "_SearchResults.csv"
#: the largest ``_SearchResults.csv`` read [bytes] (PEER's, with its spectra: about 150 kB for 30 records)
MAX_BYTES = 20_000_000

#: the columns read, by their name in PEER's header (blanks around it, case ignored): the field
_COLUMNS: dict[str, str] = {
    "record sequence number": "rsn",
    "earthquake name": "earthquake",
    "year": "year",
    "station name": "station",
    "magnitude": "mw",
    "mechanism": "mechanism",
    "rjb (km)": "rjb_km",
    "rrup (km)": "rrup_km",
    "vs30 (m/sec)": "vs30_m_s",
    "vs30 (m/s)": "vs30_m_s",
    "lowest useable frequency (hz)": "luf_hz",
    "lowest usable frequency (hz)": "luf_hz",
    "scale factor": "scale_factor",
    "horizontal-1 acc. filename": "h1",
    "horizontal-2 acc. filename": "h2",
    "vertical acc. filename": "vertical",
}
_REQUIRED = ("rsn", "h1", "h2")
_NUMBERS = ("mw", "rjb_km", "rrup_km", "vs30_m_s", "luf_hz", "scale_factor")
#: the names of the numeric columns in messages
_LABELS = {
    "mw": "Magnitude", "rjb_km": "Rjb (km)", "rrup_km": "Rrup (km)", "vs30_m_s": "Vs30 (m/sec)",
    "luf_hz": "Lowest Useable Frequency (Hz)", "scale_factor": "Scale Factor",
}  # fmt: skip
#: a cell that stands for no value: empty, ``-`` or ``-----``
_NONE = re.compile(r"^-*$")


def record_id(rsn: int) -> str:
    """The record id of a PEER record: ``RSN<n>`` (``RSN1063``)."""
    return f"RSN{int(rsn)}"


@dataclass(frozen=True)
class PeerRow:
    """One record of a PEER search (a row of ``_SearchResults.csv``).

    Attributes
    ----------
    row : int
        Its number among the records of the table, from 1.
    line : int
        Its line in the file.
    metadata : RecordMetadata
        The recording's metadata: PEER's record sequence number (every row has one: :attr:`rsn`),
        magnitude, mechanism, distances, Vs30, lowest usable frequency, year (None or "" when not
        given, ``-``).
    earthquake, station : str
        As the table names them ("" when not given).
    scale_factor : float or None
        The scale factor of the search (None when not given).
    h1, h2, vertical : str or None
        File names of the two horizontals and the vertical (None: ``-----``, no such file).
    """

    row: int
    line: int
    metadata: RecordMetadata
    earthquake: str = ""
    station: str = ""
    scale_factor: float | None = None
    h1: str | None = None
    h2: str | None = None
    vertical: str | None = None

    @property
    def rsn(self) -> int:
        """PEER's record sequence number."""
        assert self.metadata.rsn is not None  # a row without one ends the table: read_search_results
        return self.metadata.rsn

    @property
    def id(self) -> str:
        """The record id, ``RSN<n>``."""
        return record_id(self.rsn)

    @property
    def files(self) -> tuple[str, ...]:
        """The file names the row gives (horizontals first)."""
        return tuple(f for f in (self.h1, self.h2, self.vertical) if f)

    def manifest_values(self) -> dict[str, Any]:
        """The values of the manifest row of each of its files: the metadata columns, and ``event``
        and ``station`` when the table names them."""
        out: dict[str, Any] = asdict(self.metadata)
        if self.earthquake:
            out["event"] = self.earthquake
        if self.station:
            out["station"] = self.station
        return out


def _clean(cell: str) -> str:
    """A cell without PEER's blanks and quotes (``' "Landers"'`` -> ``Landers``)."""
    return cell.strip().strip('"').strip()


def _header_key(cell: str) -> str:
    return " ".join(_clean(cell).lower().split())


def read_search_results(path: str | Path) -> list[PeerRow]:
    """The records of a PEER ``_SearchResults.csv``.

    Parameters
    ----------
    path : path-like
        The file (or the search folder holding it).

    Returns
    -------
    list of PeerRow
        In the order of the table.

    Raises
    ------
    IsorockError
        One line naming the file (and the line): it cannot be read, holds no table of records (no
        header line with the columns ``Record Sequence Number``, ``Horizontal-1 Acc. Filename`` and
        ``Horizontal-2 Acc. Filename``), the table has no row, a row's RSN is not a positive integer or
        is given twice, a number is not a number, a file name is a path.
    """
    path = Path(path)
    if path.is_dir():
        path = path / SEARCH_RESULTS
    what = "a PEER search report (NGA-West2 '_SearchResults.csv', with its table of records)"
    lines = _csv_lines(path, what)
    head = None
    for k, cells in enumerate(lines):
        keys = [_header_key(c) for c in cells]
        if "record sequence number" in keys and "horizontal-1 acc. filename" in keys:
            head = k
            break
    if head is None:
        raise IsorockError(
            f"{path}: no table of records (no line with the columns 'Record Sequence Number', "
            f"'Horizontal-1 Acc. Filename', 'Horizontal-2 Acc. Filename'): not {what}"
        )
    col: dict[str, int] = {}
    for j, c in enumerate(lines[head]):
        name = _COLUMNS.get(_header_key(c))
        if name and name not in col:
            col[name] = j
    missing = [n for n in _REQUIRED if n not in col]
    if missing:
        names = {v: k for k, v in reversed(list(_COLUMNS.items()))}
        raise IsorockError(
            f"{path}:{head + 1}: the table of records has no column "
            f"{', '.join(repr(names[n]) for n in missing)}: not {what}"
        )
    rows: list[PeerRow] = []
    seen: dict[int, int] = {}
    for k in range(head + 1, len(lines)):
        cells = lines[k]
        line = k + 1
        if not any(c.strip() for c in cells) or len(cells) <= col["rsn"] or not _clean(cells[col["rsn"]]):
            break  # the table ends at its first blank row (PEER's notes and spectra follow)
        r = _row(
            {n: _clean(cells[j]) if j < len(cells) else "" for n, j in col.items()}, len(rows) + 1, path, line
        )
        if r.rsn in seen:
            raise IsorockError(f"{path}:{line}: RSN {r.rsn} is given twice (first on line {seen[r.rsn]})")
        seen[r.rsn] = line
        rows.append(r)
    if not rows:
        raise IsorockError(f"{path}:{head + 1}: the table of records has no row")
    return rows


def _csv_lines(path: Path, what: str) -> list[list[str]]:
    """The cells of each line of a CSV file; refuses a file that cannot be read, too large, binary."""
    try:
        size = path.stat().st_size
        if size > MAX_BYTES:
            raise IsorockError(f"{path}: {size:,} bytes: too large for {what}")
        raw = path.read_bytes()
    except OSError as exc:
        raise IsorockError(f"{path}: cannot read it: {exc.strerror or exc}") from None
    if b"\0" in raw:
        raise IsorockError(f"{path}: binary, not {what}")
    text = raw.decode("utf-8-sig", errors="replace")
    try:
        lines = list(csv.reader(io.StringIO(text, newline="")))
    except csv.Error as exc:
        raise IsorockError(f"{path}: not CSV ({exc}): expected {what}") from None
    return lines


def _row(value: dict[str, str], row: int, path: Path, line: int) -> PeerRow:
    """One row of the table from its cells (by field name)."""
    rsn = _integer(value["rsn"], "Record Sequence Number", path, line, positive=True)
    assert rsn is not None  # a blank RSN ends the table: read_search_results
    numbers: dict[str, Any] = {n: _number(value.get(n, ""), _LABELS[n], path, line) for n in _NUMBERS}
    names: dict[str, Any] = {n: _file_name(value.get(n, ""), path, line) for n in ("h1", "h2", "vertical")}
    mechanism = value.get("mechanism", "")
    scale_factor = numbers.pop("scale_factor")
    metadata = RecordMetadata(
        rsn=rsn,
        year=_integer(value.get("year", ""), "Year", path, line),
        mechanism="" if _NONE.match(mechanism) else mechanism,
        **numbers,
    )
    return PeerRow(
        row=row,
        line=line,
        metadata=metadata,
        earthquake=value.get("earthquake", ""),
        station=value.get("station", ""),
        scale_factor=scale_factor,
        **names,
    )


def _number(cell: str, name: str, path: Path, line: int) -> float | None:
    if _NONE.match(cell):
        return None
    try:
        x = float(cell)
    except ValueError:
        x = math.nan
    if not math.isfinite(x):
        raise IsorockError(f"{path}:{line}: {name} {cell!r} is not a number")
    return x


def _integer(cell: str, name: str, path: Path, line: int, *, positive: bool = False) -> int | None:
    x = _number(cell, name, path, line)
    if x is None:
        return None
    if x != int(x) or (positive and x < 1):
        raise IsorockError(
            f"{path}:{line}: {name} {cell!r} is not {'a positive' if positive else 'an'} integer"
        )
    return int(x)


def _file_name(cell: str, path: Path, line: int) -> str | None:
    """A file name of the table (None for ``-----``); a path (``/``, ``\\``, ``..``) is refused: the
    files are those of the search folder."""
    if _NONE.match(cell):
        return None
    if "/" in cell or "\\" in cell or cell in (".", "..") or any(ord(c) < 32 for c in cell):
        raise IsorockError(f"{path}:{line}: file name {cell!r} is not the name of a file in the folder")
    return cell


@dataclass
class PeerSearchResult:
    """What :func:`add_peer_search` did.

    Attributes
    ----------
    rows : list of PeerRow
        Every row of the table.
    added : list of ManifestEntry
        The manifest rows written (none for a file already registered).
    records : list of str
        The record ids of the rows added, or already registered (``RSN<n>``), in table order.
    skipped : list of str
        One line per row skipped: ``_SearchResults.csv row 3 (RSN 1063): file ... is not in DIR``.
    notes : list of str
        Files already registered (not added again), leftovers removed.
    """

    rows: list[PeerRow]
    added: list[ManifestEntry] = field(default_factory=list)
    records: list[str] = field(default_factory=list)
    skipped: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)


def _skip_line(r: PeerRow, search_dir: Path) -> str | None:
    """Why the row cannot be added (a file is not in the folder), in one line, or None."""
    where = f"{SEARCH_RESULTS} row {r.row} (RSN {r.rsn})"
    if not (r.h1 or r.h2):
        return f"{where}: no horizontal file name"
    missing = [f for f in r.files if not (search_dir / f).is_file()]
    if not missing:
        return None
    if len(missing) == 1:
        return f"{where}: file {missing[0]} is not in {search_dir}"
    return f"{where}: files {', '.join(missing)} are not in {search_dir}"


def add_peer_search(
    search_dir: str | Path,
    directory: str | Path,
    *,
    replace: bool = False,
    waiting: Callable[[], None] | None = None,
    max_samples: int = MAX_SAMPLES,
    max_duration_s: float = MAX_DURATION_S,
) -> PeerSearchResult:
    """Add the records of a PEER search folder to a records directory (see the module docstring).

    Parameters
    ----------
    search_dir : path-like
        The folder holding ``_SearchResults.csv`` and the ``.AT2`` files.
    directory : path-like
        The records directory (created when absent).
    replace, waiting, max_samples, max_duration_s
        As :func:`isorock.records.manifest.add_records`.

    Returns
    -------
    PeerSearchResult
        ``skipped`` is not empty when a row's file is not in the folder.

    Raises
    ------
    IsorockError
        ``_SearchResults.csv`` is missing or malformed (:func:`read_search_results`), or a file cannot
        be added (unreadable, or an id or name registered with another content): nothing is added.
    """
    search_dir = Path(search_dir)
    if not search_dir.is_dir():
        raise IsorockError(f"--peer-search {search_dir}: not a folder (give PEER's search folder)")
    if not (search_dir / SEARCH_RESULTS).is_file():
        raise IsorockError(
            f"{search_dir}: no {SEARCH_RESULTS} (PEER's table of the records of a search, saved with them)"
        )
    rows = read_search_results(search_dir / SEARCH_RESULTS)
    result = PeerSearchResult(rows=rows)
    files: list[str | Path] = []
    ids: list[str] = []
    values: list[dict[str, Any]] = []
    for r in rows:
        why = _skip_line(r, search_dir)
        if why:
            result.skipped.append(why)
            continue
        first = r.h1 or r.h2
        for name in r.files:
            v = r.manifest_values()
            if name == r.vertical:  # the vertical of the record (records.vertical), no record of its own
                v.update(id="")
            elif name != first:  # the second horizontal: no record of its own, paired with the first
                v.update(id="", note=PAIRED_NOTE)
            files.append(search_dir / name)
            ids.append(r.id)
            values.append(v)
        result.records.append(r.id)
    if files:
        result.added = add_records(
            files,
            directory,
            ids=ids,
            metadata=values,
            replace=replace,
            notes=result.notes,
            waiting=waiting,
            max_samples=max_samples,
            max_duration_s=max_duration_s,
        )
    return result
