"""Horizontal components of a record: their azimuths, the direction a catalog row asks for, rotation
of two components to it, and the choice of the component analysed.

The paper's Table 1 names the component it used: strike-normal or strike-parallel (``SN``/``SP``,
defined by the fault strike of the catalog row and its cited source), an azimuth (``090``), or a
name whose azimuth is not stated (``Long``/``Tran``). :func:`choose_component` turns the files of a
row into that component:

1. every horizontal component of the files is a candidate (a multi-component file gives each of its
   horizontals); its azimuth comes from the manifest's ``azimuth_deg`` or from its name
   (:func:`parse_azimuth`: ``230``, ``N-S``, ``S16E`` ...), and a name such as ``FN`` marks a
   component its provider already rotated (:func:`provided_orientation`);
2. when the row's azimuth is known, two horizontal components of one recording (the same file, or
   two files of the same station and format, including the files of another catalog row of the same
   station and event, ``partner`` files, which serve only as the second component of a pair) are
   rotated to it (:func:`isorock.pulse.rotate_horizontal`, ObsPy's ``rotate2zne``) before processing,
   provided their azimuths are known and they are time-aligned (:func:`check_alignment`: same time
   step, same stated start, lengths within 0.5 %, energy envelopes peaking together within 1 s). A
   pair refused for a missing azimuth or a misalignment is said so in the QA mark when no other
   rotation or provided component is used;
3. every candidate is processed with the same steps, and they are ranked: QA passed first; then
   those whose PGA and PGV are within a factor 1.5 of the catalog's (the paper's own values of its
   component: a direction that disagrees with them is not the component the paper analysed); then
   by how the direction was obtained (:data:`METHODS`: provided by the data source, rotated here, a
   recorded component within :data:`ALIGNED_DEG` of the direction, any other recorded component, the
   closest first); then by the PGV closest to the catalog's (``choose="table1_pgv"``) or the
   manifest order (``"first"``).

The result (:class:`ComponentChoice`) says which direction was analysed and how, compares its PGA
and PGV with the catalog's, and carries a QA mark when the direction is not the row's: "as
recorded, azimuth 065 instead of SN (15 deg off)". Records without a catalog row are analysed as
recorded, without a mark.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

from obspy import Trace

from isorock.errors import IsorockError
from isorock.io import read_record, read_trace, trace_component
from isorock.records.manifest import ManifestEntry

# the processing and the records' provenance (scipy, ObsPy filters) are imported where they are used:
# the workflow's plan imports this module for RecordFile and Target only

__all__ = [
    "ALIGNED_DEG",
    "METHODS",
    "PAIR_MAX_LAG_S",
    "Alignment",
    "check_alignment",
    "RecordFile",
    "Target",
    "component_from_name",
    "ComponentChoice",
    "parse_azimuth",
    "provided_orientation",
    "line_angle",
    "choose_component",
]

#: a recorded component this close to the wanted direction [deg] is taken as it (cos 5 deg = 0.996)
ALIGNED_DEG = 5.0
#: how the analysed direction was obtained, best first (the rank of a candidate)
METHODS = ("provided", "rotated", "aligned", "as recorded")
#: two components are rotated only if their azimuths are at least this far from parallel [deg]
_PAIR_MIN_DEG = 60.0
#: two files of one recording: lengths within this fraction
_PAIR_NPTS_RTOL = 0.005
#: two files of one recording: their energy envelopes peak together within this lag [s] ...
PAIR_MAX_LAG_S = 1.0
#: ... or their zero-lag correlation is at least this fraction of the best one [-]
_PAIR_ZERO_LAG_FRACTION = 0.8
#: two files of one recording: their energy envelopes correlate at least this well [-]
_PAIR_MIN_ENVELOPE_CORR = 0.5
#: moving-average window of the energy envelopes compared [s]
_ENVELOPE_S = 1.0
#: a PGA or PGV this far from the catalog's (ratio or its inverse) is noted
_TABLE1_RATIO = 1.5

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
_STATION_DOWN = re.compile(r"^[A-Z]{1,4}\d{0,3}DWN$")
_NAME_VERTICAL = {"UD", "UP", "U-D", "VER", "VERT", "VERTICAL", "DOWN", "DWN"}


#: the extensions of record files (lower case), taken off a name before its parts are read
_EXTENSIONS = frozenset(
    {"at2", "vt2", "dt2", "txt", "dat", "acc", "bbp", "csv", "asc", "sac", "mseed", "v1", "v2", "g3", "gz"}
)


def _stem(filename: str | Path) -> str:
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
    parts = [x for x in re.split(r"[-_.\s]+", _stem(filename)) if x]
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
            or _STATION_DOWN.match(u)  # PEER's station code and DWN: C05DWN, PASDWN
        ):
            # a name that says down keeps it: its samples are positive down (issue 34, docs/model.md §17)
            return "DWN" if u in ("DWN", "DOWN") or _STATION_DOWN.match(u) else "U-D"
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


@dataclass(frozen=True)
class Alignment:
    """Whether two horizontal components are time-aligned (see :func:`check_alignment`).

    Attributes
    ----------
    ok : bool
        They may be rotated together.
    problem : str
        Why not, in words ("" when ``ok``).
    lag_s : float or None
        Lag [s] at which the energy envelopes of the two correlate best; positive when the energy of
        the second arrives later (None when not measured: one file, or refused before).
    envelope_corr : float or None
        That correlation [-] (1: the envelopes are the same function of time).
    npts : tuple of int
        Number of samples of each.
    """

    ok: bool
    problem: str = ""
    lag_s: float | None = None
    envelope_corr: float | None = None
    npts: tuple[int, int] = (0, 0)

    def describe(self) -> str:
        """``"time-aligned (energy envelopes peak 0.50 s apart, correlation 0.94)"``."""
        if not self.ok:
            return f"not time-aligned: {self.problem}"
        if self.lag_s is None:
            return "time-aligned (one file, one time column)"
        return (
            f"time-aligned (energy envelopes peak {abs(self.lag_s):.2f} s apart, "
            f"correlation {self.envelope_corr:.2f})"
        )


def _stated_start(tr: Trace) -> float | None:
    """The start [s, epoch] a file states (an absolute start time, or the first value of a time
    column), or None when the format states none (ObsPy's default start and no time column)."""
    t0 = tr.stats.get("isorock", {}).get("t0")
    start = float(tr.stats.starttime.timestamp)
    if t0 is None and start == 0.0:
        return None
    return start + float(t0 or 0.0)


def _envelope(x: Any, dt: float) -> Any:
    """Energy envelope [(m/s^2)^2]: the squared, linearly detrended signal averaged over
    :data:`_ENVELOPE_S`."""
    import numpy as np
    from scipy.signal import detrend

    a = detrend(np.asarray(x, dtype=float), type="linear")
    k = max(1, int(round(_ENVELOPE_S / dt)))
    return np.convolve(a * a, np.ones(k) / k, mode="same")


def check_alignment(
    tr1: Trace,
    tr2: Trace,
    *,
    one_file: bool = False,
    envelopes: bool = True,
    length_rtol: float | None = None,
) -> Alignment:
    """Whether two horizontal components of one recording are time-aligned sample for sample.

    A rotation combines the two sample by sample, so sample ``k`` of both must be the same instant.
    Two components of one file (the N-S and E-W columns of a BBP file) share its time column and are
    aligned by construction. Two files carry no common clock (most formats state no start time), so
    the check uses what they state and what the motion itself shows:

    1. the same time step (to 1e-6);
    2. the same start, when both formats state one (an absolute start time, or the first value of a
       time column), within half a time step;
    3. lengths within 0.5 % (two files of one recording are cut alike; a longer trailer is allowed,
       the rotation stops at the shorter one);
    4. the energy envelopes agree without a shift: the normalised cross-correlation of the squared,
       linearly detrended accelerations averaged over 1 s (:data:`_ENVELOPE_S`) reaches at least
       0.5 (else the two are not one recording), and it peaks within :data:`PAIR_MAX_LAG_S` (1 s) of
       zero lag, or its zero-lag value is at least 0.8 of its peak. A pair is refused only when a
       shift of more than 1 s makes the envelopes agree clearly better.

    Why the envelopes and not the signed traces: two horizontal components are projections of one
    motion on two directions; their signed cross-correlation depends on the polarisation (near zero
    for a motion along one of them, a quarter period off for an elliptical one), so where it peaks
    says little about alignment (on the pairs of the shared records it peaks anywhere from -1.8 s to
    +0.6 s). Their energy rises and falls with the arrival of the wave groups whatever the
    polarisation, and a shift of one file moves the envelope peak by the shift. Measured on the
    shared records: the two-file pairs peak within 0.65 s of zero lag, at zero-lag values of at
    least 0.88 of the peak (correlations 0.89-0.97); the N-S and E-W columns of one BBP file
    (Sylmar Converter Station East), aligned by their time column, peak 2.9 s apart, at a zero-lag
    value of 0.86 of the peak: the natural difference can exceed 1 s (hence the second condition);
    a 2 s shift of any of these pairs drops the zero-lag value below 0.75 of a peak moved by the
    shift. Shifts of about 2 s or more are thus detected; shifts under about 1 s cannot be told from
    the natural difference between two directions of one motion and are not.

    Parameters
    ----------
    tr1, tr2 : obspy.Trace
        The two components (acceleration, any units; raw or processed).
    one_file : bool
        Both come from one file with one time column: items 1 and 3 are checked, not 2 and 4.
    envelopes : bool
        Judge item 4. False for a vertical beside a horizontal: its energy arrives with the P waves,
        before the S waves that carry most of the horizontal energy (measured: 1.2 s on El Centro 1940
        UP against 180, 1.5 s on the U-D and N-S columns of the Jensen BBP file, which share one time
        column), so the envelopes' lag is measured and reported but tells nothing of the alignment.
    length_rtol : float, optional
        The largest relative difference of the lengths (default 0.5 %, item 3).

    Returns
    -------
    Alignment
        ``ok``, the ``problem`` in words, the envelope lag [s] and correlation [-] (None for
        ``one_file``).
    """
    d1, d2 = float(tr1.stats.delta), float(tr2.stats.delta)
    n1, n2 = int(tr1.stats.npts), int(tr2.stats.npts)
    npts = (n1, n2)
    if not math.isclose(d1, d2, rel_tol=1e-6):
        return Alignment(False, f"time steps differ ({d1:g} and {d2:g} s)", npts=npts)
    rtol = _PAIR_NPTS_RTOL if length_rtol is None else length_rtol
    if abs(n1 - n2) > rtol * max(n1, n2):
        why = (
            f"lengths differ by {abs(n1 - n2)} samples ({abs(n1 - n2) / max(n1, n2):.1%}, at most {rtol:.1%})"
        )
        return Alignment(False, why, npts=npts)
    if one_file:
        return Alignment(True, npts=npts)
    s1, s2 = _stated_start(tr1), _stated_start(tr2)
    if s1 is not None and s2 is not None and abs(s2 - s1) > 0.5 * d1:
        return Alignment(False, f"their files state starts {s2 - s1:+.3f} s apart", npts=npts)
    lag, corr, corr0 = _envelope_lag(tr1, tr2)
    if corr is None:
        return Alignment(False, "a component is constant", npts=npts)
    if not envelopes:
        return Alignment(True, "", lag, corr, npts)
    if corr < _PAIR_MIN_ENVELOPE_CORR:
        why = f"their energy envelopes do not correlate (at most {corr:.2f}): not one recording?"
        return Alignment(False, why, lag, corr, npts)
    if abs(lag) > PAIR_MAX_LAG_S and corr0 < _PAIR_ZERO_LAG_FRACTION * corr:
        why = (
            f"the energy of the second arrives {abs(lag):.2f} s {'after' if lag > 0 else 'before'} that "
            f"of the first (energy envelopes correlate at {corr:.2f} with that shift, {corr0:.2f} without)"
        )
        return Alignment(False, why, lag, corr, npts)
    return Alignment(True, "", lag, corr, npts)


def _envelope_lag(tr1: Trace, tr2: Trace) -> tuple[float, float | None, float]:
    """Lag [s] of the peak of the normalised cross-correlation of the energy envelopes of two traces
    of one time step (positive: the second later), that peak and the zero-lag value [-]."""
    import numpy as np
    from scipy.signal import correlate, correlation_lags

    dt = float(tr1.stats.delta)
    n = max(tr1.stats.npts, tr2.stats.npts)
    e1, e2 = (np.pad(_envelope(t.data, dt), (0, n - t.stats.npts)) for t in (tr1, tr2))
    e1, e2 = e1 - e1.mean(), e2 - e2.mean()
    norm = math.sqrt(float(np.dot(e1, e1)) * float(np.dot(e2, e2)))
    if norm == 0.0:
        return 0.0, None, 0.0
    c = correlate(e2, e1, mode="full") / norm
    lags = correlation_lags(n, n, mode="full")
    k = int(np.argmax(c))
    return float(lags[k]) * dt, float(c[k]), float(c[lags == 0][0])


@dataclass(frozen=True)
class RecordFile:
    """One file that may provide a record, with how to read it.

    Parameters
    ----------
    path : str
        Absolute path of the file.
    format : str or None
        Manifest format name (None: detect).
    dt_s : float or None
        Time step [s] for files that do not state it.
    units : str or None
        Units of the values in the file.
    component : str or None
        Component of a multi-component file (None: the file's only one, or all its horizontals).
    substitute : bool
        The file stands in for the catalog row (another station).
    note : str
        Manifest note.
    station : str
        Station as the manifest names it (files of one station may be rotated together).
    component_name : str
        Component as the manifest names it (``230``, ``FN``, ``N-S`` ...).
    azimuth_deg : float or None
        Azimuth of that component [deg] when the manifest states it.
    partner : bool
        The file belongs to another catalog row of the same station and event (the other horizontal
        component of the recording): it serves only as the second component of a rotation, never as
        the component analysed on its own.
    """

    path: str
    format: str | None = None
    dt_s: float | None = None
    units: str | None = None
    component: str | None = None
    substitute: bool = False
    note: str = ""
    station: str = ""
    component_name: str = ""
    azimuth_deg: float | None = None
    partner: bool = False

    @classmethod
    def from_entry(cls, directory: Path, e: ManifestEntry) -> RecordFile:
        """The file of a manifest row of ``directory``, with how to read it."""
        kw = e.read_kwargs()
        return cls(
            path=str((directory / e.file).resolve()),
            format=kw["format"],
            dt_s=kw["dt"],
            units=kw["units"],
            component=kw["component"],
            substitute=e.is_substitute,
            note=e.note,
            station=e.station,
            component_name=e.component,
            azimuth_deg=e.azimuth_deg,
        )


@dataclass(frozen=True)
class Target:
    """The direction a catalog row asks for.

    Parameters
    ----------
    label : str
        The row's component: ``SN``, ``SP``, an azimuth (``090``) or a name (``Long``); "" for a
        record without a catalog row.
    azimuth_deg : float or None
        Its azimuth [deg, in [0, 360)] when known (``SN``: strike + 90, ``SP``: strike).
    strike_deg : float or None
        Fault strike [deg] of an ``SN``/``SP`` row.
    strike_source : str
        Where the strike comes from.
    """

    label: str = ""
    azimuth_deg: float | None = None
    strike_deg: float | None = None
    strike_source: str = ""

    @classmethod
    def of(cls, label: str | None, strike_deg: float | None = None, strike_source: str = "") -> Target:
        """The target of a catalog row from its ``component``, ``strike_deg`` and ``strike_source``."""
        lab = str(label or "").strip()
        from isorock.processing.orientation import fault_azimuth

        orient = provided_orientation(lab)
        strike = None if strike_deg is None or not math.isfinite(float(strike_deg)) else float(strike_deg)
        if orient is not None:
            az = fault_azimuth(strike, orient) if strike is not None else None
            return cls(orient, az, strike, strike_source or "")
        return cls(lab, parse_azimuth(lab), None, "")

    def describe(self) -> str:
        """``"SN (azimuth 053.0 deg, fault strike 323 deg)"`` and the like."""
        if not self.label:
            return "no catalog direction"
        if self.label in ("SN", "SP") and self.strike_deg is not None:
            return (
                f"{self.label} (azimuth {self.azimuth_deg:05.1f} deg, fault strike {self.strike_deg:g} deg)"
            )
        if self.azimuth_deg is not None:
            return f"azimuth {self.azimuth_deg:05.1f} deg"
        return f"{self.label} (azimuth not known)"


@dataclass
class _Candidate:
    """One horizontal direction that may be analysed, before and after processing."""

    raw: Trace
    files: tuple[int, ...]
    name: str
    azimuth_deg: float | None
    provided: str | None
    method: str = "as recorded"
    angle_deg: float | None = None
    text: str = ""
    rec: Any = None  # LoadedRecord once processed
    info: dict[str, Any] = field(default_factory=dict)
    parts: tuple[_Candidate, ...] = ()


@dataclass
class ComponentChoice:
    """The component analysed for a record and how it was obtained.

    Attributes
    ----------
    record : isorock.records.motion.LoadedRecord
        The processed record; ``record.source`` has its provenance (``rotated_from`` for a rotation).
    file : RecordFile
        The (first) file it comes from.
    target : Target
        The direction the catalog row asks for.
    component : str
        Label of the direction analysed: the target's label when it is that direction (provided,
        rotated or aligned), else the recorded component's name.
    recorded_component : str
        Name of the recorded component analysed ("" for a rotation).
    azimuth_deg : float or None
        Its azimuth [deg] (None when not known).
    method : str
        One of :data:`METHODS`.
    description : str
        How it was obtained, in words.
    qa_mark : str
        "" when the direction is the row's; else e.g. "as recorded, azimuth 065 instead of SN (15 deg
        off)"; followed by :attr:`pairs_refused` when the direction is neither rotated nor provided.
    table1_check : str
        "" when PGA and PGV are within a factor 1.5 of the catalog's; else which is not.
    pga_over_table1, pgv_over_table1 : float or None
        Ratios of the processed record's PGA and PGV to the catalog's [-].
    candidates : list of dict
        One line per candidate considered (file(s), component, azimuth, method, QA, PGA, PGV, chosen).
    pairs_refused : list of str
        One line per pair of components of one recording not rotated (an azimuth not known, not
        time-aligned); in ``qa_mark`` too when the direction analysed is neither rotated nor provided.
    pair : tuple of obspy.Trace or None
        Two orthogonal horizontals of the recording analysed, processed alike (rotated from its two
        recorded components to the analysed direction and 90 degrees from it): the RotD values are
        of them (:func:`isorock.processing.imt.rotd`). None when the recording has one horizontal
        only, or its two could not be paired (azimuths not known, not time-aligned).
    pair_description : str
        Which components they are, in words ("" when none).
    """

    record: Any
    file: RecordFile
    target: Target
    component: str
    recorded_component: str
    azimuth_deg: float | None
    method: str
    description: str
    qa_mark: str
    table1_check: str
    pga_over_table1: float | None
    pgv_over_table1: float | None
    candidates: list[dict[str, Any]]
    pairs_refused: list[str] = field(default_factory=list)
    pair: tuple[Trace, Trace] | None = None
    pair_description: str = ""

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary (without the traces)."""
        return {
            "component": self.component,
            "azimuth_deg": self.azimuth_deg,
            "component_method": self.method,
            "component_description": self.description,
            "component_qa": self.qa_mark,
            "target": asdict(self.target),
            "table1_check": self.table1_check,
            "pga_over_table1": self.pga_over_table1,
            "pgv_over_table1": self.pgv_over_table1,
        }


def _read(f: RecordFile) -> list[Trace]:
    """The horizontal components of one file, raw [m/s^2]: all of a multi-component file (BBP),
    whichever column its manifest row names."""
    if f.format in (None, "bbp"):
        st = read_record(f.path, f.format, dt=f.dt_s, units=f.units)
        traces = [tr for tr in st if not is_vertical(trace_component(tr))]
        if len(traces) > 1:
            return traces
    return [read_trace(f.path, f.format, dt=f.dt_s, units=f.units, component=f.component)]


def _az_of(f: RecordFile, tr: Trace, single: bool) -> float | None:
    name = trace_component(tr)
    if single and f.azimuth_deg is not None:
        return float(f.azimuth_deg) % 360.0
    az = parse_azimuth(name)
    if az is None and single:
        az = parse_azimuth(f.component_name)
    return az


def _candidates(
    files: Sequence[RecordFile],
    target: Target,
    problems: list[dict],
    refused: list[str],
    every_single: list[_Candidate] | None = None,
) -> list[_Candidate]:
    """Every single component of the row's own files, then the rotated pairs (a partner file only in
    a pair); ``refused`` gets one line per pair of one recording that could not be rotated, and
    ``every_single`` (where given) every single horizontal read, a partner file's too."""
    singles: list[_Candidate] = []
    seen: set[tuple[str, str]] = set()
    for i, f in enumerate(files):
        try:
            traces = _read(f)
        except IsorockError as exc:
            problems.append({"file": Path(f.path).name, "ok": False, "problem": str(exc).splitlines()[0]})
            continue
        for tr in traces:
            name = trace_component(tr) or f.component_name
            if (f.path, name) in seen or is_vertical(name):
                continue  # a vertical (UP, DWN, U-D) is no input of a horizontal analysis
            seen.add((f.path, name))
            single = len(traces) == 1
            provided = provided_orientation(name) or (
                provided_orientation(f.component_name) if single else None
            )
            singles.append(_Candidate(tr, (i,), name, _az_of(f, tr, single), provided))
    pairs: list[_Candidate] = []
    if target.azimuth_deg is not None:
        for a in range(len(singles)):
            for b in range(a + 1, len(singles)):
                c1, c2 = singles[a], singles[b]
                ok, why, al = _pair_check(files, c1, c2, target)
                if ok:
                    pairs.append(_rotated(files, c1, c2, target, al))
                elif why:
                    refused.append(why)
    own = [c for c in singles if not files[c.files[0]].partner]
    if every_single is not None:
        every_single.extend(singles)
    return own + pairs


