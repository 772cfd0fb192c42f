"""SCEC Broadband Platform (BBP) time histories: comment header, then time and three components.

The header lines start with ``#`` or ``%``; one of them names the columns and their units::

    #    time(sec)      N-S(cm/s/s)      E-W(cm/s/s)      U-D(cm/s/s)
    0.000000e+00   -2.593600e+00    3.454229e-01   -2.593600e+00

Variants name the columns ``NS EW UP`` and write the units as ``units= cm/s/s`` or on a
``NPTS, DT:`` line; the observed records of the BBP validation data describe one column per header
line (tab-separated data)::

    # Column 1: Time (s)
    # Column 2: North-south acceleration (cm/s/s) (+ is northward)
    # Column 3: East-west acceleration (cm/s/s) (+ is eastward)
    # Column 4: Up-down acceleration (cm/s/s) (+ is upward)
 Each component becomes one trace whose channel is ``N-S``, ``E-W`` or ``U-D``;
the time step comes from the time column. ObsPy format name: ``BBP`` (detected automatically).
"""

from __future__ import annotations

import re
from typing import Any

import numpy as np
from obspy import Stream, Trace

from isorock.errors import (
    ColumnCountError,
    EmptyRecordError,
    HeaderError,
    MissingUnitsError,
    NptsMismatchError,
    TruncatedRecordError,
    UnitsError,
)
from isorock.io._common import (
    GIVE_UNITS,
    TextLines,
    check_given_dt,
    check_given_units,
    check_time_column,
    make_trace,
    normalize_units,
    parse_values,
    peek_lines,
    stem,
)

__all__: list[str] = []

_COMMENT = ("#", "%")
_COL = re.compile(r"([A-Za-z][A-Za-z/\-]*)\s*\(([^)]*)\)")
_UNITS_LINE = re.compile(r"\bunits\s*[=:]\s*([A-Za-z][A-Za-z/^*0-9]*)", re.I)
_NPTS_DT = re.compile(r"NPTS\s*,\s*DT\s*:?\s*(\d+)\s+([-+]?[\d.]+(?:[Ee][-+]?\d+)?)", re.I)
_STATION = re.compile(r"\b(?:station|site|sta)\s*[=:]\s*(\S+)", re.I)
_COMPONENTS = {
    "N-S": "N-S", "NS": "N-S", "N/S": "N-S", "N": "N-S",
    "E-W": "E-W", "EW": "E-W", "E/W": "E-W", "E": "E-W",
    "U-D": "U-D", "UD": "U-D", "U/D": "U-D", "UP": "U-D", "Z": "U-D", "VER": "U-D",
}  # fmt: skip
_DEFAULT_CHANNELS = ("N-S", "E-W", "U-D")
# "Column 2: North-south acceleration (cm/s/s) (+ is northward)"
_COLUMN_LINE = re.compile(r"^column\s+(\d+)\s*:\s*([^()]*?)\s*(?:\(([^)+][^)]*)\))?\s*(?:\(.*)?$", re.I)
_WORDS = (
    (re.compile(r"\b(north[-\s]?south|n-s|ns|n/s)\b", re.I), "N-S"),
    (re.compile(r"\b(east[-\s]?west|e-w|ew|e/w)\b", re.I), "E-W"),
    (re.compile(r"\b(up[-\s]?down|u-d|ud|vertical)\b", re.I), "U-D"),
)
_HORIZONTAL = re.compile(r"\b(N-S|NS|N/S|E-W|EW|E/W|NORTH[-\s]?SOUTH|EAST[-\s]?WEST)\b")


def _component_of(description: str) -> str | None:
    """``N-S``, ``E-W`` or ``U-D`` from a column description such as ``North-south acceleration``."""
    for pattern, name in _WORDS:
        if pattern.search(description):
            return name
    return None


def _header_end(lines: list[str]) -> int:
    i = 0
    while i < len(lines) and (not lines[i].strip() or lines[i].lstrip().startswith(_COMMENT)):
        i += 1
    return i


def _is_bbp(filename: Any) -> bool:
    """True if the file looks like a BBP time history. Never raises.

    The file must start with comment lines (``#`` or ``%``), one of which names a time column and a
    horizontal component (``N-S``, ``NS``, ``N/S`` ...), and its first data line must hold 4 numbers.
    """
    try:
        lines = peek_lines(filename, 8192, 60)
        if not lines or not lines[0].lstrip().startswith(_COMMENT):
            return False
        end = _header_end(lines)
        if end >= len(lines):
            return False
        header = " ".join(lines[:end]).upper()
        if "TIME" not in header or not _HORIZONTAL.search(header):
            return False
        toks = lines[end].split()
        if len(toks) != 4:
            return False
        [float(t) for t in toks]
        return True
    except Exception:
        return False


