"""The candidates for the component analysed of a record: every horizontal of its own files, and the
pairs of one recording rotated to the direction its catalog row asks for, where their azimuths are
known and they are time-aligned (:func:`isorock.records.files.check_alignment`)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from obspy import Trace

from isorock.errors import IsorockError
from isorock.io import trace_component
from isorock.records.files import PAIR_MIN_DEG, Alignment, azimuth_of, check_alignment, read_horizontals
from isorock.records.naming import is_vertical, line_angle, provided_orientation
from isorock.records.spec import RecordFile, Target

__all__ = ["Candidate", "find_candidates", "pair_check", "same_recording"]


@dataclass
class Candidate:
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
    parts: tuple[Candidate, ...] = ()


def find_candidates(
    files: Sequence[RecordFile],
    target: Target,
    problems: list[dict],
    refused: list[str],
    every_single: list[Candidate] | None = None,
) -> list[Candidate]:
    """Every single component of the row's own files, then the rotated pairs (a partner file only in
    a pair); ``refused`` gets one line per pair of one recording that could not be rotated, and
    ``every_single`` (where given) every single horizontal read, a partner file's too."""
    singles: list[Candidate] = []
    seen: set[tuple[str, str]] = set()
    for i, f in enumerate(files):
        try:
            traces = read_horizontals(f)
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
            singles.append(Candidate(tr, (i,), name, azimuth_of(f, tr, single), provided))
    pairs: list[Candidate] = []
    if target.azimuth_deg is not None:
        for a in range(len(singles)):
            for b in range(a + 1, len(singles)):
                c1, c2 = singles[a], singles[b]
                ok, why, al = pair_check(files, c1, c2, target)
                if ok:
                    pairs.append(_rotated(files, c1, c2, target, al))
                elif why:
                    refused.append(why)
    own = [c for c in singles if not files[c.files[0]].partner]
    if every_single is not None:
        every_single.extend(singles)
    return own + pairs


def same_recording(files: Sequence[RecordFile], c1: Candidate, c2: Candidate) -> bool:
    """Two components of one file, or of two files of one station and format (not both partners)."""
    f1, f2 = files[c1.files[0]], files[c2.files[0]]
    if f1.partner and f2.partner:
        return False
    if f1.path == f2.path:
        return True
    st1, st2 = f1.station.strip().lower(), f2.station.strip().lower()
    return bool(st1) and st1 == st2 and (f1.format or "") == (f2.format or "")


def pair_check(
    files: Sequence[RecordFile], c1: Candidate, c2: Candidate, target: Target
) -> tuple[bool, str, Alignment | None]:
    """Whether two components may be rotated together to the target.

    Returns ``(ok, why, alignment)``: ``why`` is "" when the two are simply not a pair (a component
    its provider rotated, two recordings, two near-parallel components), else the reason a pair of
    one recording is refused (an azimuth not known, not time-aligned: :func:`check_alignment`).
    """
    if c1.provided or c2.provided or not same_recording(files, c1, c2):
        return False, "", None
    az1, az2 = c1.azimuth_deg, c2.azimuth_deg
    if az1 is not None and az2 is not None and line_angle(az1, az2) < PAIR_MIN_DEG:
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
    files: Sequence[RecordFile], c1: Candidate, c2: Candidate, target: Target, al: Alignment | None
) -> Candidate:
    from isorock.processing.orientation import rotate_horizontal

    a1, a2, az_target = c1.azimuth_deg, c2.azimuth_deg, target.azimuth_deg
    # find_candidates pairs only components of known azimuths (pair_check), for a target of known azimuth
    assert a1 is not None and a2 is not None and az_target is not None
    az = float(az_target)
    raw = rotate_horizontal(c1.raw, a1, c2.raw, a2, az)
    n1, n2 = c1.raw.stats.npts, c2.raw.stats.npts
    cut = f"; lengths differ by {abs(n1 - n2)} samples: aligned at the first sample" if n1 != n2 else ""
    names = " and ".join(f"{c.name} ({Path(files[c.files[0]].path).name})" for c in (c1, c2))
    c = Candidate(raw, c1.files + c2.files, target.label, az, None, method="rotated", angle_deg=0.0)
    c.parts = (c1, c2)
    timing = f", {al.describe()}" if al is not None else ""
    c.text = f"rotated from {names} to {target.describe()}{timing}{cut}"
    return c
