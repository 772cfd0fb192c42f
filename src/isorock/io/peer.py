"""PEER strong-motion time series: AT2 files with their 4 header lines, and AT2 bodies without them.

Three header variants are read (line 4 gives the number of points and the time step)::

    PEER NGA STRONG MOTION DATABASE RECORD                          (NGA-West2)
    San Fernando, 2/9/1971, Pacoima Dam (upper left abut), 164
    ACCELERATION TIME SERIES IN UNITS OF G
    NPTS=   4172, DT=   .0100 SEC,

    PACIFIC ENGINEERING AND ANALYSIS STRONG-MOTION DATA             (PE&A)
    IMPERIAL VALLEY 10/15/79 2316, El Centro Array #4, 140
    ACCELERATION TIME HISTORY IN UNITS OF G,  PGA=   .48431 G, PGV=   39.6246 CM/SEC, PGD=   25.1238 CM
    NPTS=   7818, DT=   .0050 SEC,   0 POLE @    40.00000 HZ, ...

    PEER NGA STRONG MOTION DATABASE RECORD                          (NGA 2005)
    NORTHRIDGE, 1/17/94 12:31, RINALDI RECEIVING STA, 228
    ACCELERATION TIME HISTORY IN UNITS OF G
    1991    0.0100    NPTS, DT

then the values, several per line. ObsPy format names: ``PEERAT2`` (detected automatically) and
``PEERAT2BODY`` (the data lines alone; read only by name, with ``dt`` and ``units``).
"""

from __future__ import annotations

import re
from typing import Any

from obspy import Stream

from isorock.errors import (
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
    check_dt,
    check_given_dt,
    check_given_units,
    make_trace,
    normalize_units,
    parse_values,
    peek_lines,
    stem,
    stream,
)

__all__: list[str] = []

_FLOAT = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[EeDd][-+]?\d+)?"
_NPTS_DT = re.compile(rf"NPTS\s*=\s*(\d+)\s*,?\s*DT\s*=\s*({_FLOAT})", re.I)
_NPTS_DT_2005 = re.compile(rf"^\s*(\d+)\s+({_FLOAT})\s+NPTS\s*,?\s*DT\b", re.I)
_NPTS_ONLY = re.compile(r"NPTS\s*=\s*(\d+)", re.I)
_UNITS = re.compile(r"UNITS\s+OF\s+([A-Za-z][A-Za-z/^*0-9']*)", re.I)
_KIND = re.compile(r"\b(ACCELERATION|VELOCITY|DISPLACEMENT)\b", re.I)
_HDR_PGA = re.compile(rf"PGA\s*=\s*({_FLOAT})\s*G\b", re.I)

# header PGA (PE&A variant) and data PGA may differ by this much before the file is refused
_HDR_PGA_RTOL = 0.05


def _is_peer_at2(filename: Any) -> bool:
    """True if the file looks like a PEER AT2 file (4 header lines, NPTS on line 4). Never raises.

    Parameters
    ----------
    filename : str or file-like
        The file.
    """
    try:
        lines = peek_lines(filename, 2048, 5)
        if not lines or len(lines) < 4:
            return False
        line3, line4 = lines[2].upper(), lines[3].upper()
        if "UNITS" not in line3 and "TIME SERIES" not in line3 and "TIME HISTORY" not in line3:
            return False
        return "NPTS" in line4
    except Exception:
        return False


def _is_peer_at2_body(filename: Any) -> bool:
    """Never claims a file: an AT2 body has no header to recognise. Read it with ``format="PEERAT2BODY"``."""
    return False


def _parse_npts_dt(text: TextLines) -> tuple[int, float]:
    line4 = text.lines[3]
    m = _NPTS_DT.search(line4) or _NPTS_DT_2005.search(line4)
    if m is None:
        if _NPTS_ONLY.search(line4):
            raise text.error(HeaderError, f"no DT on the NPTS line: {line4.strip()!r}", 4)
        raise text.error(HeaderError, f"cannot find NPTS and DT on line 4: {line4.strip()!r}", 4)
    npts = int(m.group(1))
    dt = check_dt(text.path, float(m.group(2).upper().replace("D", "E")), 4)
    return npts, dt


def _parse_units(text: TextLines, given: str | None) -> tuple[str, str]:
    """Units of the values and where they come from (``"header"`` or ``"given"``)."""
    line3 = text.lines[2]
    kind = _KIND.search(line3)
    if kind and kind.group(1).upper() != "ACCELERATION":
        raise text.error(UnitsError, f"holds {kind.group(1).lower()}, not acceleration", 3)
    m = _UNITS.search(line3)
    if m is None:
        if given is None:
            raise text.error(MissingUnitsError, f"units not stated on line 3: {GIVE_UNITS}", 3)
        return normalize_units(given, text.path), "given"
    units = normalize_units(m.group(1).rstrip(",."), text.path, 3)
    check_given_units(text.path, given, units, 3)
    return units, "header"


