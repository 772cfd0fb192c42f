"""Where the record files are: the user's records directory and the built-in samples; record checks.

What is in a records directory (its ``manifest.csv``, the catalog rows it provides, adding records
to it) is :mod:`isorock.records.manifest`.

* :func:`records_dir` says which directory holds the user's record files: a value from the
  configuration or the command line, else the ``ISOROCK_RECORDS`` environment variable (the one
  place that reads it); :func:`default_records_dir` is the place ``isorock records add`` uses when
  neither names one (``./records``), which a run then finds too;
* :func:`check_file` / :func:`check_trace` read a record and check that it is usable;
* :func:`sample_records` lists the built-in default record set: the ground motions shipped with the
  optional ``pyslammer`` package (GPL; install ``isorock[samples]``), read in place, never copied.
"""

from __future__ import annotations

import importlib.util
import math
import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from isorock.constants import ENV_RECORDS, G
from isorock.errors import IsorockError, RecordError
from isorock.io import read_record, trace_component

__all__ = [
    "ENV_RECORDS",
    "DEFAULT_RECORDS_DIR",
    "FileCheck",
    "SampleRecord",
    "records_dir",
    "default_records_dir",
    "MAX_DURATION_S",
    "MAX_SAMPLES",
    "check_file",
    "check_size",
    "check_trace",
    "too_long",
    "sample_records",
    "samples_dir",
]


# limits of a plausible record used by check_file (the readers refuse PGA > 10 g outright)
MIN_PGA_G = 0.005
MIN_DURATION_S = 1.0

#: the longest record analysed unless asked for more [s]: strong-motion records last up to a few
#: hundred seconds (a great earthquake's, about 300 s); a longer one is most likely a continuous
#: recording, or a file read with a wrong time step
MAX_DURATION_S = 600.0
#: the most samples of a record analysed unless asked for more: 600 s at 200 Hz is 120,000; the record
#: jobs' memory grows with the samples (benchmarks/bench_memory.py)
MAX_SAMPLES = 200_000
#: the most bytes a sample takes in a text record file (a CSV line of time and acceleration in full
#: precision): a larger file is refused before it is read, the reading of a huge file costing gigabytes
MAX_BYTES_PER_SAMPLE = 64

#: how to go beyond the limits, for the messages of the commands that read a record
BEYOND = (
    "--max-samples N / --max-duration S, or records.max_samples / records.max_duration_s of the "
    "configuration, to go beyond"
)
#: the same for a workflow run
BEYOND_CONFIG = "raise records.max_samples / records.max_duration_s of the configuration to go beyond"


# --------------------------------------------------------------------------- records directory
def records_dir(config_value: str | Path | None = None, *, must_exist: bool = True) -> Path | None:
    """The directory holding the user's record files.

    Parameters
    ----------
    config_value : str or Path, optional
        Directory named in the configuration or on the command line; it wins over the environment.
    must_exist : bool
        Raise if the named directory does not exist.

    Returns
    -------
    Path or None
        ``config_value``, else ``$ISOROCK_RECORDS``, else None (meaning: use :func:`sample_records`).

    Raises
    ------
    IsorockError
        The named directory does not exist or is not a directory.
    """
    source = "records directory"
    value: str | Path | None = config_value
    if value is None or str(value).strip() == "":
        env = os.environ.get(ENV_RECORDS, "").strip()
        if not env:
            return None
        value, source = env, f"{ENV_RECORDS}"
    path = Path(value).expanduser()
    if must_exist and not path.is_dir():
        raise IsorockError(f"{path}: {source} does not exist or is not a directory")
    return path


DEFAULT_RECORDS_DIR = "records"
"""The records directory ``isorock records add`` uses when neither ``--records`` nor
``$ISOROCK_RECORDS`` names one (relative to the working directory)."""


def default_records_dir(basedir: str | Path | None = None) -> Path | None:
    """``basedir/records`` (:data:`DEFAULT_RECORDS_DIR`) when it holds a ``manifest.csv`` (records
    added there with ``isorock records add``), else None.

    Parameters
    ----------
    basedir : path-like, optional
        The working directory of the run (default: the current directory).
    """
    d = (Path(basedir) if basedir is not None else Path.cwd()) / DEFAULT_RECORDS_DIR
    return d if (d / "manifest.csv").is_file() else None


# --------------------------------------------------------------------------- checks
@dataclass
class FileCheck:
    """Result of checking one record file.

    Parameters
    ----------
    file : str
        The file (as listed).
    ok : bool
        Readable and plausible.
    problem : str
        What is wrong ("" if ok).
    format : str
        Format used.
    npts : int
        Samples [-].
    dt_s : float
        Time step [s].
    pga_g : float
        Peak ground acceleration [g].
    duration_s : float
        ``(npts - 1) dt`` [s].
    component : str
        Component read.
    table1_id : str
        Catalog row it belongs to.
    id : str
        Record id of a record that is not a catalog row.
    """

    file: str
    ok: bool
    problem: str = ""
    format: str = ""
    npts: int = 0
    dt_s: float = math.nan
    pga_g: float = math.nan
    duration_s: float = math.nan
    component: str = ""
    table1_id: str = ""
    id: str = ""


def check_file(
    path: str | Path,
    format: str | None = None,
    *,
    dt: float | None = None,
    units: str | None = None,
    component: str | None = None,
    label: str | None = None,
    max_samples: int = MAX_SAMPLES,
    max_duration_s: float = MAX_DURATION_S,
) -> FileCheck:
    """Read a record and check it is usable: readable, units plausible, dt sane, long enough and not
    too long.

    Returns a :class:`FileCheck`; reading errors become ``ok=False`` with the error message. A file
    too large for ``max_samples`` is refused unread (:func:`check_size`). See :func:`check_trace` for
    the checks after reading.
    """
    label = label or str(path)
    big = check_size(path, max_samples)
    if big:
        return FileCheck(label, False, big, format or "")
    try:
        st = read_record(path, format, dt=dt, units=units, component=component)
    except RecordError as exc:
        return FileCheck(label, False, str(exc), format or "")
    return check_trace(st[0], label, max_samples=max_samples, max_duration_s=max_duration_s)