def _same_recording(files: Sequence[RecordFile], c1: _Candidate, c2: _Candidate) -> bool:
    """Two components of one file, or of two files of one station and format (not both partners)."""
    f1, f2 = files[c1.files[0]], files[c2.files[0]]
    if f1.partner and f2.partner:
        return False
    if f1.path == f2.path:
        return True
    st1, st2 = f1.station.strip().lower(), f2.station.strip().lower()
    return bool(st1) and st1 == st2 and (f1.format or "") == (f2.format or "")


def _pair_check(
    files: Sequence[RecordFile], c1: _Candidate, c2: _Candidate, target: Target
) -> tuple[bool, str, Alignment | None]:
    """Whether two components may be rotated together to the target.

    Returns ``(ok, why, alignment)``: ``why`` is "" when the two are simply not a pair (a component
    its provider rotated, two recordings, two near-parallel components), else the reason a pair of
    one recording is refused (an azimuth not known, not time-aligned: :func:`check_alignment`).
    """
    if c1.provided or c2.provided or not _same_recording(files, c1, c2):
        return False, "", None
    az1, az2 = c1.azimuth_deg, c2.azimuth_deg
    if az1 is not None and az2 is not None and line_angle(az1, az2) < _PAIR_MIN_DEG:
        return False, "", None
    al = check_alignment(c1.raw, c2.raw, one_file=files[c1.files[0]].path == files[c2.files[0]].path)
    reasons = []
    unknown = [c.name for c in (c1, c2) if c.azimuth_deg is None]
    if unknown:
        whose = f"the azimuth of {unknown[0]} is" if len(unknown) == 1 else "their azimuths are"
        reasons.append(f"{whose} not known (stated neither by the manifest nor by the name)")
    if not al.ok:
        reasons.append(f"not time-aligned: {al.problem}")
    if not reasons:
        return True, "", al
    names = " and ".join(f"{c.name} ({Path(files[c.files[0]].path).name})" for c in (c1, c2))
    aligned = f"; the two are {al.describe()}" if al.ok else ""
    return False, f"{names} not rotated to {target.label}: {'; '.join(reasons)}{aligned}", al


