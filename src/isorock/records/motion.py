"""From a record file to the ground motion the engine analyses: the one path every entry point takes.

``isorock simulate``, ``min-overturn``, ``map``, ``info`` and ``pulse``, the Python API and the
workflow's ``process_record`` all call :func:`load_record`: read the file
(:func:`isorock.io.read_trace`: format detected or named, units from the header when it states them
and otherwise required), apply the processing steps (the packaged ``processing.yaml`` unless another
configuration is named; ``raw=True`` skips them), and keep the provenance of the result
(:class:`RecordSource`: file, sha256, format, units and where they came from, component, processing
steps), which every JSON and HDF5 output carries. The same file and options therefore give the same
samples, bit for bit, wherever they are read.

Example
-------
>>> from isorock import load_motion                                        # doctest: +SKIP
>>> gm = load_motion("RSN77_SFERN_PUL164-hor1.AT2")                        # doctest: +SKIP
>>> gm.pga_g, gm.meta["record"]["processing"][0]                           # doctest: +SKIP
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from obspy import Trace

from isorock.io import read_trace, trace_component, trace_station
from isorock.physics.excitation import GroundMotion
from isorock.processing import AppliedStep, ProcessingConfig, applied_steps, process
from isorock.store import file_sha256

__all__ = ["RecordSource", "LoadedRecord", "load_record", "load_motion", "record_source"]


@dataclass(frozen=True)
class RecordSource:
    """Provenance of a ground motion read from a file.

    Attributes
    ----------
    file : str
        Absolute path of the file.
    sha256 : str
        sha256 of the file's bytes.
    format : str
        Format it was read as (``peer-at2``, ``bbp``, ``one-column`` ...).
    units : str
        Units of the values in the file (``g``, ``m/s2``, ``cm/s2``, ``mm/s2``).
    units_source : str
        ``"header"`` (the file states them) or ``"given"`` (the caller did).
    component : str
        Component read ("" for a file with one unnamed component).
    station : str
        Station name as the file gives it.
    processing : list of str or None
        One line per processing step applied, for people; None for the raw record.
    steps : list of AppliedStep or None
        The same steps, structured (``step``, ``parameters``, ``note``:
        :class:`isorock.processing.AppliedStep`); None for the raw record.
    dt_s : float
        Time step [s].
    npts : int
        Samples [-].
    azimuth_deg : float or None
        Azimuth of the component analysed [deg clockwise from north], when known.
    rotated_from : list of dict or None
        For a component rotated from two recorded ones (:mod:`isorock.records.components`): each one's
        ``file``, ``sha256``, ``component`` and ``azimuth_deg``; ``file`` and ``sha256`` above are
        then the first one's.
    """

    file: str
    sha256: str
    format: str
    units: str
    units_source: str
    component: str
    station: str
    processing: list[str] | None = field(default=None)
    dt_s: float = 0.0
    npts: int = 0
    azimuth_deg: float | None = None
    rotated_from: list[dict[str, Any]] | None = None
    steps: list[AppliedStep] | None = None

    @property
    def raw(self) -> bool:
        """True when no processing step was applied."""
        return self.processing is None

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form; ``processing`` is ``"none (raw record)"`` for a raw record."""
        d = asdict(self)
        if self.processing is None:
            d["processing"] = "none (raw record)"
        return d


@dataclass
class LoadedRecord:
    """A record read and processed: the traces, the ground motion and its provenance.

    Attributes
    ----------
    raw : obspy.Trace
        The record as read [m/s^2].
    trace : obspy.Trace
        The record analysed: processed, or a copy of ``raw`` when processing was skipped [m/s^2].
    source : RecordSource
        Provenance.
    """

    raw: Trace
    trace: Trace
    source: RecordSource

    @property
    def motion(self) -> GroundMotion:
        """The :class:`~isorock.physics.excitation.GroundMotion` of :attr:`trace`; ``meta["record"]`` is the
        provenance (:meth:`RecordSource.to_dict`)."""
        comp = self.source.component
        name = Path(self.source.file).name + (f":{comp}" if comp else "")
        return GroundMotion(
            dt=float(self.trace.stats.delta),
            acc=np.asarray(self.trace.data, dtype=float),
            name=name,
            meta={"record": self.source.to_dict()},
        )


def load_record(
    path: str | Path,
    *,
    format: str | None = None,
    dt: float | None = None,
    units: str | None = None,
    component: str | None = None,
    processing: ProcessingConfig | str | Path | None = None,
    raw: bool = False,
) -> LoadedRecord:
    """Read a record file and process it: the one way from a file to a ground motion.

    Parameters
    ----------
    path : str or Path
        The record file.
    format : str, optional
        Format name (:data:`isorock.io.FORMATS`); detected when None.
    dt : float, optional
        Time step [s], for files that do not state it (checked against files that do).
    units : str, optional
        Units of the values, for files that do not state them (a conflict with the header is an
        error).
    component : str, optional
        Component of a multi-component file.
    processing : ProcessingConfig, path or None
        Processing steps; None: the packaged default (``isorock/processing/processing.yaml``).
    raw : bool
        Skip the processing (the record is analysed as read).

    Returns
    -------
    LoadedRecord

    Raises
    ------
    RecordError
        Unreadable file, missing time step, units or component (all named at once).
    """
    tr = read_trace(path, format, dt=dt, units=units, component=component)
    analysed = tr.copy() if raw else process(tr, processing)
    return LoadedRecord(raw=tr, trace=analysed, source=record_source(path, tr, analysed, raw))


def record_source(path: str | Path, tr: Trace, analysed: Trace, raw: bool) -> RecordSource:
    """The provenance of ``analysed``, the trace ``tr`` read from ``path`` and processed (or not)."""
    info = tr.stats.isorock
    return RecordSource(
        file=str(Path(str(path)).resolve()),
        sha256=file_sha256(path),
        format=str(info.get("format", "")),
        units=str(info.get("units", "")),
        units_source=str(info.get("units_source", "given")),
        component=trace_component(tr),
        station=trace_station(tr),
        processing=None if raw else [str(s) for s in analysed.stats.get("processing", [])],
        dt_s=float(analysed.stats.delta),
        npts=int(analysed.stats.npts),
        steps=None if raw else applied_steps(analysed),
    )


def load_motion(path: str | Path, **kw: Any) -> GroundMotion:
    """The ground motion of a record file, processed (see :func:`load_record` for the options)."""
    return load_record(path, **kw).motion