def check_size(path: str | Path, max_samples: int = MAX_SAMPLES, beyond: str = BEYOND) -> str:
    """Why the file ``path`` is too large to be a record of at most ``max_samples`` samples (more than
    :data:`MAX_BYTES_PER_SAMPLE` bytes a sample), or "" (also when it cannot be looked at: reading it
    says why); ``beyond`` ends the message (how to go beyond)."""
    try:
        size = os.stat(path).st_size
    except OSError:
        return ""
    if size <= max_samples * MAX_BYTES_PER_SAMPLE:
        return ""
    return (
        f"{path}: {size / 1e6:,.1f} MB, more than a record of at most {max_samples:,} samples takes "
        f"(not read; {beyond})"
    )


def check_trace(
    tr, label: str = "", *, max_samples: int = MAX_SAMPLES, max_duration_s: float = MAX_DURATION_S
) -> FileCheck:
    """Check a trace read by :func:`isorock.io.read_record`.

    A PGA below :data:`MIN_PGA_G` (a file in g read as cm/s^2?), a record shorter than
    :data:`MIN_DURATION_S`, or one of more than ``max_samples`` samples or longer than
    ``max_duration_s`` [s] fails; the readers already refuse PGA > 10 g and a bad dt.
    """
    info = tr.stats.get("isorock", {})
    src = info.get("source", label)
    pga_g = float(np.max(np.abs(tr.data))) / G
    dur = (tr.stats.npts - 1) * tr.stats.delta
    fc = FileCheck(
        label or src,
        True,
        "",
        info.get("format", ""),
        int(tr.stats.npts),
        float(tr.stats.delta),
        pga_g,
        dur,
        trace_component(tr),
    )
    if pga_g < MIN_PGA_G:
        fc.ok, fc.problem = (
            False,
            (
                f"{src}: PGA {pga_g:.3g} g is implausibly small for a strong-motion record "
                f"(units {info.get('units')}): wrong units?"
            ),
        )
    elif dur < MIN_DURATION_S:
        fc.ok, fc.problem = False, f"{src}: record lasts only {dur:.3g} s (< {MIN_DURATION_S:g} s)"
    elif long := too_long(src, tr.stats.npts, tr.stats.delta, max_samples, max_duration_s):
        fc.ok, fc.problem = False, long
    return fc


def too_long(
    src: str | Path,
    npts: int,
    dt: float,
    max_samples: int = MAX_SAMPLES,
    max_duration_s: float = MAX_DURATION_S,
    beyond: str = BEYOND,
) -> str:
    """Why the record ``src`` of ``npts`` samples at ``dt`` [s] is longer than the bounds, or "";
    ``beyond`` ends the message (how to go beyond)."""
    dur = (npts - 1) * dt
    if npts <= max_samples and dur <= max_duration_s:
        return ""
    return (
        f"{src}: {npts:,} samples over {dur:,.1f} s, longer than isorock analyses unless asked (at most "
        f"{max_samples:,} samples and {max_duration_s:g} s; {beyond})"
    )


# --------------------------------------------------------------------------- default record set
_SAMPLE_NAME = re.compile(r"^(?P<event>.+)_(?P<year>\d{4})_(?P<station>[^_]+)-(?P<component>[^-_]+)$")

SAMPLES_MISSING = (
    "no records directory given (set {env} or name one) and the built-in sample record set needs the "
    "optional package pyslammer: pip install 'isorock[samples]'"
)


@dataclass(frozen=True)
class SampleRecord:
    """A ground motion of the built-in default set (pyslammer's sample motions).

    Parameters
    ----------
    name : str
        File stem, e.g. ``Imperial_Valley_1979_BCR-230``.
    path : Path
        The CSV file inside the installed pyslammer package.
    event : str
        Earthquake, e.g. ``Imperial Valley``.
    year : int or None
        Year of the earthquake.
    station, component : str
        Station code and component.
    format : str
        Always ``pyslammer-csv`` (time [s], acceleration [g]).
    """

    name: str
    path: Path
    event: str
    year: int | None
    station: str
    component: str
    format: str = "pyslammer-csv"


def samples_dir() -> Path:
    """Folder of pyslammer's sample ground motions (found without importing pyslammer).

    Raises
    ------
    IsorockError
        pyslammer is not installed, or its data folder is missing.
    """
    spec = importlib.util.find_spec("pyslammer")
    if spec is None or not spec.submodule_search_locations:
        raise IsorockError(SAMPLES_MISSING.format(env=ENV_RECORDS))
    for loc in spec.submodule_search_locations:
        d = Path(loc) / "sample_ground_motions"
        if d.is_dir():
            return d
    raise IsorockError("pyslammer is installed but has no sample_ground_motions folder: reinstall it")


def sample_records() -> list[SampleRecord]:
    """The built-in default record set: pyslammer's sample ground motions, sorted by name.

    Raises
    ------
    IsorockError
        With installation advice when pyslammer is not installed.
    """
    out = []
    for p in sorted(samples_dir().glob("*.csv")):
        m = _SAMPLE_NAME.match(p.stem)
        if m:
            out.append(
                SampleRecord(
                    p.stem, p, m["event"].replace("_", " "), int(m["year"]), m["station"], m["component"]
                )
            )
        else:
            out.append(SampleRecord(p.stem, p, p.stem.replace("_", " "), None, "", ""))
    return out