def _rotated(
    files: Sequence[RecordFile], c1: _Candidate, c2: _Candidate, target: Target, al: Alignment | None
) -> _Candidate:
    from isorock.processing.orientation import rotate_horizontal

    a1, a2, az_target = c1.azimuth_deg, c2.azimuth_deg, target.azimuth_deg
    # _candidates pairs only components of known azimuths (_pair_check), for a target of known azimuth
    assert a1 is not None and a2 is not None and az_target is not None
    az = float(az_target)
    raw = rotate_horizontal(c1.raw, a1, c2.raw, a2, az)
    n1, n2 = c1.raw.stats.npts, c2.raw.stats.npts
    cut = f"; lengths differ by {abs(n1 - n2)} samples: aligned at the first sample" if n1 != n2 else ""
    names = " and ".join(f"{c.name} ({Path(files[c.files[0]].path).name})" for c in (c1, c2))
    c = _Candidate(raw, c1.files + c2.files, target.label, az, None, method="rotated", angle_deg=0.0)
    c.parts = (c1, c2)
    timing = f", {al.describe()}" if al is not None else ""
    c.text = f"rotated from {names} to {target.describe()}{timing}{cut}"
    return c


def _classify(c: _Candidate, target: Target) -> None:
    """Method, angle to the target and a description of a single component."""
    if c.method == "rotated":
        return
    where = f"azimuth {c.azimuth_deg:05.1f} deg" if c.azimuth_deg is not None else "azimuth not known"
    if c.provided is not None and target.label and c.provided == target.label:
        c.method, c.angle_deg = "provided", 0.0
        c.text = f"{c.name} as provided by the data source ({target.label})"
        if target.azimuth_deg is not None:
            c.azimuth_deg = target.azimuth_deg
        return
    if c.azimuth_deg is not None and target.azimuth_deg is not None:
        c.angle_deg = line_angle(c.azimuth_deg, target.azimuth_deg)
    if c.angle_deg is not None and c.angle_deg <= ALIGNED_DEG:
        c.method = "aligned"
        c.text = f"{c.name} as recorded, {where}, {c.angle_deg:.0f} deg from {target.describe()}"
        return
    c.method = "as recorded"
    c.text = f"{c.name} as recorded, {where}"


