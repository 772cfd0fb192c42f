"""The vertical component of a recording, beside its horizontal pair (issue 24, records part).

A record set often carries the vertical motion too: a PEER set has an ``UP``/``DWN``/``V`` file beside
its two horizontals, a BBP file has a ``U-D`` column, a MiniSEED file a ``Z`` channel. :func:`find_vertical`
looks for it among the files of one recording (a catalog row's files, or the files of an added
record) and checks it before it is used:

- it must be a recording of its own: a column that repeats a horizontal sample for sample (the U-D
  column of four of the five BBP files of ``../shared/records`` repeats their N-S column) is refused,
  and so is one that correlates above :data:`COPY_CORRELATION` with a horizontal of the same recording;
- it must be time-aligned with the horizontal analysed, by the test the horizontal pair passes
  (:func:`isorock.records.components.check_alignment`: the same time step, the same stated start,
  lengths within 1 % (:data:`VERTICAL_LENGTH_RTOL`) rather than 0.5 %), without its energy-envelope
  item: a vertical's energy arrives with the P waves, before the horizontal's (the lag is measured
  and kept);
- it is processed by the same steps as the horizontal (:func:`isorock.processing.process`), so that the
  two are filtered and corrected alike;
- it is put positive up, the engine's sense of ``a_v`` (docs/model.md §17), from the sense its file
  states (:func:`vertical_polarity`): a component named ``DWN``/``DOWN``/``DN`` (the Pacoima Dam
  vertical of 1971 in PEER's NGA-West2 file ``RSN77_SFERN_PULDWN``) is positive down and its sign is
  reversed; ``UP`` is positive up; a name that states no sense (``U-D``, ``V``, ``Z``, ``HNZ``) is
  taken positive up. A user who knows better states it (``--vertical-positive up|down``).

The result names what was found and, for each candidate refused, why (:class:`VerticalSearch`); nothing
here decides whether the vertical is used (the engine's ``--vertical``, the configuration's
``records.vertical``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from obspy import Trace

from isorock.errors import IsorockError
from isorock.io import read_record, read_trace, trace_component
from isorock.physics.excitation import GroundMotion
from isorock.records.files import Alignment, check_alignment
from isorock.records.naming import VerticalPolarity, is_vertical, vertical_polarity
from isorock.records.spec import RecordFile

__all__ = [
    "VerticalComponent",
    "VerticalSearch",
    "find_vertical",
    "is_copy",
    "COPY_CORRELATION",
]

#: the largest relative difference of length between a vertical and the horizontal analysed [-]: the
#: files of a PEER set are trimmed apart (El Centro 1940: the UP file is 6 samples longer than the 180
#: file and 32 (0.6 %) longer than the 270 file, which the pair test's 0.5 % would refuse)
VERTICAL_LENGTH_RTOL = 0.01
#: a vertical candidate that correlates above this with a horizontal of its recording is a copy of it
#: (two real components of one recording correlate far less: 0.1 to 0.5 for the Table 1 sets)
COPY_CORRELATION = 0.999


@dataclass(frozen=True)
class VerticalComponent:
    """A vertical component found beside a horizontal one, checked.

    Attributes
    ----------
    trace : obspy.Trace
        The vertical as read [m/s^2, in the sense its file gives it: :attr:`polarity`].
    file : str
        Its file.
    component : str
        Its name in the file (``UP``, ``DWN``, ``U-D``, ``HNZ`` ...).
    alignment : Alignment
        Its time alignment with the horizontal.
    positive : {"up", "down"} or None
        The sense of the file's samples as the user states it (None: from :attr:`component`).
    """

    trace: Trace
    file: str
    component: str
    alignment: Alignment
    positive: str | None = None

    @property
    def polarity(self) -> VerticalPolarity:
        """The sense of the file's samples and the sign that puts them positive up
        (:func:`vertical_polarity`)."""
        return vertical_polarity(self.component, self.positive)

    @property
    def pga_g(self) -> float:
        """Peak vertical acceleration of the trace as read [g]."""
        from isorock.constants import G

        return float(np.max(np.abs(self.trace.data))) / G

    def motion(self, processing: Any = None, *, raw: bool = False) -> GroundMotion:
        """The vertical ground motion, processed by the steps of the horizontal.

        Parameters
        ----------
        processing : ProcessingConfig, path or None
            The processing steps of the horizontal (None: the packaged default).
        raw : bool
            As read, unprocessed (as the horizontal with ``--raw``).

        Returns
        -------
        GroundMotion
            Vertical acceleration [m/s^2, positive up: the file's samples times
            :attr:`polarity`'s sign, before processing]; ``meta["vertical"]`` holds the file, the
            component, the processing applied and the polarity (``positive_in_file``, ``sign``,
            ``polarity``: :meth:`VerticalPolarity.to_dict`).
        """
        from isorock.processing import process

        pol = self.polarity
        up = self.trace.copy()
        if pol.sign < 0:
            up.data = -np.asarray(up.data, dtype=float)
        tr = up if raw else process(up, processing)
        steps = [] if raw else [str(x) for x in tr.stats.get("processing", [])]
        info = {"file": self.file, "component": self.component, "processing": steps, **pol.to_dict()}
        return GroundMotion(
            dt=float(tr.stats.delta),
            acc=np.asarray(tr.data, dtype=float),
            name=f"{Path(self.file).name}:{self.component}",
            meta={"vertical": info},
        )


@dataclass(frozen=True)
class VerticalSearch:
    """What :func:`find_vertical` found.

    Attributes
    ----------
    found : VerticalComponent or None
        The vertical (None: the recording has none that passes).
    refused : list of str
        One line per candidate refused, with why.
    """

    found: VerticalComponent | None
    refused: list[str] = field(default_factory=list)

    def describe(self) -> str:
        """One line: what was found, or why none."""
        if self.found is not None:
            v = self.found
            return (
                f"vertical {v.component} of {Path(v.file).name}: peak {v.pga_g:.3g} g, "
                f"{v.alignment.describe()}; {v.polarity.why}"
            )
        return "no vertical component" + (f" ({'; '.join(self.refused)})" if self.refused else "")


def is_copy(vertical: Any, horizontal: Any) -> bool:
    """True when ``vertical`` repeats ``horizontal``: the same samples, or a correlation above
    :data:`COPY_CORRELATION` over their common length (either sign)."""
    a, b = np.asarray(vertical, dtype=float), np.asarray(horizontal, dtype=float)
    n = min(a.size, b.size)
    if n < 2:
        return False
    a, b = a[:n], b[:n]
    if np.array_equal(a, b) or np.array_equal(a, -b):
        return True
    sa, sb = np.std(a), np.std(b)
    if sa == 0 or sb == 0:
        return False
    r = float(np.mean((a - a.mean()) * (b - b.mean())) / (sa * sb))
    return abs(r) > COPY_CORRELATION


def _traces(f: RecordFile) -> tuple[list[Trace], list[Trace]]:
    """The vertical and the horizontal traces of one file, raw [m/s^2]."""
    if f.format in (None, "bbp", "mseed", "MSEED"):
        try:
            st = read_record(f.path, f.format, dt=f.dt_s, units=f.units)
        except IsorockError:
            st = None
        if st is not None and len(st) > 1:
            vertical = [tr for tr in st if is_vertical(trace_component(tr))]
            return vertical, [tr for tr in st if tr not in vertical]
    tr = read_trace(f.path, f.format, dt=f.dt_s, units=f.units, component=f.component)
    name = trace_component(tr) or f.component_name
    if is_vertical(name) or is_vertical(f.component_name):
        return [tr], []
    return [], [tr]


def find_vertical(
    files: Sequence[RecordFile],
    horizontal: Trace,
    horizontal_file: str | Path | None = None,
    positive: str | None = None,
) -> VerticalSearch:
    """The vertical component of the recording of ``files``, beside the horizontal ``horizontal``.

    Parameters
    ----------
    files : sequence of RecordFile
        The files of one recording (a catalog row's, or an added record's), horizontals and verticals.
    horizontal : obspy.Trace
        The horizontal component analysed, raw [m/s^2] (its alignment is what the vertical must meet).
    horizontal_file : path-like, optional
        The file it was read from: a vertical of the same file shares its time column.
    positive : {"up", "down"} or None
        The sense of the vertical's samples as the user states it (None: as its name states,
        :func:`vertical_polarity`).

    Returns
    -------
    VerticalSearch
        The first vertical that is no copy and is aligned with ``horizontal``, and why the others
        were refused.
    """
    if positive is not None:
        vertical_polarity(None, positive)  # refuse a sense other than up or down before reading
    refused: list[str] = []
    found: VerticalComponent | None = None
    read = []
    for f in files:
        try:
            read.append((f, *_traces(f)))
        except IsorockError as exc:
            refused.append(f"{Path(f.path).name}: {str(exc).splitlines()[0]}")
    horizontals = [h for _, _, hs in read for h in hs]
    for f, verticals, own in read:
        for v in verticals:
            name = trace_component(v) or f.component_name
            label = f"{Path(f.path).name}:{name}"
            copied = next((h for h in own + horizontals if is_copy(v.data, h.data)), None)
            if copied is not None:
                refused.append(f"{label} repeats the horizontal {trace_component(copied)}: no vertical")
                continue
            same_file = (
                horizontal_file is not None and Path(horizontal_file).resolve() == Path(f.path).resolve()
            )
            al = check_alignment(
                horizontal, v, one_file=same_file, envelopes=False, length_rtol=VERTICAL_LENGTH_RTOL
            )
            if not al.ok:
                refused.append(f"{label} {al.describe()}")
                continue
            if found is None:
                found = VerticalComponent(
                    trace=v, file=f.path, component=name, alignment=al, positive=positive
                )
    return VerticalSearch(found, refused)


def sibling_files(path: str | Path, fmt: str | None = None) -> list[RecordFile]:
    """The files that may hold the vertical of the record file ``path``: the file itself (a BBP file's
    U-D column, a MiniSEED file's Z channel) and the files beside it of its recording that a name
    marks as vertical (``..._PULDWN-up.AT2`` beside ``..._PUL164-hor1.AT2``, PEER's
    ``RSN6_IMPVALL.I_I-ELC-UP.AT2`` beside ``RSN6_IMPVALL.I_I-ELC180.AT2``: the same extensions and the
    same name up to its last ``_``)."""
    from isorock.records.naming import component_from_name, file_stem

    def extensions(name: str) -> str:  # ".AT2", ".AT2.g3": a dot inside the name is no extension
        return name[len(file_stem(name)) :].lower()

    p = Path(path)
    out = [RecordFile(path=str(p.resolve()), format=fmt)]
    stem = p.name
    cut = stem.rfind("_")
    prefix = stem[: cut + 1] if cut > 0 else ""
    if not prefix or not p.parent.is_dir():
        return out
    for q in sorted(p.parent.iterdir()):
        if (
            q == p
            or not q.is_file()
            or not q.name.startswith(prefix)
            or extensions(q.name) != extensions(p.name)
        ):
            continue
        comp = component_from_name(q.name)
        if is_vertical(comp):
            out.append(RecordFile(path=str(q.resolve()), format=fmt, component_name=comp or ""))
    return out


def with_vertical(motion: GroundMotion, vertical: GroundMotion, what: str) -> GroundMotion:
    """``motion`` carrying ``vertical`` (processed alike) sample for sample.

    Both start at their first sample (their alignment was checked); a vertical a few samples longer
    is cut to the horizontal's length and a shorter one is continued with zeros, and ``meta["vertical"]``
    says how many. ``what`` names the vertical in errors.

    Raises
    ------
    IsorockError
        Another time step, or lengths more than :data:`VERTICAL_LENGTH_RTOL` apart.
    """
    if abs(vertical.dt - motion.dt) > 1e-9 * motion.dt:
        raise IsorockError(f"{what}: time step {vertical.dt:g} s, the horizontal's {motion.dt:g} s")
    n = motion.npts
    if abs(vertical.npts - n) > VERTICAL_LENGTH_RTOL * n:
        raise IsorockError(
            f"{what}: {vertical.npts} samples, the horizontal {n}: more than "
            f"{VERTICAL_LENGTH_RTOL:.0%} apart, not one recording"
        )
    v = vertical.acc[:n]
    if v.size < n:
        v = np.concatenate([v, np.zeros(n - v.size)])
    info = dict(vertical.meta.get("vertical", {}))
    info.update(
        samples=vertical.npts,
        cut=max(0, vertical.npts - n),
        padded=max(0, n - vertical.npts),
        peak_g=vertical.pga_g,
    )
    return GroundMotion(motion.dt, motion.acc, motion.name, {**motion.meta, "vertical": info}, v)


def vertical_from_file(
    path: str | Path,
    horizontal: Trace,
    *,
    fmt: str | None = None,
    dt: float | None = None,
    units: str | None = None,
    positive: str | None = None,
) -> VerticalComponent:
    """The vertical given as a file (``--vertical FILE``), read as the horizontal's file is (``fmt``,
    ``dt`` [s], ``units``: the record's file options) and checked as :func:`find_vertical` checks one;
    ``positive`` states the sense of its samples (None: as its name states, :func:`vertical_polarity`).

    Raises
    ------
    IsorockError
        The file holds no single vertical, or it is a copy of the horizontal, or not aligned with it.
    """
    traces = read_record(path, fmt, dt=dt, units=units)
    verts = [tr for tr in traces if is_vertical(trace_component(tr))]
    if len(traces) == 1:
        verts = list(traces)
    if len(verts) != 1:
        raise IsorockError(f"{path}: {len(verts)} vertical components in the file: give a file with one")
    v = verts[0]
    if is_copy(v.data, horizontal.data):
        raise IsorockError(f"{path}: repeats the horizontal sample for sample: no vertical")
    al = check_alignment(horizontal, v, one_file=False, envelopes=False, length_rtol=VERTICAL_LENGTH_RTOL)
    if not al.ok:
        raise IsorockError(f"{path}: {al.describe()}")
    comp = trace_component(v) or ""
    return VerticalComponent(trace=v, file=str(path), component=comp, alignment=al, positive=positive)


def vertical_beside(
    files: Sequence[RecordFile],
    raw: Trace,
    raw_file: str | Path,
    analysed: Trace,
    processing: Any = None,
    positive: str | None = None,
) -> tuple[GroundMotion | None, dict[str, Any]]:
    """The vertical of a recording for the store: found beside the horizontal (:func:`find_vertical`;
    a rotation of the horizontals leaves the vertical as it is, so it is looked for beside its inputs),
    processed by the same steps and put on the samples of the horizontal analysed.

    Parameters
    ----------
    files : sequence of RecordFile
        The files of the recording.
    raw : obspy.Trace
        The horizontal as read (what the vertical's alignment is checked against) [m/s^2].
    raw_file : path-like
        The file it was read from.
    analysed : obspy.Trace
        The horizontal analysed, processed [m/s^2].
    processing : ProcessingConfig, path or None
        The processing steps of the horizontal.
    positive : {"up", "down"} or None
        The sense of the vertical's samples as the user states it (None: as its name states).

    Returns
    -------
    motion : GroundMotion or None
        The horizontal analysed carrying the vertical, positive up (None: none found or usable);
        ``meta["vertical"]`` says the sense of the file's samples and the sign applied.
    attrs : dict
        ``vertical_component`` (``file:component``, "" if none), ``vertical_pga_g`` [g],
        ``vertical_pgv_m_s`` [m/s] (NaN if none), ``vertical_note`` (how it was found, with the sense
        taken and why, or why none), and ``_lines`` (what to log).
    """
    from isorock.processing import metrics

    nan = float("nan")
    none: dict[str, Any] = {"vertical_component": "", "vertical_pga_g": nan, "vertical_pgv_m_s": nan}
    found = find_vertical(files, raw, raw_file, positive)
    if found.found is None:
        return None, {**none, "vertical_note": found.describe(), "_lines": []}
    vc = found.found
    dt = float(analysed.stats.delta)
    try:
        gm = with_vertical(
            GroundMotion(dt, np.asarray(analysed.data, dtype=float)), vc.motion(processing), vc.file
        )
    except IsorockError as exc:
        note = f"{Path(vc.file).name}:{vc.component} refused: {exc}"
        return None, {**none, "vertical_note": note, "_lines": [note]}
    vtr = analysed.copy()
    vtr.data = np.asarray(gm.vertical, dtype=float)
    m = metrics(vtr)
    info = gm.meta["vertical"]
    note = found.describe() + f"; {info['cut']} samples cut, {info['padded']} padded"
    return gm, {
        "vertical_component": f"{Path(vc.file).name}:{vc.component}",
        "vertical_pga_g": float(m["pga_g"]),
        "vertical_pgv_m_s": float(m["pgv_m_s"]),
        "vertical_note": note,
        "_lines": [note],
    }
