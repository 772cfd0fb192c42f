"""Shared pieces of the record readers: text access, numeric parsing, units, checks, traces.

Every problem with a record file is raised as a subclass of :class:`isorock.errors.RecordError`
(all defined in :mod:`isorock.errors`) whose message names the file, the 1-based line (where the
problem sits on one line) and the problem.
"""

from __future__ import annotations

import math
import re
import unicodedata
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from obspy import Stream, Trace
from obspy.core.util import AttribDict

from isorock.constants import UNIT_FACTORS, G
from isorock.errors import (
    BinaryFileError,
    ColumnCountError,
    EmptyRecordError,
    MissingTimeStepError,
    MissingUnitsError,
    NonFiniteError,
    NonNumericError,
    RecordError,
    TimeStepError,
    UnitsError,
)

__all__ = [
    "Limits",
    "LIMITS",
    "GIVE_UNITS",
    "GIVE_DT",
    "TextLines",
    "DataBlock",
    "normalize_units",
    "unit_factor",
    "parse_values",
    "make_trace",
    "check_dt",
    "check_time_column",
    "source_name",
    "seed_code",
    "trace_station",
    "trace_component",
]


# --------------------------------------------------------------------------- limits
@dataclass(frozen=True)
class Limits:
    """Plausibility limits applied to every record that is read.

    Parameters
    ----------
    max_pga_g : float
        Largest credible peak ground acceleration [g]; a larger value almost always means
        wrong units (a file in cm/s^2 read as g).
    min_dt : float
        Smallest accepted time step [s].
    max_dt : float
        Largest accepted time step [s].
    min_npts : int
        Fewest samples of a record [-].
    """

    max_pga_g: float = 10.0
    min_dt: float = 1e-4
    max_dt: float = 0.2
    min_npts: int = 2


LIMITS = Limits()


# --------------------------------------------------------------------------- units
#: advice appended to "units not given" / "time step not given" messages
GIVE_UNITS = "give them (units= or --units: g, m/s2, cm/s2)"
GIVE_DT = "give it (dt= or --dt, in s)"
_ALIASES = {
    "g": "g",
    "g's": "g",
    "gs": "g",
    "m/s2": "m/s2",
    "m/s^2": "m/s2",
    "m/s**2": "m/s2",
    "m/s/s": "m/s2",
    "m/sec2": "m/s2",
    "m/sec^2": "m/s2",
    "m/sec/sec": "m/s2",
    "cm/s2": "cm/s2",
    "cm/s^2": "cm/s2",
    "cm/s**2": "cm/s2",
    "cm/s/s": "cm/s2",
    "cm/sec2": "cm/s2",
    "cm/sec^2": "cm/s2",
    "cm/sec/sec": "cm/s2",
    "cms/sec/sec": "cm/s2",
    "gal": "cm/s2",
    "mm/s2": "mm/s2",
    "mm/s^2": "mm/s2",
    "mm/s/s": "mm/s2",
}
_VELOCITY = {"cm/s", "cm/sec", "m/s", "m/sec", "mm/s", "in/s", "in/sec", "cms/sec"}
_DISPLACEMENT = {"cm", "m", "mm", "in", "cms"}


def normalize_units(units: str | None, path: object = "", line: int | None = None) -> str:
    """Canonical name of an acceleration unit.

    Parameters
    ----------
    units : str
        A unit as written in a header or given by a user: ``"g"``, ``"CM/SEC/SEC"``, ``"gal"``,
        ``"m/s^2"`` ...
    path, line
        Where the unit comes from, for the error message.

    Returns
    -------
    str
        One of ``"g"``, ``"m/s2"``, ``"cm/s2"``, ``"mm/s2"``.

    Raises
    ------
    UnitsError
        Missing, unknown, or a velocity/displacement unit.
    """
    if units is None or not str(units).strip():
        raise MissingUnitsError(path, f"units not given: {GIVE_UNITS}", line)
    key = re.sub(r"\s+", "", str(units)).lower()
    if key in _ALIASES:
        return _ALIASES[key]
    if key in _VELOCITY:
        raise UnitsError(path, f"units {units!r} are a velocity, not an acceleration", line)
    if key in _DISPLACEMENT:
        raise UnitsError(path, f"units {units!r} are a displacement, not an acceleration", line)
    raise UnitsError(path, f"unknown units {units!r}: valid g, m/s2, cm/s2 (or gal, cm/s/s, m/s^2)", line)


def unit_factor(units: str) -> float:
    """Factor from a canonical unit (see :func:`normalize_units`) to m/s^2 [m/s^2 per unit]."""
    return UNIT_FACTORS[units]


# --------------------------------------------------------------------------- text access
def source_name(src: Any) -> str:
    """Name of a file or file-like object for messages."""
    if isinstance(src, (str, Path)):
        return str(src)
    return str(getattr(src, "name", "<stream>"))


