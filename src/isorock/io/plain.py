"""Plain numeric records: one column, two columns, ``%``-header files and pyslammer CSV files.

ObsPy format names and how the time step is found:

=================  ==========================================================  ======================
format             layout                                                      time step
=================  ==========================================================  ======================
``ONECOLUMN``      one value per line (``#``/``%`` comment lines allowed)      ``dt=`` (required)
``TWOCOLUMN``      time and value per line (blank or comma separated)          time column
``PERCENTHEADER``  ``%`` header lines, then several values per line; zero      header, else ``dt=``
                   padding of the last line is stripped
``PYSLAMMERCSV``   ``# Time Series: ...`` / ``# Time (s),Acceleration (g's)``  time column
                   then ``time,acc`` lines (the pyslammer sample motions)
=================  ==========================================================  ======================

``PYSLAMMERCSV`` is detected automatically, and so is ``PERCENTHEADER`` when its ``%`` header states
the time step (a ``%`` line with the sample count and the time step, e.g. ``%12321 0.004000 ...``, or
``... POINTS OF ACCEL DATA EQUALLY SPACED AT .020 SEC``); the others have no header to recognise and
are read by name with ``dt`` and ``units``.
"""

from __future__ import annotations

import re
from typing import Any

import numpy as np
from obspy import Stream

from isorock.errors import (
    EmptyRecordError,
    MissingTimeStepError,
    MissingUnitsError,
    NptsMismatchError,
    TruncatedRecordError,
)
from isorock.io._common import (
    GIVE_DT,
    GIVE_UNITS,
    TextLines,
    check_dt,
    check_given_dt,
    check_given_units,
    check_time_column,
    make_trace,
    normalize_units,
    parse_values,
    peek_lines,
    stem,
    stream,
)

__all__: list[str] = []

_COMMENT = ("#", "%")
_FLOAT = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[Ee][-+]?\d+)?"


# --------------------------------------------------------------------------- detection
def _is_one_column(filename: Any) -> bool:
    """Never claims a file: a list of numbers has nothing to recognise. Use ``format="ONECOLUMN"``."""
    return False


def _is_two_column(filename: Any) -> bool:
    """Never claims a file: use ``format="TWOCOLUMN"``."""
    return False


def _is_percent_header(filename: Any) -> bool:
    """True for a file that starts with ``%`` header lines stating the time step, then numbers.

    The header must state the time step in one of the forms the reader understands: a line with the
    sample count and the time step (``%12321 0.004000 ...``, the SAC/Somerville style, in the first
    three lines), ``N POINTS OF ACCEL DATA EQUALLY SPACED AT DT SEC`` or ``INTERVALS OF DT SEC``; and
    the first line after the header must hold numbers only. Other ``%`` files are read with
    ``format="PERCENTHEADER"`` and ``dt``. Never raises.
    """
    try:
        lines = peek_lines(filename, 16384, 120)
        if not lines or not lines[0].lstrip().startswith("%"):
            return False
        end, info = _percent_header(TextLines("", lines))
        if info["dt"] is None or end >= len(lines):
            return False
        toks = lines[end].replace(",", " ").split()
        return bool(toks) and all(re.fullmatch(_FLOAT, t) for t in toks)
    except Exception:
        return False


_PYSL_COLS = re.compile(r"time\s*\(\s*s\s*\)\s*,\s*acc", re.I)


def _is_pyslammer_csv(filename: Any) -> bool:
    """True for a pyslammer sample-motion CSV (``#`` header naming ``Time (s),Acceleration``).

    Never raises.
    """
    try:
        lines = peek_lines(filename, 2048, 10)
        if not lines or not lines[0].startswith("#"):
            return False
        i = 0
        named = False
        while i < len(lines) and lines[i].startswith("#"):
            named = named or bool(_PYSL_COLS.search(lines[i]))
            i += 1
        if not named or i >= len(lines):
            return False
        parts = lines[i].split(",")
        return len(parts) == 2 and all(re.fullmatch(rf"\s*{_FLOAT}\s*", p) for p in parts)
    except Exception:
        return False


# --------------------------------------------------------------------------- readers
def _read_one_column(
    filename: Any, dt: float | None = None, units: str | None = None, **kwargs: Any
) -> Stream:
    """Read one value per line.

    Parameters
    ----------
    filename : str or file-like
        The file.
    dt : float
        Time step [s] (required).
    units : str
        Units of the values (required): ``g``, ``m/s2``, ``cm/s2``.
    **kwargs
        Other ObsPy reader arguments (ignored).

    Returns
    -------
    obspy.Stream
        One trace in m/s^2 named after the file.
    """
    text = TextLines.read(filename)
    unit = normalize_units(units, text.path)
    dt = check_dt(text.path, dt)
    block = parse_values(text, 0, skip_prefixes=_COMMENT, ncols=1)
    if block.values.size == 0:
        raise text.error(EmptyRecordError, "no data values")
    return stream(
        make_trace(
            text,
            block.values,
            dt=dt,
            units=unit,
            fmt="one-column",
            station=stem(text.path),
            meta={"dt_source": "given", "units_source": "given"},
            lines=block.line_of,
        )
    )