def _qa_mark(c: _Candidate, target: Target) -> str:
    if c.method != "as recorded" or not target.label:
        return ""
    if c.provided is not None:
        return f"as provided ({c.name}) instead of {target.label}"
    if c.azimuth_deg is None:
        return f"as recorded ({c.name}, azimuth not known) instead of {target.label}"
    off = f" ({c.angle_deg:.0f} deg off)" if c.angle_deg is not None else " (its azimuth not known)"
    return f"as recorded, azimuth {c.azimuth_deg:03.0f} instead of {target.label}{off}"


def _ratio(x: float, ref: float | None) -> float | None:
    return None if ref is None or not ref or not math.isfinite(ref) else float(x / ref)


def choose_component(
    files: Sequence[RecordFile],
    target: Target | None = None,
    *,
    processing: Any = None,
    raw: bool = False,
    choose: str = "table1_pgv",
    table1_pga_g: float | None = None,
    table1_pgv_m_s: float | None = None,
    pairs: bool = False,
) -> ComponentChoice:
    """The component of a record to analyse, from its files (see the module docstring).

    Parameters
    ----------
    files : sequence of RecordFile
        The files that may provide the record, in manifest order.
    target : Target, optional
        The direction the catalog row asks for (None: analyse as recorded).
    processing : ProcessingConfig, path or None
        Processing steps (None: the packaged ``processing.yaml``).
    raw : bool
        Skip the processing.
    choose : {"table1_pgv", "first"}
        Order among candidates of equal rank: PGV closest to ``table1_pgv_m_s``, or manifest order.
    table1_pga_g, table1_pgv_m_s : float, optional
        The catalog's PGA [g] and PGV [m/s].
    pairs : bool
        Also find the two orthogonal horizontals of the recording (:attr:`ComponentChoice.pair`).

    Returns
    -------
    ComponentChoice

    Raises
    ------
    IsorockError
        No file could be read (the message lists why).
    """
    from isorock.processing import metrics, process, qa_passed, qa_reasons
    from isorock.records.motion import LoadedRecord, record_source

    target = target or Target()
    problems: list[dict] = []
    refused: list[str] = []
    every_single: list[_Candidate] = []
    cands = _candidates(files, target, problems, refused, every_single)
    if not cands:
        why = "; ".join(f"{p['file']}: {p['problem']}" for p in problems) or "no file"
        raise IsorockError(f"no file could be read ({why})")
    for c in cands:
        _classify(c, target)
        analysed = c.raw.copy() if raw else process(c.raw, processing)
        f = files[c.files[0]]
        src = record_source(f.path, c.raw, analysed, raw)
        m = metrics(analysed)
        c.info = {
            "file": " + ".join(Path(files[i].path).name for i in c.files),
            "ok": True,
            "problem": "",
            "component": c.name,
            "azimuth_deg": c.azimuth_deg,
            "method": c.method,
            "qa_passed": qa_passed(analysed),
            "qa_reasons": qa_reasons(analysed),
            "pga_g": m["pga_g"],
            "pgv_m_s": m["pgv_m_s"],
            "substitute": any(files[i].substitute for i in c.files),
        }
        c.rec = LoadedRecord(raw=c.raw, trace=analysed, source=src)
    order = {m: k for k, m in enumerate(METHODS)}

    def consistent(c: _Candidate) -> bool:
        r = (_ratio(c.info["pga_g"], table1_pga_g), _ratio(c.info["pgv_m_s"], table1_pgv_m_s))
        return all(x is None or 1.0 / _TABLE1_RATIO <= x <= _TABLE1_RATIO for x in r)

    def key(k: int, check: bool = True) -> tuple:
        c = cands[k]
        pgv = c.info["pgv_m_s"]
        if choose == "table1_pgv" and table1_pgv_m_s:
            closeness: float = abs(math.log(max(pgv, 1e-12) / table1_pgv_m_s))
        else:
            closeness = k
        angle = c.angle_deg if c.angle_deg is not None else 90.0
        return (not c.info["qa_passed"], check and not consistent(c), order[c.method], angle, closeness)

    pick = min(range(len(cands)), key=key)
    by_direction = min(range(len(cands)), key=lambda k: key(k, check=False))
    for k, c in enumerate(cands):
        c.info["chosen"] = k == pick
    best = cands[pick]
    rec = best.rec
    assert rec is not None
    if best.method == "rotated":
        rotated_from = [_part_source(files, p) for p in best.parts]
        rec = type(rec)(rec.raw, rec.trace, replace(rec.source, rotated_from=rotated_from))
    comp = target.label if best.method != "as recorded" and target.label else best.name
    rec = _with_orientation(rec, comp, best.azimuth_deg)
    m = metrics(rec.trace)
    pga_r, pgv_r = _ratio(m["pga_g"], table1_pga_g), _ratio(m["pgv_m_s"], table1_pgv_m_s)
    check = [
        f"{what} {val:.3g} {unit} = {r:.2f} x the catalog's"
        for what, val, unit, r in (("PGA", m["pga_g"], "g", pga_r), ("PGV", m["pgv_m_s"], "m/s", pgv_r))
        if r is not None and not (1.0 / _TABLE1_RATIO <= r <= _TABLE1_RATIO)
    ]
    mark = _qa_mark(best, target)
    if by_direction != pick:
        other = cands[by_direction]
        why = " and ".join(
            f"{w} is {r:.2f} x"
            for w, r in (
                ("PGA", _ratio(other.info["pga_g"], table1_pga_g)),
                ("PGV", _ratio(other.info["pgv_m_s"], table1_pgv_m_s)),
            )
            if r is not None and not (1.0 / _TABLE1_RATIO <= r <= _TABLE1_RATIO)
        )
        instead = f"the {other.method} {other.name} is not used: its {why} the catalog's"
        mark = "; ".join(x for x in (mark, instead) if x)
    if best.method not in ("rotated", "provided"):
        mark = "; ".join(x for x in (mark, *refused) if x)
    pair, pair_text = (
        _horizontal_pair(files, cands, best, processing, raw, every_single) if pairs else (None, "")
    )
    return ComponentChoice(
        record=rec,
        file=files[best.files[0]],
        target=target,
        component=comp,
        recorded_component="" if best.method == "rotated" else best.name,
        azimuth_deg=best.azimuth_deg,
        method=best.method,
        description=best.text,
        qa_mark=mark,
        table1_check="; ".join(check),
        pga_over_table1=pga_r,
        pgv_over_table1=pgv_r,
        candidates=problems + [c.info for c in cands],
        pairs_refused=refused,
        pair=pair,
        pair_description=pair_text,
    )