def _read_bytes(src: Any, limit: int | None = None) -> bytes:
    """Bytes of a path or of a file-like object (its position is restored)."""
    if hasattr(src, "read"):
        pos = src.tell() if hasattr(src, "tell") else None
        data = src.read() if limit is None else src.read(limit)
        if pos is not None and hasattr(src, "seek"):
            src.seek(pos)
        if isinstance(data, str):
            data = data.encode("utf-8", "replace")
        return data
    with open(src, "rb") as fh:
        return fh.read() if limit is None else fh.read(limit)


def _decode(raw: bytes) -> str | None:
    """Text of ``raw``, or None when it does not look like text."""
    if b"\x00" in raw:
        return None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    if text.startswith("\ufeff"):  # UTF-8 byte-order mark
        text = text[1:]
    sample = text[:65536]
    if sample:
        bad = sum(1 for ch in sample if unicodedata.category(ch) == "Cc" and ch not in "\t\n\r\x0b\x0c\x1a")
        if bad > max(2, len(sample) // 1000):
            return None
    return text


def peek_lines(src: Any, nbytes: int = 4096, nlines: int = 8) -> list[str] | None:
    """First lines of a file for format detection; None when unreadable or not text. Never raises."""
    try:
        raw = _read_bytes(src, nbytes)
        text = _decode(raw)
        if text is None:
            return None
        lines = text.splitlines()
        if len(raw) >= nbytes and lines:  # last line may be cut
            lines = lines[:-1]
        return lines[:nlines]
    except Exception:
        return None


@dataclass
class TextLines:
    """The lines of a text record file.

    Parameters
    ----------
    path : str
        File name (for messages).
    lines : list of str
        Lines without line ends; ``lines[i]`` is line ``i + 1``.
    """

    path: str
    lines: list[str]

    @classmethod
    def read(cls, src: Any) -> TextLines:
        """Read a path or file-like object.

        Raises
        ------
        RecordError
            The file does not exist or cannot be read.
        EmptyRecordError
            The file is empty.
        BinaryFileError
            The file is not text.
        """
        name = source_name(src)
        try:
            raw = _read_bytes(src)
        except FileNotFoundError:
            raise RecordError(name, "no such file") from None
        except IsADirectoryError:
            raise RecordError(name, "is a directory, not a record file") from None
        except OSError as exc:
            raise RecordError(name, f"cannot read file: {exc.strerror or exc}") from None
        if not raw.strip():
            raise EmptyRecordError(name, "file is empty")
        text = _decode(raw)
        if text is None:
            raise BinaryFileError(name, "binary data, not a text record file")
        return cls(name, text.splitlines())

    def error(self, cls: type[RecordError], problem: str, line: int | None = None) -> RecordError:
        """An error of class ``cls`` about this file."""
        return cls(self.path, problem, line)


# --------------------------------------------------------------------------- numbers
_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[EeDd][-+]?\d+)?"
# Fortran E-format numbers that touch when a negative value fills its field: "-.1E-01-.2E-01"
_EXP_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)[EeDd][-+]?\d+"
_FUSED = re.compile(rf"{_EXP_NUM}(?:[-+](?:\d+\.?\d*|\.\d+)[EeDd][-+]?\d+)+")
_ONE_NUM = re.compile(_EXP_NUM)


@dataclass
class DataBlock:
    """Numeric values read from data lines.

    Parameters
    ----------
    values : numpy.ndarray
        All values in file order (flattened).
    line_of : numpy.ndarray
        1-based line number of each value.
    per_line : list of tuple
        ``(line number, number of values)`` for each data line.
    """

    values: np.ndarray
    line_of: np.ndarray
    per_line: list[tuple[int, int]] = field(default_factory=list)

    @property
    def last_line(self) -> int | None:
        return self.per_line[-1][0] if self.per_line else None


def _split(line: str, commas: bool) -> list[str]:
    return line.replace(",", " ").split() if commas else line.split()