def _read_time_value(
    text: TextLines,
    fmt: str,
    dt: float | None,
    unit: str,
    *,
    station: str,
    channel: str = "",
    meta: dict | None = None,
) -> Stream:
    block = parse_values(text, 0, commas=True, skip_prefixes=_COMMENT, ncols=2)
    if block.values.size == 0:
        raise text.error(EmptyRecordError, "no data values")
    table = block.values.reshape(-1, 2)
    rows_line = block.line_of[::2]
    step = check_time_column(text, table[:, 0], rows_line)
    check_given_dt(text.path, dt, step, "time column")
    info = {"dt_source": "time column", "units_source": "given", "t0": float(table[0, 0])}
    info.update(meta or {})
    return stream(
        make_trace(
            text,
            table[:, 1],
            dt=step,
            units=unit,
            fmt=fmt,
            station=station,
            channel=channel,
            meta=info,
            lines=rows_line,
        )
    )


def _read_two_column(
    filename: Any, dt: float | None = None, units: str | None = None, **kwargs: Any
) -> Stream:
    """Read time [s] and acceleration per line; the time column must be uniform.

    Parameters
    ----------
    filename : str or file-like
        The file.
    dt : float, optional
        Time step [s]; checked against the time column if given.
    units : str
        Units of the values (required).
    **kwargs
        Other ObsPy reader arguments (ignored).

    Returns
    -------
    obspy.Stream
        One trace in m/s^2; ``stats.isorock.t0`` is the first time [s].
    """
    text = TextLines.read(filename)
    unit = normalize_units(units, text.path)
    return _read_time_value(text, "two-column", dt, unit, station=stem(text.path))


_PH_POINTS = re.compile(rf"(\d+)\s+POINTS\s+OF\s+ACC\w*\s+DATA.*?SPACED\s+AT\s+({_FLOAT})\s*SEC", re.I)
_PH_INTERVAL = re.compile(rf"INTERVALS\s+OF\s+({_FLOAT})\s*SEC", re.I)
_PH_UNITS = re.compile(r"\(\s*UNITS\s*:\s*([A-Za-z/^0-9*]+)\s*\)", re.I)
# "2990 5.00000E-03 0 0 0. ..." or "12321 0.004000 ..." (the count and the step, then anything)
_PH_NPTS_DT = re.compile(rf"^\s*(\d+)\s+({_FLOAT})(?:\s+.*)?$")


def _percent_header(text: TextLines) -> tuple[int, dict]:
    """Index of the first data line and what the leading ``%`` lines state."""
    end = 0
    while end < len(text.lines) and (not text.lines[end].strip() or text.lines[end].lstrip().startswith("%")):
        end += 1
    info: dict = {"npts": None, "dt": None, "units": None, "line": None, "units_line": None}
    hdr_lines = [(i, text.lines[i].lstrip()[1:] if text.lines[i].lstrip() else "") for i in range(end)]
    for i, s in hdr_lines:
        m = _PH_POINTS.search(s)
        if m:
            info.update(npts=int(m.group(1)), dt=float(m.group(2)), line=i + 1)
        elif info["dt"] is None:
            m = _PH_INTERVAL.search(s)
            if m:
                info.update(dt=float(m.group(1)), line=i + 1)
        m = _PH_UNITS.search(s)
        if m and info["units"] is None:
            info.update(units=m.group(1), units_line=i + 1)
    if info["dt"] is None:  # "%   2990    5.00000E-03  0  0  0. ..." near the top (SAC/Somerville style)
        for i, s in hdr_lines[:3]:
            m = _PH_NPTS_DT.match(s)
            if m and ("." in m.group(2) or "e" in m.group(2).lower()) and 0 < float(m.group(2)) < 1:
                info.update(npts=int(m.group(1)), dt=float(m.group(2)), line=i + 1)
                break
    return end, info