def _horizontal_pair(
    files: Sequence[RecordFile],
    cands: Sequence[_Candidate],
    best: _Candidate,
    processing: Any,
    raw: bool,
    every_single: Sequence[_Candidate] = (),
) -> tuple[tuple[Trace, Trace] | None, str]:
    """Two orthogonal horizontals of the recording of ``best``, processed alike, and their description
    (see :attr:`ComponentChoice.pair`): the two recorded components of a rotation, or the component
    analysed and another of its recording (same file, or same station and format) with both azimuths
    known, not near-parallel and time-aligned; each pair rotated to the analysed direction and 90
    degrees from it, then processed, as a rotation is."""
    from isorock.processing import process
    from isorock.processing.orientation import rotate_horizontal

    if best.method == "rotated":
        c1, c2 = best.parts
    else:
        singles: list[_Candidate] = []
        for c in [*cands, *every_single]:  # a partner file (a PEER search's second horizontal) too
            for x in c.parts if c.method == "rotated" else (c,):
                if all(x is not y for y in singles):
                    singles.append(x)
        mates = [
            c
            for c in singles
            if c is not best and not c.provided and not best.provided and _same_recording(files, best, c)
        ]
        pair = None
        for c in mates:
            ok, _, _ = _pair_check(files, best, c, Target(azimuth_deg=best.azimuth_deg))
            if ok:
                pair = (best, c)
                break
        if pair is None:
            return None, ""
        c1, c2 = pair
    a1, a2 = c1.azimuth_deg, c2.azimuth_deg
    if a1 is None or a2 is None:
        return None, ""
    az = float(best.azimuth_deg if best.azimuth_deg is not None else a1)
    out = []
    for k in (0.0, 90.0):
        r = rotate_horizontal(c1.raw, a1, c2.raw, a2, (az + k) % 360.0)
        out.append(r.copy() if raw else process(r, processing))
    names = " and ".join(f"{c.name} ({Path(files[c.files[0]].path).name})" for c in (c1, c2))
    text = f"{names}, rotated to azimuths {az % 360.0:.0f} and {(az + 90.0) % 360.0:.0f} deg"
    return (out[0], out[1]), text


def _part_source(files: Sequence[RecordFile], p: _Candidate) -> dict[str, Any]:
    """File, sha256, component and azimuth of one component of a rotation (a partner file's too,
    which is not processed on its own)."""
    from isorock.store import file_sha256

    if p.rec is not None:
        path, sha = p.rec.source.file, p.rec.source.sha256
    else:
        path = str(Path(files[p.files[0]].path).resolve())
        sha = file_sha256(path)
    return {"file": path, "sha256": sha, "component": p.name, "azimuth_deg": p.azimuth_deg}


def _with_orientation(rec: Any, component: str, azimuth: float | None) -> Any:
    """The record with the label and azimuth of its direction in its provenance."""
    return type(rec)(rec.raw, rec.trace, replace(rec.source, component=component, azimuth_deg=azimuth))
