"""How long the records of a run are, read before any job: the bounds on a record's length, the
durations the cost estimate counts and the memory the record jobs declare.

:func:`record_lengths` reads every file of every record of a plan (the reader every job uses) and
returns each record's samples, time step and duration (the longest of its files). A record longer
than the configuration's ``records.max_samples`` or ``records.max_duration_s`` stops the run before
any job, in one line naming the file and the keys that go beyond; so does a file too large to be
read for them (:func:`isorock.records.directory.check_size`, unread). A file that cannot be read is
left to the job that processes its record (which notes it and uses the record's other files).

The lengths found are kept in ``.snakemake/isorock-lengths.json`` of the run folder (:func:`keep_lengths`,
once a run goes ahead), by file path, size, modification time and reading options, so that a run of
hundreds of records reads them once.
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path

from isorock.errors import IsorockError, RecordError

__all__ = ["RecordLength", "record_lengths", "read_lengths", "keep_lengths", "LENGTHS_FILE"]

#: the lengths of the record files read by earlier runs, relative to the run folder
LENGTHS_FILE = ".snakemake/isorock-lengths.json"

#: the lengths read by this process (a notebook or a test session plans many runs), by the same keys
_SEEN: dict[str, list] = {}


@dataclass(frozen=True)
class RecordLength:
    """The length of one record of a run.

    Attributes
    ----------
    id : str
        Record id.
    file : str
        Its longest file.
    npts : int
        Samples [-].
    dt_s : float
        Time step [s].
    """

    id: str
    file: str
    npts: int
    dt_s: float

    @property
    def duration_s(self) -> float:
        """``(npts - 1) dt`` [s]."""
        return (self.npts - 1) * self.dt_s


def _key(f) -> str | None:
    """The key of a record file's length: its path, size, modification time and reading options;
    None when it is not there."""
    try:
        st = os.stat(f.path)
    except OSError:
        return None
    return json.dumps([str(Path(f.path).resolve()), st.st_size, st.st_mtime_ns, f.format, f.dt_s, f.units,
                       f.component])  # fmt: skip


def read_lengths(directory: Path) -> dict:
    """The lengths kept in the run folder ``directory`` (:data:`LENGTHS_FILE`; empty when none)."""
    return _read_cache(directory / LENGTHS_FILE)


def keep_lengths(directory: Path, lengths: dict) -> None:
    """Keep ``lengths`` (filled by :func:`record_lengths`) in the run folder ``directory``, atomically;
    nothing when it cannot be written (they are read again next time)."""
    _write_cache(directory / LENGTHS_FILE, lengths)


def _read_cache(path: Path) -> dict:
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def _write_cache(path: Path, data: dict) -> None:
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
        tmp.write_text(json.dumps(data))
        os.replace(tmp, path)
    except OSError:  # a read-only run folder: the lengths are read again next time
        pass


def record_lengths(
    records, config: Mapping, cache: dict | None = None, notify: Callable[[str], None] | None = None
) -> list[RecordLength]:
    """The length of every record of a run; a record too long for the configuration is refused.

    Parameters
    ----------
    records : list of RecordSpec
        The records of the run (:attr:`isorock.control.plan.Plan.records`).
    config : mapping
        The validated configuration (``records.max_samples``, ``records.max_duration_s``).
    cache : dict, optional
        The lengths read before (:func:`read_lengths`): used where a file is unchanged, and left holding
        those of this run's files, for :func:`keep_lengths` once the run goes ahead.
    notify : callable, optional
        Called with one line before reading many files that were not read before.

    Returns
    -------
    list of RecordLength
        One per record whose files could be read, in the order of ``records``.

    Raises
    ------
    IsorockError
        A record file of more samples than ``records.max_samples`` or longer than
        ``records.max_duration_s``, or too large to be read for them.
    """
    from isorock.io import read_trace
    from isorock.records.directory import BEYOND_CONFIG, check_size, too_long

    max_n = int(config["records"]["max_samples"])
    max_s = float(config["records"]["max_duration_s"])
    known = {**_SEEN, **(cache or {})}
    keys = [[_key(f) for f in r.files] for r in records]
    todo = sum(1 for ks in keys for k in ks if k is not None and k not in known)
    if notify is not None and todo >= 50:
        notify(f"isorock: reading the length of {todo} record files (once: kept in {LENGTHS_FILE})")
    out, seen = [], {}
    for r, ks in zip(records, keys, strict=True):
        best: RecordLength | None = None
        for f, key in zip(r.files, ks, strict=True):
            if key is None:
                continue  # no such file: the record's job says so
            if key not in known:
                big = check_size(f.path, max_n, BEYOND_CONFIG)
                if big:
                    raise IsorockError(f"record {r.id}: {big}")
                try:
                    tr = read_trace(f.path, f.format, dt=f.dt_s, units=f.units, component=f.component)
                except RecordError:
                    continue  # the record's job notes it and uses its other files
                known[key] = [int(tr.stats.npts), float(tr.stats.delta)]
            npts, dt = known[key]
            seen[key] = known[key]
            long = too_long(f.path, npts, dt, max_n, max_s, BEYOND_CONFIG)
            if long:
                raise IsorockError(f"record {r.id}: {long}")
            if best is None or (npts - 1) * dt > best.duration_s:
                best = RecordLength(r.id, f.path, npts, dt)
        if best is not None:
            out.append(best)
    _SEEN.update(seen)
    if cache is not None:
        cache.clear()
        cache.update(seen)
    return out