def parse_values(
    text: TextLines,
    start: int = 0,
    *,
    commas: bool = False,
    skip_prefixes: tuple[str, ...] = (),
    ncols: int | None = None,
) -> DataBlock:
    """Parse the numbers on lines ``start ..`` (0-based index) of a text file.

    Parameters
    ----------
    text : TextLines
        The file.
    start : int
        Index of the first data line.
    commas : bool
        Commas separate values as well as blanks.
    skip_prefixes : tuple of str
        Lines starting with one of these (after leading blanks) are comments.
    ncols : int, optional
        Every data line must hold exactly this many values.

    Raises
    ------
    NonNumericError, NonFiniteError, HeaderError
        With the line of the first offending token.
    """
    tokens: list[str] = []
    per_line: list[tuple[int, int]] = []
    for idx in range(start, len(text.lines)):
        s = text.lines[idx].strip()
        if not s or (skip_prefixes and s.startswith(skip_prefixes)):
            continue
        toks = _split(s, commas)
        if ncols is not None and len(toks) != ncols:
            fixed = _unfuse(toks)
            if fixed is None or len(fixed) != ncols:
                cols = f"{ncols} columns are" if ncols > 1 else "1 column is"
                raise text.error(
                    ColumnCountError, f"{len(toks)} values on a line where {cols} expected", idx + 1
                )
            toks = fixed
        tokens.extend(toks)
        per_line.append((idx + 1, len(toks)))
    line_of = np.repeat(np.array([ln for ln, _ in per_line], dtype=int), [n for _, n in per_line])
    try:
        values = np.array(tokens, dtype=float)
    except ValueError:
        values, line_of, per_line = _parse_slow(text, tokens, per_line)
    if values.size and not np.all(np.isfinite(values)):
        k = int(np.flatnonzero(~np.isfinite(values))[0])
        raise text.error(NonFiniteError, f"non-finite value {values[k]} (NaN or infinity)", int(line_of[k]))
    return DataBlock(values, line_of, per_line)


def _unfuse(toks: list[str]) -> list[str] | None:
    """Split Fortran fixed-width numbers that touch (``-1.2E-03-4.5E-03``); None if not numbers."""
    out: list[str] = []
    for t in toks:
        if _FUSED.fullmatch(t):
            out.extend(_ONE_NUM.findall(t))
        elif _to_float(t) is not None:
            out.append(t)
        else:
            return None
    return out


def _to_float(tok: str) -> float | None:
    try:
        return float(tok)
    except ValueError:
        if re.fullmatch(_NUM, tok) and tok.upper().count("D") == 1:
            return float(tok.upper().replace("D", "E"))
        return None


def _parse_slow(text: TextLines, tokens: list[str], per_line: list[tuple[int, int]]):
    """Token by token, to locate a bad token or to split fused numbers."""
    vals: list[float] = []
    lines: list[int] = []
    new_per_line: list[tuple[int, int]] = []
    k = 0
    for ln, n in per_line:
        count = 0
        for tok in tokens[k : k + n]:
            v = _to_float(tok)
            if v is not None:
                vals.append(v)
                count += 1
                continue
            parts = _unfuse([tok])
            if parts is None:
                raise text.error(NonNumericError, f"non-numeric value {tok!r}", ln)
            for p in parts:
                vals.append(float(p.upper().replace("D", "E")))
                count += 1
        lines.extend([ln] * count)
        new_per_line.append((ln, count))
        k += n
    return np.array(vals, dtype=float), np.array(lines, dtype=int), new_per_line


# --------------------------------------------------------------------------- checks
def check_dt(path: str, dt: float | None, line: int | None = None, limits: Limits = LIMITS) -> float:
    """Validate a time step [s]; returns it as float.

    Raises
    ------
    TimeStepError
        Missing, not finite, <= 0, or outside ``[limits.min_dt, limits.max_dt]``.
    """
    if dt is None:
        raise MissingTimeStepError(path, f"time step not given: {GIVE_DT}", line)
    try:
        dt = float(dt)
    except (TypeError, ValueError):
        raise TimeStepError(path, f"time step dt={dt!r} is not a number", line) from None
    if not math.isfinite(dt):
        raise TimeStepError(path, f"time step dt={dt:g} is not a finite number of seconds", line)
    if dt <= 0:
        raise TimeStepError(path, f"time step dt={dt:g} s must be > 0", line)
    if not (limits.min_dt <= dt <= limits.max_dt):
        raise TimeStepError(
            path,
            f"time step dt={dt:g} s is implausible: valid {limits.min_dt:g} to {limits.max_dt:g} s",
            line,
        )
    return dt


def check_time_column(text: TextLines, t: np.ndarray, line_of: np.ndarray) -> float:
    """Time step of a uniformly increasing time column [s].

    Raises
    ------
    TimeStepError
        Time not increasing or not uniform (with the line where it breaks).
    """
    if t.size < 2:
        raise text.error(EmptyRecordError, "fewer than 2 samples", int(line_of[0]) if line_of.size else None)
    steps = np.diff(t)
    if np.any(steps <= 0):
        k = int(np.flatnonzero(steps <= 0)[0])
        raise text.error(
            TimeStepError, f"time {t[k + 1]:g} s does not increase (previous {t[k]:g} s)", int(line_of[k + 1])
        )
    dt = float(f"{(t[-1] - t[0]) / (t.size - 1):.10g}")  # drop float noise: 0.019999999999999997 -> 0.02
    tol = 0.01 * dt + 5e-7
    off = np.abs(steps - dt) > tol
    if np.any(off):
        k = int(np.flatnonzero(off)[0])
        raise text.error(
            TimeStepError,
            f"time step {steps[k]:g} s differs from the mean step {dt:g} s (non-uniform sampling)",
            int(line_of[k + 1]),
        )
    return dt


