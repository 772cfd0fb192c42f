"""What a component's name says: its azimuth (``230``, ``N-S``, ``S16E``), whether its provider rotated
it (``FN``, ``SP``), whether it is a vertical and which way it is positive (``DWN``), and the component
named by a file's name."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any, NamedTuple

from isorock.errors import IsorockError

__all__ = [
    "parse_azimuth",
    "component_from_name",
    "provided_orientation",
    "is_vertical",
    "line_angle",
    "POSITIVE",
    "STATION_DOWN",
    "VerticalPolarity",
    "vertical_polarity",
    "file_stem",
]

_VERTICAL = {"U-D", "UD", "UP", "Z", "V", "VER", "VERT", "VERTICAL", "D-U", "DOWN", "DWN", "DN"}


_NAMED = {
    "N-S": 0.0, "NS": 0.0, "N": 0.0, "NORTH": 0.0, "S-N": 0.0, "SN-COMPONENT": 0.0,
    "E-W": 90.0, "EW": 90.0, "E": 90.0, "EAST": 90.0, "W-E": 90.0,
}  # fmt: skip


_PROVIDED = {
    "FN": "SN", "SN": "SN", "FAULT-NORMAL": "SN", "FAULT NORMAL": "SN", "STRIKE-NORMAL": "SN",
    "FP": "SP", "SP": "SP", "FAULT-PARALLEL": "SP", "FAULT PARALLEL": "SP", "STRIKE-PARALLEL": "SP",
}  # fmt: skip


_BEARING = re.compile(r"^([NS])\s*(\d{1,2}(?:\.\d+)?)\s*([EW])$")


def parse_azimuth(name: str | None) -> float | None:
    """Azimuth [deg clockwise from north, in [0, 360)] of a component named by it, or None.

    ``"230"``, ``"090"``, ``"360"`` (degrees); ``"N-S"``, ``"E-W"`` and their variants; quadrant
    bearings ``"S16E"`` (164), ``"N44W"`` (316); SEED channel codes ending in ``N`` or ``E``
    (``"HNE"``). Names without a stated azimuth (``"TR"``, ``"FN"``, ``"Long"``) give None.
    """
    if name is None:
        return None
    s = str(name).strip().upper()
    if not s:
        return None
    if re.fullmatch(r"\d{1,3}(\.\d+)?", s):
        return float(s) % 360.0
    if s in _NAMED:
        return _NAMED[s]
    m = _BEARING.match(s)
    if m:
        a = float(m[2])
        if a > 90.0:
            return None
        base, sign = (0.0, 1.0) if m[1] == "N" else (180.0, -1.0)
        return (base + (sign if m[3] == "E" else -sign) * a) % 360.0
    if re.fullmatch(r"[BHELS][HNL][NE]", s):
        return 0.0 if s.endswith("N") else 90.0
    return None


_HORIZONTAL_N = re.compile(r"^(?:HOR|H)([12])$")


_STATION_AZIMUTH = re.compile(r"^[A-Z]{2,5}(\d{3})$")


_AZIMUTH_FN = re.compile(r"^(?:\d{3})?(FN|FP|SN|SP)$")


STATION_DOWN = re.compile(r"^[A-Z]{1,4}\d{0,3}DWN$")


_NAME_VERTICAL = {"UD", "UP", "U-D", "VER", "VERT", "VERTICAL", "DOWN", "DWN"}


#: the extensions of record files (lower case), taken off a name before its parts are read
_EXTENSIONS = frozenset(
    {"at2", "vt2", "dt2", "txt", "dat", "acc", "bbp", "csv", "asc", "sac", "mseed", "v1", "v2", "g3", "gz"}
)


def file_stem(filename: str | Path) -> str:
    """A record file's name without its extensions (``RSN982_NORTHR_JEN022.AT2.g3`` ->
    ``RSN982_NORTHR_JEN022``), a dot inside the name kept (PEER's ``RSN6_IMPVALL.I_I-ELC-UP.AT2`` ->
    ``RSN6_IMPVALL.I_I-ELC-UP``: its component is the last part, not lost with everything after the
    first dot)."""
    stem = Path(str(filename)).name
    while "." in stem.strip("."):
        head, ext = stem.rsplit(".", 1)
        if ext.lower() not in _EXTENSIONS:
            break
        stem = head
    return stem


def component_from_name(filename: str | Path) -> str | None:
    """The component a record file's name states, or None.

    The name (without its extensions) is cut at ``-``, ``_``, ``.`` and blanks; its parts after the
    first, last first, are tried: a provider's rotation (``fn``, ``_fp``, ``230fn`` -> ``FN``), a
    direction (``-N``, ``-E``, ``NS``, ``E-W`` -> ``N``, ``E``, ``NS``, ``EW``), a vertical (``UD``,
    ``UP``, a last part ``V`` or ``Z``, ``HNZ`` -> ``U-D``; ``DWN``, ``DOWN``, ``C05DWN`` -> ``DWN``, its
    samples positive down), an azimuth of three digits
    (``090``, ``-230``) or after a station code (``PKC090``, PEER's NGA names -> ``090``), a quadrant
    bearing (``S16E``), a numbered horizontal (``hor1``, ``H2`` -> ``HOR1``, ``HOR2``: named, azimuth
    unknown; only when no part states a direction, ``PUL164-hor1`` -> ``164``). The first part (an
    event or station) is never read as a component. See :func:`parse_azimuth` for the azimuths of these
    names.
    """
    parts = [x for x in re.split(r"[-_.\s]+", file_stem(filename)) if x]
    for part in reversed(parts[1:]):
        u = part.upper()
        m = _AZIMUTH_FN.match(u)
        if m:
            return m[1] if m[1] in ("FN", "FP") else {"SN": "FN", "SP": "FP"}[m[1]]
        if u in _NAMED and len(u) <= 2:
            return u
        # PEER's UP/DWN, Chi-Chi's "-V" (the last part only: a lone V or Z elsewhere names no
        # component), a SEED vertical channel (HNZ)
        last = part is parts[-1]
        if (
            u in _NAME_VERTICAL
            or (last and u in ("V", "Z"))
            or re.fullmatch(r"[BHELS][HNL]Z", u)
            or STATION_DOWN.match(u)  # PEER's station code and DWN: C05DWN, PASDWN
        ):
            # a name that says down keeps it: its samples are positive down (issue 34, docs/model.md §17)
            return "DWN" if u in ("DWN", "DOWN") or STATION_DOWN.match(u) else "U-D"
        if re.fullmatch(r"\d{3}", u) and int(u) <= 360:
            return u
        m = _STATION_AZIMUTH.match(u)
        if m and int(m[1]) <= 360:
            return m[1]
        if _BEARING.match(u) and parse_azimuth(u) is not None:
            return u
    for part in reversed(parts[1:]):  # a numbered horizontal only when no part states its direction
        m = _HORIZONTAL_N.match(part.upper())
        if m:
            return f"HOR{m[1]}"
    return None


def provided_orientation(name: str | None) -> str | None:
    """``"SN"`` or ``"SP"`` for a component its provider rotated (``FN``, ``fault-normal``, ``FP`` ...)."""
    if name is None:
        return None
    return _PROVIDED.get(str(name).strip().upper())


def is_vertical(name: str | None) -> bool:
    """The component is vertical (``U-D``, ``Z``, SEED ``HNZ`` ...)."""
    s = str(name or "").strip().upper()
    return s in _VERTICAL or bool(re.fullmatch(r"[BHELS][HNL]Z", s))


def line_angle(a_deg: float, b_deg: float) -> float:
    """Angle between two horizontal lines of azimuths ``a`` and ``b`` [deg], in [0, 90]."""
    d = abs(a_deg - b_deg) % 180.0
    return min(d, 180.0 - d)


#: the senses a vertical's samples can be stated in: positive up (the engine's a_v) or positive down
POSITIVE = ("up", "down")


#: component names that state a positive downward sense: PEER's ``DWN`` (the line 2 of an AT2 file is
#: the record's component: RSN77 Pacoima Dam, "..., DWN"), the COSMOS orientation ``Down`` (code 401,
#: beside 400 ``Up`` and 402 "Vertical, sense not indicated"), its short forms
_DOWN_NAMES = frozenset({"DWN", "DOWN", "DN"})


class VerticalPolarity(NamedTuple):
    """The sense of a vertical's samples as its file gives them, and what makes them positive up.

    Attributes
    ----------
    positive : str
        ``"up"`` or ``"down"``: the direction in which the file's samples are positive.
    sign : int
        +1 or -1: the factor that puts them positive up, the engine's a_v (docs/model.md §17).
    source : str
        ``"name"`` (the component's name states the sense), ``"given"`` (the user stated it) or
        ``"assumed"`` (the name states none: positive up is assumed).
    why : str
        One line: the sense taken and why.
    """

    positive: str
    sign: int
    source: str
    why: str

    def to_dict(self) -> dict[str, Any]:
        """``positive_in_file``, ``sign`` and ``polarity`` (the line), the JSON keys of the vertical."""
        return {"positive_in_file": self.positive, "sign": self.sign, "polarity": self.why}


def _names_down(name: str) -> bool:
    u = name.strip().upper()
    return u in _DOWN_NAMES or bool(STATION_DOWN.match(u))


def vertical_polarity(name: str | None, given: str | None = None) -> VerticalPolarity:
    """The sense of the samples of a vertical component named ``name`` (as its file names it: the
    component of a PEER file's header line, a BBP column, a SEED channel), or as the user states it.

    Parameters
    ----------
    name : str or None
        The component's name in its file (``DWN``, ``UP``, ``U-D``, ``HNZ`` ...).
    given : {"up", "down"} or None
        The sense stated by the user (``--vertical-positive``): it overrides the name.

    Returns
    -------
    VerticalPolarity
        ``DWN``, ``DOWN``, ``DN`` (and PEER's station-and-DWN names, ``C05DWN``): positive down, sign
        -1; ``UP``: positive up, sign +1; any other name states no sense and is taken positive up
        (``source="assumed"``, said so in ``why``).

    Raises
    ------
    IsorockError
        ``given`` is neither ``"up"`` nor ``"down"``.
    """
    label = str(name or "").strip() or "(unnamed)"
    down = _names_down(label)
    says = "down" if down else "up" if label.upper() == "UP" else None
    if given is not None:
        g = str(given).strip().lower()
        if g not in POSITIVE:
            raise IsorockError(f"vertical polarity {given!r}: give 'up' or 'down'")
        note = "" if says in (None, g) else f" (its name {label} says {says})"
        if g == "down":
            why = f"positive down in the file as stated{note}: sign reversed to positive up"
            return VerticalPolarity("down", -1, "given", why)
        return VerticalPolarity("up", 1, "given", f"positive up in the file as stated{note}: taken as read")
    if says == "down":
        why = (
            f"positive down in the file: its component is named {label} (down, the COSMOS vertical "
            "orientation 401): sign reversed to the engine's positive up"
        )
        return VerticalPolarity("down", -1, "name", why)
    if says == "up":
        return VerticalPolarity("up", 1, "name", f"positive up in the file: its component is named {label}")
    why = f"the name {label} states no sense: taken positive up, as read"
    return VerticalPolarity("up", 1, "assumed", why)
