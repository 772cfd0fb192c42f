"""Reading strong-motion records: ObsPy format plugins and one entry point, :func:`read_record`.

The plugins (``peer``, ``bbp``, ``plain``) are registered with ObsPy through the entry points of
``pyproject.toml`` (the only list of them), so ``obspy.read(path)`` reads PEER AT2, BBP, pyslammer
CSV files and ``%``-header files that state their time step without a format argument, and
``obspy.read(path, format="ONECOLUMN", dt=0.01, units="g")`` reads headerless ones.
Every trace holds acceleration in m/s^2 with ``stats.delta`` [s], ``stats.station``,
``stats.channel`` (component) and ``stats.isorock`` (source file, format, original units, event
text, header lines ...).

=================  ==================  ===============================================
manifest name      ObsPy format        time step / units from
=================  ==================  ===============================================
``peer-at2``       ``PEERAT2``         header (3 variants: NGA-West2, PE&A, NGA 2005)
``peer-at2-body``  ``PEERAT2BODY``     ``dt=``, ``units=``
``one-column``     ``ONECOLUMN``       ``dt=``, ``units=``
``two-column``     ``TWOCOLUMN``       time column, ``units=``
``bbp``            ``BBP``             time column, header
``percent-header`` ``PERCENTHEADER``   header or ``dt=``; ``units=`` (or header)
``pyslammer-csv``  ``PYSLAMMERCSV``    time column, header (g)
=================  ==================  ===============================================
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import obspy
from obspy import Stream, Trace

from isorock.errors import (
    BinaryFileError,
    ColumnCountError,
    EmptyRecordError,
    HeaderError,
    MissingTimeStepError,
    MissingUnitsError,
    NonFiniteError,
    NonNumericError,
    NptsMismatchError,
    RecordError,
    TimeStepError,
    TruncatedRecordError,
    UnitsError,
    UnknownFormatError,
)
from isorock.io._common import (
    LIMITS,
    Limits,
    TextLines,
    normalize_units,
    peek_lines,
    seed_code,
    trace_component,
    trace_station,
)
from isorock.physics.excitation import GroundMotion

__all__ = [
    "FORMATS",
    "OBSPY_FORMATS",
    "AUTODETECTED",
    "read_record",
    "read_trace",
    "to_ground_motion",
    "trace_component",
    "trace_station",
    "obspy_format",
    "normalize_units",
    "Limits",
    "LIMITS",
    "RecordError",
    "EmptyRecordError",
    "BinaryFileError",
    "HeaderError",
    "NonNumericError",
    "NonFiniteError",
    "NptsMismatchError",
    "TruncatedRecordError",
    "TimeStepError",
    "UnitsError",
    "MissingTimeStepError",
    "MissingUnitsError",
    "ColumnCountError",
    "UnknownFormatError",
]

#: manifest format name -> ObsPy format name
OBSPY_FORMATS: dict[str, str] = {
    "peer-at2": "PEERAT2",
    "peer-at2-body": "PEERAT2BODY",
    "one-column": "ONECOLUMN",
    "two-column": "TWOCOLUMN",
    "bbp": "BBP",
    "percent-header": "PERCENTHEADER",
    "pyslammer-csv": "PYSLAMMERCSV",
}
#: the manifest format names, in the order above
FORMATS: tuple[str, ...] = tuple(OBSPY_FORMATS)
#: formats recognised without a format argument
AUTODETECTED: tuple[str, ...] = ("peer-at2", "bbp", "pyslammer-csv")

_BY_OBSPY = {v: k for k, v in OBSPY_FORMATS.items()}
_UNDETECTED = (
    "cannot tell the format: {looks}; isorock recognises peer-at2, bbp, pyslammer-csv files and "
    "percent-header files whose '%' header states the time step (a '%' line with the sample count and "
    "the time step); for other files give the format (peer-at2-body, one-column, two-column, "
    "percent-header) with dt and units"
)

_COMPONENT_ALIASES = {
    "NS": "N-S",
    "N/S": "N-S",
    "EW": "E-W",
    "E/W": "E-W",
    "UD": "U-D",
    "U/D": "U-D",
    "UP": "U-D",
}


def obspy_format(name: str, path: object = "") -> str:
    """ObsPy format name for a manifest name (``"peer-at2"``) or an ObsPy name (``"PEERAT2"``).

    Raises
    ------
    UnknownFormatError
        Not one of :data:`FORMATS`.
    """
    key = str(name).strip()
    if key.lower() in OBSPY_FORMATS:
        return OBSPY_FORMATS[key.lower()]
    if key.upper() in _BY_OBSPY:
        return key.upper()
    raise UnknownFormatError(path, f"unknown format {name!r}: valid {', '.join(FORMATS)}")


def read_record(
    path: str | Path,
    format: str | None = None,
    *,
    dt: float | None = None,
    units: str | None = None,
    component: str | None = None,
) -> Stream:
    """Read a strong-motion record file into an ObsPy Stream of accelerations [m/s^2].

    Parameters
    ----------
    path : str or Path
        The record file.
    format : str, optional
        One of :data:`FORMATS` (or its ObsPy name). None: detect it (PEER AT2, BBP, pyslammer CSV
        and ``%``-header files stating their time step, by their header; a headerless file of plain
        numbers is read as ``one-column`` or ``two-column`` by its count of values per line, with
        ``dt`` and ``units`` as given).
    dt : float, optional
        Time step [s]; required by ``one-column`` and ``peer-at2-body`` (and ``percent-header`` files
        whose header gives none), otherwise checked against the file.
    units : str, optional
        Units of the values in the file (``g``, ``m/s2``, ``cm/s2``); required where the file does
        not state them, otherwise checked against the file.
    component : str, optional
        Keep only this component (``stats.channel``, e.g. ``"N-S"`` or ``"164"``). A file with a
        single unnamed component takes it as its channel name.

    Returns
    -------
    obspy.Stream
        Traces in m/s^2 with ``stats.isorock`` metadata.

    Raises
    ------
    RecordError
        Any problem with the file (a subclass names the kind), the format or the component; the
        message names the file and, where it applies, the line.
    """
    spath = str(path)
    p = Path(spath)
    if not p.exists():
        raise RecordError(spath, "no such file")
    if p.is_dir():
        raise RecordError(spath, "is a directory, not a record file")
    # empty files and binary junk: refuse before any ObsPy plugin sees them
    TextLines.read(spath)
    name = obspy_format(format, spath) if format is not None else None
    kwargs = {k: v for k, v in (("dt", dt), ("units", units)) if v is not None}
    if name is None:
        # the format named to obspy.read, which then loads that plugin alone: left to ObsPy, the
        # detection imports every waveform plugin it knows (about 80 modules, 0.2 s) before it
        # reaches isorock's, which come last in its order
        name = _header_format(spath)
    if name is None:
        # a headerless numeric file: one value per line, or time and value per line
        plain = _plain_columns(spath)
        name = OBSPY_FORMATS[plain] if plain else None
    try:
        st = obspy.read(spath, format=name, check_compression=False, **kwargs)
    except RecordError:
        raise
    except TypeError as exc:
        if name is None and "Unknown format" in str(exc):
            raise UnknownFormatError(spath, _UNDETECTED.format(looks=_first_lines(spath))) from None
        raise RecordError(spath, f"cannot read: {exc}") from None
    except Exception as exc:  # a reader outside isorock, or ObsPy itself
        raise RecordError(spath, f"cannot read: {exc}") from None
    for tr in st:
        fmt = name or tr.stats.get("_format", "")
        if fmt not in _BY_OBSPY or "isorock" not in tr.stats:
            raise UnknownFormatError(
                spath,
                f"ObsPy reads this file as {fmt}, which is not a strong-motion acceleration format "
                f"isorock reads: valid {', '.join(FORMATS)}",
            )
        tr.stats.isorock.obspy_format = fmt
    if component is not None:
        st = _select(st, str(component), spath)
    return st


def _header_format(path: str) -> str | None:
    """The ObsPy name of the format with a recognisable header (:data:`AUTODETECTED` and
    ``percent-header`` files stating their time step) that claims the file, None if none does. The
    formats are tried in the order ObsPy tries isorock's plugins (by name), so that a file two of them
    claim is read as ``obspy.read`` without a format reads it."""
    from isorock.io import bbp, peer, plain

    detectors = (
        ("BBP", bbp._is_bbp),
        ("PEERAT2", peer._is_peer_at2),
        ("PERCENTHEADER", plain._is_percent_header),
        ("PYSLAMMERCSV", plain._is_pyslammer_csv),
    )
    return next((name for name, claims in detectors if claims(path)), None)


def _first_lines(path: str, n: int = 3, width: int = 40) -> str:
    """What the first lines of a file look like, in words (for the error of an undetected format)."""
    lines = [s for s in (peek_lines(path, 8192, 200) or []) if s.strip()]
    if not lines:
        return "the file holds no text line"
    shown = " | ".join(repr(s.strip()[:width] + ("..." if len(s.strip()) > width else "")) for s in lines[:n])
    nhead = 0
    while nhead < len(lines) and lines[nhead].lstrip().startswith(("%", "#")):
        nhead += 1
    rest = lines[nhead:]
    counts = sorted({len(s.replace(",", " ").split()) for s in rest[:50]})
    numeric = all(_is_number(t) for s in rest[:50] for t in s.replace(",", " ").split())
    what = []
    if nhead:
        mark = lines[0].lstrip()[0]
        note = " stating no time step" if mark == "%" else ""
        what.append(f"{nhead} '{mark}' header line{'s' if nhead > 1 else ''}{note}")
    if rest and numeric:
        per = "-".join(str(c) for c in (counts[0], counts[-1])) if len(counts) > 1 else str(counts[0])
        what.append(f"then {per} numbers per line" if nhead else f"{per} numbers per line, no header")
    elif rest:
        what.append("then text that is not numbers" if nhead else "text that is not numbers")
    return f"the file begins {shown} ({', '.join(what)})"


def _is_number(tok: str) -> bool:
    try:
        float(tok)
    except ValueError:
        return False
    return True


def _plain_columns(path: str) -> str | None:
    """``"one-column"`` or ``"two-column"`` for a file of plain numbers (``#``/``%`` comments allowed)
    with the same count of 1 or 2 values on every line of its first 4 kB; None otherwise."""
    lines = peek_lines(path, 4096, 200) or []
    counts = set()
    for line in lines:
        s = line.strip()
        if not s or s.startswith(("#", "%")):
            continue
        toks = s.replace(",", " ").split()
        try:
            [float(t) for t in toks]
        except ValueError:
            return None
        counts.add(len(toks))
    if counts == {1}:
        return "one-column"
    if counts == {2}:
        return "two-column"
    return None


def read_trace(
    path: str | Path,
    format: str | None = None,
    *,
    dt: float | None = None,
    units: str | None = None,
    component: str | None = None,
) -> Trace:
    """Read one component of a record file: :func:`read_record` that insists on a single trace.

    Parameters are those of :func:`read_record`. What the caller must add is reported at once: a
    time step or units the file does not state, and the choice of a component, in one error.

    Raises
    ------
    RecordError
        As :func:`read_record`; several missing pieces (time step, units, component) in one message.
    """
    problems: list[RecordError] = []
    given: dict[str, Any] = {"dt": dt, "units": units}
    # a missing time step or units: note it, and read on with a placeholder to find what else is missing
    placeholders: dict[type[RecordError], tuple[str, Any]] = {
        MissingTimeStepError: ("dt", 0.01),
        MissingUnitsError: ("units", "mm/s2"),
    }
    st = None
    for _ in range(len(placeholders) + 1):
        try:
            st = read_record(path, format, component=component, **given)
            break
        except (MissingTimeStepError, MissingUnitsError) as exc:
            key, value = placeholders[type(exc)]
            if given[key] is not None:
                raise
            problems.append(exc)
            given[key] = value
        except RecordError:
            if problems:  # what is missing comes first; the rest may follow from it
                break
            raise
    if st is not None and len(st) != 1:
        comps = ", ".join(trace_component(tr) or "(unnamed)" for tr in st)
        problems.append(
            RecordError(str(path), f"holds {len(st)} components ({comps}): choose one with --component")
        )
    if len(problems) == 1:
        raise problems[0]
    if problems:
        raise RecordError(str(path), "; ".join(p.problem for p in problems))
    assert st is not None  # every way out of the loop without a stream noted a problem
    return st[0]


def _norm_comp(c: str) -> str:
    c = c.strip().upper()
    return _COMPONENT_ALIASES.get(c, c)


def _select(st: Stream, wanted: str, path: str) -> Stream:
    want = _norm_comp(wanted)
    if len(st) == 1 and not trace_component(st[0]):
        st[0].stats.isorock.component = wanted
        st[0].stats.channel = seed_code(wanted, 3)
        return st
    hits = [tr for tr in st if _norm_comp(trace_component(tr)) == want]
    if not hits:
        have = ", ".join(trace_component(tr) or "(unnamed)" for tr in st)
        raise RecordError(path, f"no component {wanted!r} in this file: it holds {have}")
    return Stream(traces=hits[:1])


def to_ground_motion(trace: Trace, name: str | None = None) -> GroundMotion:
    """The engine's sampled ground motion from a trace read by :func:`read_record`.

    Parameters
    ----------
    trace : obspy.Trace
        Acceleration [m/s^2], ``stats.delta`` [s].
    name : str, optional
        Label; default ``<file name>`` plus ``:<component>`` when the trace has one.

    Returns
    -------
    GroundMotion
        ``dt`` [s], ``acc`` [m/s^2], ``meta`` = the ``stats.isorock`` entries plus station and channel.
    """
    info = dict(trace.stats.get("isorock", {}))
    comp = trace_component(trace)
    if name is None:
        src = Path(str(info.get("source", ""))).name or trace_station(trace) or "record"
        name = f"{src}:{comp}" if comp else src
    meta = {**info, "station": trace_station(trace), "channel": comp}
    return GroundMotion(
        dt=float(trace.stats.delta), acc=np.asarray(trace.data, dtype=float), name=name, meta=meta
    )