def _read_percent_header(
    filename: Any, dt: float | None = None, units: str | None = None, **kwargs: Any
) -> Stream:
    """Read a file with ``%`` header lines and several values per line.

    Trailing zeros on the last data line are row padding and are stripped; when the header declares
    the number of points, the values past it must be zeros (padding) and fewer values is an error.
    ``%`` lines after the data start (commented-out samples) are skipped.

    Parameters
    ----------
    filename : str or file-like
        The file.
    dt : float, optional
        Time step [s]; required when the header does not state it, else checked against it.
    units : str, optional
        Units of the values; required unless the header says ``(UNITS: ...)``, else checked.
    **kwargs
        Other ObsPy reader arguments (ignored).

    Returns
    -------
    obspy.Stream
        One trace in m/s^2; ``stats.isorock.padding`` is the number of stripped zeros.
    """
    text = TextLines.read(filename)
    end, hdr = _percent_header(text)
    if hdr["units"] is not None:
        unit = normalize_units(hdr["units"], text.path, hdr["units_line"])
        check_given_units(text.path, units, unit, hdr["units_line"])
    else:
        if units is None:
            raise text.error(MissingUnitsError, f"units not stated in the header: {GIVE_UNITS}")
        unit = normalize_units(units, text.path)
    if hdr["dt"] is not None:
        step = check_dt(text.path, hdr["dt"], hdr["line"])
        check_given_dt(text.path, dt, step, f"header (line {hdr['line']})", hdr["line"])
        dt_source = "header"
    else:
        if dt is None:
            raise text.error(
                MissingTimeStepError, f"time step not given and the header states none: {GIVE_DT}"
            )
        step = check_dt(text.path, dt)
        dt_source = "given"
    block = parse_values(text, end, skip_prefixes=_COMMENT)
    vals = block.values
    if vals.size == 0:
        raise text.error(EmptyRecordError, "no data values after the header", end or None)
    npts = hdr["npts"]
    if npts is not None:
        if vals.size < npts:
            raise text.error(
                TruncatedRecordError,
                f"file ends after {vals.size} of the {npts} values the header declares (line {hdr['line']})",
                block.last_line,
            )
        extra = vals[npts:]
        if np.any(extra != 0):
            k = npts + int(np.flatnonzero(extra != 0)[0])
            raise text.error(
                NptsMismatchError,
                f"more values than the {npts} the header declares (line {hdr['line']}); "
                f"value {k + 1} is not zero padding",
                int(block.line_of[k]),
            )
        padding = int(extra.size)
        vals = vals[:npts]
    else:
        last_line, nlast = block.per_line[-1]
        tail = vals[vals.size - nlast :]
        nz = np.flatnonzero(tail != 0)
        padding = nlast - (int(nz[-1]) + 1 if nz.size else 0)
        vals = vals[: vals.size - padding]
    header = [text.lines[i].rstrip() for i in range(end)]
    event = next((h.lstrip("% ").strip() for h in header if re.search(r"[A-Za-z]{3}", h)), "")
    meta = {
        "event": event,
        "header": header,
        "dt_source": dt_source,
        "units_source": "given" if hdr["units"] is None else "header",
        "npts_declared": npts,
        "padding": padding,
    }
    return stream(
        make_trace(
            text,
            vals,
            dt=step,
            units=unit,
            fmt="percent-header",
            station=stem(text.path),
            meta=meta,
            line=hdr["units_line"],
            lines=block.line_of[: vals.size],
        )
    )


_PYSL_TITLE = re.compile(r"Time\s+Series\s*:\s*(.*?)\s+-\s+(\S+?)[\s,]*$", re.I)
_PYSL_UNITS = re.compile(r"acc\w*\s*\(([^)]*)\)", re.I)


def _read_pyslammer_csv(
    filename: Any, dt: float | None = None, units: str | None = None, **kwargs: Any
) -> Stream:
    """Read a pyslammer sample ground motion (``#`` header, then ``time,acceleration`` in g).

    Parameters
    ----------
    filename : str or file-like
        The file.
    dt : float, optional
        Time step [s]; checked against the time column if given.
    units : str, optional
        Units; the header states them (``Acceleration (g's)``), a given value is checked.
    **kwargs
        Other ObsPy reader arguments (ignored).

    Returns
    -------
    obspy.Stream
        One trace in m/s^2; station and channel from the ``Time Series`` line (``BCR-230`` gives
        station ``BCR``, channel ``230``).
    """
    text = TextLines.read(filename)
    header = [ln for ln in text.lines[:10] if ln.startswith("#")]
    unit = None
    event, record = "", stem(text.path).rsplit("_", 1)[-1]
    for i, ln in enumerate(header):
        m = _PYSL_UNITS.search(ln)
        if m and unit is None:
            unit = normalize_units(m.group(1), text.path, i + 1)
            check_given_units(text.path, units, unit, i + 1)
        m = _PYSL_TITLE.search(ln)
        if m:
            event, record = m.group(1).strip(), m.group(2).strip()
    units_source = "header"
    if unit is None:
        unit = normalize_units(units if units is not None else None, text.path)
        units_source = "given"
    station, _, channel = record.rpartition("-")
    if not station:
        station, channel = record, ""
    meta = {
        "event": event,
        "header": [h.rstrip() for h in header],
        "record": record,
        "units_source": units_source,
    }
    return _read_time_value(text, "pyslammer-csv", dt, unit, station=station, channel=channel, meta=meta)