def check_given_dt(path: str, given: float | None, found: float, where: str, line: int | None = None) -> None:
    """A user-given dt must agree with the one found in the file (0.1 %)."""
    if given is None:
        return
    g = float(given)
    if not math.isclose(g, found, rel_tol=1e-3):
        raise TimeStepError(path, f"dt={g:g} s given but the {where} says {found:g} s", line)


def check_given_units(path: str, given: str | None, found: str, line: int | None = None) -> None:
    """User-given units must agree with the units stated in the file."""
    if given is None:
        return
    g = normalize_units(given, path)
    if g != found:
        raise UnitsError(path, f"units={given!r} given but the file states {found}", line)


# --------------------------------------------------------------------------- traces
def make_trace(
    text: TextLines,
    data: np.ndarray,
    *,
    dt: float,
    units: str,
    fmt: str,
    station: str = "",
    channel: str = "",
    meta: dict | None = None,
    line: int | None = None,
    limits: Limits = LIMITS,
    allow_zero: bool = False,
    lines: np.ndarray | None = None,
) -> Trace:
    """A checked trace in m/s^2.

    Parameters
    ----------
    text : TextLines
        The source file.
    data : numpy.ndarray
        Values in ``units``.
    dt : float
        Time step [s].
    units : str
        Canonical units of ``data``.
    fmt : str
        Manifest name of the format.
    station, channel : str
        Station name and component.
    meta : dict, optional
        More ``stats.isorock`` entries (event text, header lines ...).
    line : int, optional
        Line to name in a units error.
    allow_zero : bool
        Accept a trace of zeros (one component of a multi-component file).
    lines : numpy.ndarray, optional
        Line of each sample, to name the line of an implausible peak.

    Raises
    ------
    EmptyRecordError, TimeStepError, UnitsError
    """
    dt = check_dt(text.path, dt, line, limits)
    data = np.asarray(data, dtype=np.float64)
    if data.size < limits.min_npts:
        raise text.error(
            EmptyRecordError, f"{data.size} data values; a record needs at least {limits.min_npts}", line
        )
    acc = data * unit_factor(units)
    peak = float(np.max(np.abs(acc)))
    if peak == 0.0 and not allow_zero:
        raise text.error(UnitsError, "all values are zero", line)
    pga_g = peak / G
    if pga_g > limits.max_pga_g:
        where = f" (units stated on line {line})" if line is not None else ""
        peak_line = int(lines[int(np.argmax(np.abs(acc)))]) if lines is not None and len(lines) else line
        raise text.error(
            UnitsError,
            f"peak {pga_g:.4g} g read as {units}{where} is implausible "
            f"(> {limits.max_pga_g:g} g): wrong units?",
            peak_line,
        )
    info = AttribDict(
        {
            "source": text.path,
            "format": fmt,
            "units": units,
            "event": "",
            "pga_g": pga_g,
            "station_name": station,
            "component": channel,
        }
    )
    for k, v in (meta or {}).items():
        info[k] = v
    tr = Trace(data=acc)
    tr.stats.delta = dt
    tr.stats.station = seed_code(station, 5)
    tr.stats.channel = seed_code(channel, 3)
    tr.stats.isorock = info
    return tr


def seed_code(name: str, width: int) -> str:
    """A SEED (MiniSEED) code of at most ``width`` characters for a station or channel name.

    Names that fit are kept as they are (``N-S``, ``164``); longer ones keep their first ``width``
    letters and digits, upper-cased (``Pacoima Dam (upper left abut)`` -> ``PACOI``). The full name
    stays in ``stats.isorock`` (``station_name``, ``component``).
    """
    name = str(name or "").strip()
    if len(name) <= width and name.isascii():
        return name
    return re.sub(r"[^0-9A-Za-z]", "", name).upper()[:width]


def trace_station(tr: Trace) -> str:
    """The full station name of a trace read by isorock (``stats.station`` holds its SEED code)."""
    return str(tr.stats.get("isorock", {}).get("station_name", tr.stats.station))


def trace_component(tr: Trace) -> str:
    """The full component name of a trace read by isorock (``stats.channel`` holds its SEED code)."""
    return str(tr.stats.get("isorock", {}).get("component", tr.stats.channel))


def stream(*traces: Trace) -> Stream:
    """A Stream of ``traces``."""
    return Stream(traces=list(traces))


def stem(path: str) -> str:
    """File name without directory and last extension."""
    return Path(path).stem
