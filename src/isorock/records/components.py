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
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

from obspy import Trace

from isorock.errors import IsorockError
from isorock.records.candidates import Candidate, find_candidates, pair_check, same_recording
from isorock.records.naming import line_angle
from isorock.records.spec import RecordFile, Target

# the processing and the records' provenance (scipy, ObsPy filters) are imported where they are used:
# a run that only plans its jobs (the Snakefile parse) reads spec.py, not this module

__all__ = [
    "ALIGNED_DEG",
    "METHODS",
    "ComponentChoice",
    "choose_component",
]

#: a recorded component this close to the wanted direction [deg] is taken as it (cos 5 deg = 0.996)
ALIGNED_DEG = 5.0
#: how the analysed direction was obtained, best first (the rank of a candidate)
METHODS = ("provided", "rotated", "aligned", "as recorded")
#: a PGA or PGV this far from the catalog's (ratio or its inverse) is noted
_TABLE1_RATIO = 1.5


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


def _classify(c: Candidate, target: Target) -> None:
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


def _qa_mark(c: Candidate, target: Target) -> str:
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
    every_single: list[Candidate] = []
    cands = find_candidates(files, target, problems, refused, every_single)
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

    def consistent(c: Candidate) -> bool:
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
    cands: Sequence[Candidate],
    best: Candidate,
    processing: Any,
    raw: bool,
    every_single: Sequence[Candidate] = (),
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
        singles: list[Candidate] = []
        for c in [*cands, *every_single]:  # a partner file (a PEER search's second horizontal) too
            for x in c.parts if c.method == "rotated" else (c,):
                if all(x is not y for y in singles):
                    singles.append(x)
        mates = [
            c
            for c in singles
            if c is not best and not c.provided and not best.provided and same_recording(files, best, c)
        ]
        pair = None
        for c in mates:
            ok, _, _ = pair_check(files, best, c, Target(azimuth_deg=best.azimuth_deg))
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


def _part_source(files: Sequence[RecordFile], p: Candidate) -> dict[str, Any]:
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