def _split_line2(line: str) -> tuple[str, str, str]:
    """(event text, station, component) from the second header line."""
    parts = [p.strip() for p in line.split(",")]
    parts = [p for p in parts if p]
    if len(parts) >= 3:
        return ", ".join(parts[:-2]), parts[-2], parts[-1]
    if len(parts) == 2:
        return parts[0], parts[1], ""
    return line.strip(), "", ""


def _read_peer_at2(filename: Any, dt: float | None = None, units: str | None = None, **kwargs: Any) -> Stream:
    """Read a PEER AT2 file (any of the three header variants).

    Parameters
    ----------
    filename : str or file-like
        The file.
    dt : float, optional
        Time step [s]; if given it must agree with the header.
    units : str, optional
        Units; if given they must agree with the header.
    **kwargs
        Other ObsPy reader arguments (ignored).

    Returns
    -------
    obspy.Stream
        One trace in m/s^2.

    Raises
    ------
    RecordError
        Header, count, value, time step or units problems, naming the line.
    """
    text = TextLines.read(filename)
    if len(text.lines) < 4:
        raise text.error(
            HeaderError,
            f"an AT2 file has 4 header lines; this file has {len(text.lines)} lines",
            len(text.lines),
        )
    npts, dt_hdr = _parse_npts_dt(text)
    check_given_dt(text.path, dt, dt_hdr, "header (line 4)", 4)
    unit, units_source = _parse_units(text, units)
    block = parse_values(text, 4)
    n = block.values.size
    if npts == 0:
        raise text.error(EmptyRecordError, "header declares NPTS=0", 4)
    if n == 0:
        raise text.error(EmptyRecordError, f"no data values after the header (NPTS={npts})", 4)
    if n < npts:
        raise text.error(
            TruncatedRecordError,
            f"file ends after {n} of the NPTS={npts} values declared on line 4 (truncated file?)",
            block.last_line,
        )
    if n > npts:
        raise text.error(
            NptsMismatchError,
            f"{n} data values but line 4 declares NPTS={npts}; value {npts + 1} is here",
            int(block.line_of[npts]),
        )
    event, station, channel = _split_line2(text.lines[1])
    meta = {
        "event": event,
        "title": text.lines[0].strip(),
        "header": [ln.rstrip() for ln in text.lines[:4]],
        "npts_declared": npts,
        "dt_source": "header",
        "units_source": units_source,
    }
    m = _HDR_PGA.search(text.lines[2])
    tr = make_trace(
        text,
        block.values,
        dt=dt_hdr,
        units=unit,
        fmt="peer-at2",
        station=station,
        channel=channel,
        meta=meta,
        line=3,
        lines=block.line_of,
    )
    if m:
        hdr_pga = float(m.group(1))
        tr.stats.isorock.header_pga_g = hdr_pga
        if unit == "g" and hdr_pga > 0:
            got = float(abs(block.values).max())
            if abs(got - hdr_pga) > _HDR_PGA_RTOL * hdr_pga:
                raise text.error(
                    HeaderError, f"header says PGA={hdr_pga:g} g but the data peak at {got:.5g} g", 3
                )
    return stream(tr)


def _read_peer_at2_body(
    filename: Any, dt: float | None = None, units: str | None = None, npts: int | None = None, **kwargs: Any
) -> Stream:
    """Read the data lines of an AT2 file without its header (several values per line).

    Parameters
    ----------
    filename : str or file-like
        The file.
    dt : float
        Time step [s] (required: the file does not state it).
    units : str
        Units of the values (required), usually ``"g"``.
    npts : int, optional
        Expected number of values; checked if given.
    **kwargs
        Other ObsPy reader arguments (ignored).

    Returns
    -------
    obspy.Stream
        One trace in m/s^2; its station is the file name.
    """
    text = TextLines.read(filename)
    unit = normalize_units(units, text.path)
    dt = check_dt(text.path, dt)
    block = parse_values(text, 0)
    n = block.values.size
    if n == 0:
        raise text.error(EmptyRecordError, "no data values")
    if npts is not None and n != int(npts):
        cls = TruncatedRecordError if n < int(npts) else NptsMismatchError
        raise text.error(cls, f"{n} data values but npts={npts} expected", block.last_line)
    meta = {"dt_source": "given", "units_source": "given", "npts_declared": None}
    return stream(
        make_trace(
            text,
            block.values,
            dt=dt,
            units=unit,
            fmt="peer-at2-body",
            station=stem(text.path),
            meta=meta,
            lines=block.line_of,
        )
    )