def _columns(text: TextLines, end: int) -> tuple[list[str], str | None, int | None]:
    """Channel names of the 3 data columns, the units stated in the header, and the line stating them."""
    names: list[str] = list(_DEFAULT_CHANNELS)
    units: str | None = None
    uline: int | None = None
    described: dict[int, tuple[str, str, int]] = {}  # "Column N: ..." lines: N -> (name, units, line)
    for i in range(end):
        s = text.lines[i].lstrip("#% \t")
        m = _COLUMN_LINE.match(s)
        if m:
            described[int(m.group(1))] = (m.group(2), (m.group(3) or "").strip(), i + 1)
            continue
        cols = _COL.findall(s)
        if len(cols) >= 2 and cols[0][0].lower().startswith("time"):
            data_cols = cols[1:]
            if len(data_cols) != 3:
                raise text.error(HeaderError, f"{len(data_cols)} data columns named; BBP has 3", i + 1)
            found = []
            for name, unit in data_cols:
                key = name.upper().strip("-")
                if key not in _COMPONENTS:
                    raise text.error(HeaderError, f"unknown component column {name!r}", i + 1)
                found.append(_COMPONENTS[key])
                if units is None:
                    units, uline = unit.strip(), i + 1
                elif unit.strip().lower() != units.lower():
                    raise text.error(UnitsError, f"columns in different units ({units}, {unit})", i + 1)
            names = found
        m = _UNITS_LINE.search(s)
        if m and units is None:
            units, uline = m.group(1), i + 1
        if re.search(r"ground\s+velocity|ground\s+displacement", s, re.I):
            raise text.error(UnitsError, "holds velocity or displacement, not acceleration", i + 1)
    if described:
        names, units, uline = _described_columns(text, described, units, uline)
    return names, units, uline


def _described_columns(
    text: TextLines, described: dict[int, tuple[str, str, int]], units: str | None, uline: int | None
) -> tuple[list[str], str | None, int | None]:
    """Channel names and units of the columns 2-4 described one per header line."""
    names = []
    for k in (2, 3, 4):
        if k not in described:
            raise text.error(HeaderError, f"the header describes columns {sorted(described)}; BBP has 1-4", 1)
        desc, unit, line = described[k]
        if re.search(r"\b(velocity|displacement)\b", desc, re.I):
            raise text.error(UnitsError, f"column {k} holds {desc.strip()!r}, not acceleration", line)
        name = _component_of(desc)
        if name is None:
            raise text.error(HeaderError, f"column {k}: cannot tell the component of {desc.strip()!r}", line)
        names.append(name)
        if not unit:
            continue
        if units is None:
            units, uline = unit, line
        elif unit.lower() != units.lower():
            raise text.error(UnitsError, f"columns in different units ({units}, {unit})", line)
    return names, units, uline


def _read_bbp(filename: Any, dt: float | None = None, units: str | None = None, **kwargs: Any) -> Stream:
    """Read a BBP file: one trace per component column, in m/s^2.

    Parameters
    ----------
    filename : str or file-like
        The file.
    dt : float, optional
        Time step [s]; if given it must agree with the time column.
    units : str, optional
        Units of the values; required only when the header does not state them, else checked.
    **kwargs
        Other ObsPy reader arguments (ignored).

    Returns
    -------
    obspy.Stream
        Three traces, channels ``N-S``, ``E-W``, ``U-D``. A component that repeats an earlier one
        sample for sample has ``stats.isorock.duplicate_of`` set to that component.
    """
    text = TextLines.read(filename)
    end = _header_end(text.lines)
    names, hdr_units, uline = _columns(text, end)
    if hdr_units is None:
        if units is None:
            raise text.error(MissingUnitsError, f"units not stated in the header: {GIVE_UNITS}", 1)
        unit = normalize_units(units, text.path)
    else:
        unit = normalize_units(hdr_units, text.path, uline)
        check_given_units(text.path, units, unit, uline)
    block = parse_values(text, end, skip_prefixes=_COMMENT, ncols=4)
    if block.values.size == 0:
        raise text.error(EmptyRecordError, "no data lines after the header", end or None)
    table = block.values.reshape(-1, 4)
    rows_line = block.line_of[::4]
    step = check_time_column(text, table[:, 0], rows_line)
    check_given_dt(text.path, dt, step, "time column")
    header = [ln.rstrip() for ln in text.lines[:end]]
    station = ""
    npts_decl = None
    for i, ln in enumerate(header):
        m = _STATION.search(ln)
        if m and not station:
            station = m.group(1)
        m = _NPTS_DT.search(ln)
        if m:
            npts_decl = int(m.group(1))
            check_given_dt(text.path, float(m.group(2)), step, "time column", i + 1)
    if npts_decl is not None and npts_decl != table.shape[0]:
        cls = TruncatedRecordError if table.shape[0] < npts_decl else NptsMismatchError
        raise text.error(
            cls, f"{table.shape[0]} data lines but the header declares NPTS={npts_decl}", int(rows_line[-1])
        )
    if len(set(names)) != 3:
        raise text.error(ColumnCountError, f"component columns repeat: {names}", uline)
    event = " ".join(h.lstrip("#% ").strip() for h in header if not _COL.search(h) and h.strip("#% -"))
    if not np.any(table[:, 1:]):
        raise text.error(UnitsError, "all values are zero", end + 1)
    traces: list[Trace] = []
    for k, name in enumerate(names):
        meta = {
            "event": event,
            "header": header,
            "dt_source": "time column",
            "units_source": "given" if hdr_units is None else "header",
            "column": k + 2,
            "npts_declared": npts_decl,
        }
        tr = make_trace(
            text,
            table[:, k + 1],
            dt=step,
            units=unit,
            fmt="bbp",
            station=station or stem(text.path),
            channel=name,
            meta=meta,
            line=uline,
            lines=rows_line,
            allow_zero=True,
        )
        for prev in traces:
            if np.array_equal(prev.data, tr.data):
                tr.stats.isorock.duplicate_of = prev.stats.channel
                break
        traces.append(tr)
    return Stream(traces=traces)
