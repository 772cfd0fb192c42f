"""The rule bodies of the records part of the workflow: process a record and extract its pulse (one
job, rule ``process_record``), find its minimum overturning PGA, compute its regime maps. Each takes
paths and configuration dicts and writes one HDF5 file atomically (:mod:`isorock.store`); each
job's output goes to its log through :func:`isorock.control.joblog.script_logging`.

The modules that only one rule needs (processing and ObsPy for ``process_record``, the pulse
extraction, the regime maps) are imported by that rule's function: every job is a Python process of
its own, and its imports are part of its time."""

from __future__ import annotations

import dataclasses
import json
import math
import os
import time
from collections.abc import Mapping, Sequence
from typing import Any

import h5py
import numpy as np
import pandas as pd

from isorock.control.config import case_from
from isorock.control.joblog import say
from isorock.control.plan import RecordSpec
from isorock.errors import IsorockError
from isorock.physics.excitation import Excitation, GroundMotion
from isorock.physics.model import Block, System
from isorock.physics.overturning import min_overturn_amplitude
from isorock.store import (
    OVERTURN_COLUMNS,
    atomic_path,
    attach_dims,
    attrs_dict,
    config_hash,
    dimension,
    record_attrs_in_order,
    set_attrs,
    stamp,
    time_coordinate,
    write_map,
    write_tables,
)
from isorock.version import __version__

__all__ = [
    "process_record",
    "process_records",
    "extract_pulse",
    "min_overturn",
    "regime_maps",
    "search_row",
    "block_columns",
    "map_name_lr",
]


def _check_lengths(spec: RecordSpec, max_samples: int | None, max_duration_s: float | None) -> None:
    """Refuse a record whose file is too long for the bounds
    (:func:`isorock.control.lengths.record_lengths`)."""
    from isorock.control.lengths import record_lengths
    from isorock.records.directory import MAX_DURATION_S, MAX_SAMPLES

    bounds = {
        "max_samples": MAX_SAMPLES if max_samples is None else int(max_samples),
        "max_duration_s": MAX_DURATION_S if max_duration_s is None else float(max_duration_s),
    }
    record_lengths([spec], {"records": bounds})


def _rotd_of(rid: str, ch: Any, imts: Sequence[str]) -> dict[str, str]:
    """The attributes ``rotd_pair``, ``rotd50``, ``rotd100`` of a record (JSON; empty without a pair)."""
    from isorock.processing.imt import rotd_of_traces

    if ch.pair is None:
        say(f"{rid}: one horizontal only (or its two could not be paired): no RotD50 or RotD100")
        return {"rotd_pair": "", "rotd50": "{}", "rotd100": "{}"}
    vals, lines = rotd_of_traces(ch.pair, imts)
    for line in lines:
        say(f"{rid}: {line}")
    said = ", ".join(f"{m} {v:.3g}" for m, v in vals["rotd50"].items())
    say(f"{rid}: RotD50 of {ch.pair_description}: {said}")
    return {
        "rotd_pair": ch.pair_description,
        "rotd50": json.dumps(vals["rotd50"]),
        "rotd100": json.dumps(vals["rotd100"]),
    }


def process_record(
    spec: Mapping | RecordSpec,
    out: str | os.PathLike,
    *,
    processing: str | None = None,
    choose: str = "table1_pgv",
    max_samples: int | None = None,
    max_duration_s: float | None = None,
    rotd_imts: Sequence[str] = ("PGA", "PGV"),
) -> dict:
    """Rule ``process_record``: read the record's file(s), choose its component, write ``/records/<id>``.

    :func:`isorock.records.components.choose_component` reads every file of the record, rotates two
    horizontal components of one recording to the catalog row's direction (SN/SP from the row's
    strike, or its azimuth), processes every candidate and picks one: QA passed first, then the
    direction obtained best (provided, rotated, aligned, as recorded), then the PGV closest to the
    catalog's (``choose="table1_pgv"``) or the manifest order (``"first"``). Files that fail to read
    are noted and skipped. The component analysed, its azimuth, how it was obtained and a QA mark
    when it is not the row's direction are written with the record.

    Parameters
    ----------
    spec : RecordSpec or dict
        The record (as given by :func:`plan`).
    out : path-like
        HDF5 file written (atomically) with the group ``/records/<id>``: the ``process_record``
        attributes of :data:`isorock.store.RECORD_ATTRS` (among them ``processing_json``, the steps
        applied), the processed acceleration ``acc`` [m/s^2] and the history lines ``processing``
        (layout in :mod:`isorock.store`).
    processing : str, optional
        Processing YAML (None: the packaged steps).
    choose : {"table1_pgv", "first"}
        Order among candidates of equal rank.
    max_samples, max_duration_s : int, float, optional
        The longest record processed (``records.max_samples``, ``records.max_duration_s``; default
        :data:`isorock.records.directory.MAX_SAMPLES`, ``MAX_DURATION_S``): a file too large for it is
        refused unread, a longer record before its processing. ``isorock report`` refuses such a
        record before any job; this guards a ``snakemake`` run by hand.
    rotd_imts : sequence of str
        The measures whose RotD50 and RotD100 are computed from the record's two horizontals
        (:func:`isorock.processing.imt.rotd`; attributes ``rotd50``, ``rotd100``, ``rotd_pair``); a
        period of SA the record does not support is left out with a line in the log.

    Returns
    -------
    dict
        The attributes written.

    Raises
    ------
    IsorockError
        No candidate file could be read (the message lists why).
    """
    from isorock.processing import applied_steps, metrics, qa_passed, qa_reasons, steps_to_json
    from isorock.records.components import choose_component
    from isorock.records.vertical import vertical_beside

    spec = spec if isinstance(spec, RecordSpec) else RecordSpec.from_dict(spec)
    _check_lengths(spec, max_samples, max_duration_s)
    # the record's lowest usable frequency (PEER's) raises the high-pass corner: the history says so
    from isorock.processing import with_lowest_usable_frequency

    record_processing = with_lowest_usable_frequency(processing, spec.metadata.luf_hz)
    try:
        ch = choose_component(
            spec.files,
            spec.target,
            processing=record_processing,
            choose=choose,
            table1_pga_g=spec.table1_pga_g,
            table1_pgv_m_s=spec.table1_pgv_m_s,
            pairs=True,
        )
    except IsorockError as exc:
        raise IsorockError(f"record {spec.id}: {exc}") from None
    rot = _rotd_of(spec.id, ch, rotd_imts)
    for info in ch.candidates:
        if not info["ok"]:
            say(f"{spec.id}: {info['file']} cannot be used: {info['problem']}")
    tr, src, f = ch.record.trace, ch.record.source, ch.file
    m = metrics(tr)
    say(f"{spec.id}: {ch.description} (PGA {m['pga_g']:.3f} g, PGV {m['pgv_m_s']:.3f} m/s)")
    for line in (ch.qa_mark, ch.table1_check):
        if line:
            say(f"{spec.id}: QA mark: {line}")
    nan = math.nan
    vert, vinfo = vertical_beside(spec.files, ch.record.raw, ch.file.path, tr, record_processing)
    for line in vinfo.pop("_lines"):
        say(f"{spec.id}: {line}")
    values = {
        "id": spec.id,
        "label": spec.label,
        "event": spec.event,
        "year": spec.year if spec.year is not None else -1,
        "station": spec.station,
        "component": ch.component,
        "azimuth_deg": nan if ch.azimuth_deg is None else float(ch.azimuth_deg),
        "component_method": ch.method,
        "component_description": ch.description,
        "component_qa": ch.qa_mark,
        "table1_component": spec.component if spec.catalog_id else "",
        "target_azimuth_deg": nan if ch.target.azimuth_deg is None else float(ch.target.azimuth_deg),
        "strike_deg": nan if spec.strike_deg is None else float(spec.strike_deg),
        "strike_source": spec.strike_source,
        "tp_source": spec.tp_source,
        **spec.metadata.store_attrs(),
        "catalog_id": spec.catalog_id,
        "record_source": spec.source,
        "source_file": f.path,
        "rotated_from": json.dumps(src.rotated_from or []),
        "source_format": src.format,
        "file_units": src.units,
        "file_units_source": src.units_source,
        "file_component": ch.recorded_component,
        "record_sha256": src.sha256,
        "candidates": ch.candidates,
        "substitute": bool(f.substitute),
        "npts": int(m["npts"]),
        "dt_s": float(m["dt_s"]),
        "duration_s": float(m["duration_s"]),
        "pga_g": float(m["pga_g"]),
        "pga_m_s2": float(m["pga_m_s2"]),
        "pgv_m_s": float(m["pgv_m_s"]),
        "pgd_m": float(m["pgd_m"]),
        "arias_m_s": float(m["arias_m_s"]),
        "d5_95_s": float(m["d5_95_s"]),
        "final_disp_m": float(m["final_disp_m"]),
        **vinfo,
        **rot,
        "qa_passed": bool(qa_passed(tr)),
        "qa_reasons": qa_reasons(tr),
        "table1_pga_g": spec.table1_pga_g,
        "table1_pgv_m_s": spec.table1_pgv_m_s,
        "table1_tp_s": spec.table1_tp_s,
        "table1_check": ch.table1_check,
        "processing_json": steps_to_json(applied_steps(tr)),
        "config_hash": config_hash(
            {"spec": spec.to_dict(), "processing": processing, "choose": choose, "rotd": list(rotd_imts)}
        ),
        "isorock_version": __version__,
        "units": json.dumps(
            {"acc": "m/s^2", "dt_s": "s", "pga_g": "g", "pgv_m_s": "m/s", "pgd_m": "m", "azimuth_deg": "deg"}
        ),
    }
    attrs = record_attrs_in_order(values, "process_record")  # exactly the spec's (isorock.store.RECORD_ATTRS)
    if not attrs["qa_passed"]:
        say(f"{spec.id}: QA warning: {'; '.join(attrs['qa_reasons'])}")
    with atomic_path(out) as tmp, h5py.File(tmp, "w") as h:
        stamp(h)
        g = h.create_group(f"records/{spec.id}")
        set_attrs(g, attrs)
        d = g.create_dataset("acc", data=np.asarray(tr.data, dtype=float), compression="gzip")
        d.attrs["units"] = "m/s^2"
        d.attrs["dt_s"] = float(tr.stats.delta)
        d.attrs["description"] = "processed ground acceleration, sample k at t = k dt"
        t = time_coordinate(g, d.shape[0], tr.stats.delta)  # layout 5: the dimension scale time_s
        attach_dims(d, t)
        hist = [str(s) for s in tr.stats.get("processing", [])]
        lines = g.create_dataset("processing", data=np.array(hist, dtype=h5py.string_dtype()))
        attach_dims(lines, dimension(g, "line", len(hist)))
        if vert is not None:
            v = g.create_dataset("vertical", data=vert.vertical, compression="gzip")
            v.attrs["units"] = "m/s^2"
            v.attrs["dt_s"] = float(tr.stats.delta)
            v.attrs["description"] = (
                "processed vertical ground acceleration, positive up, on the samples of acc (cut or "
                "continued with zeros to its length)"
            )
            # the sense of the file's samples and the sign that made them positive up (issue 34)
            pol = vert.meta.get("vertical", {})
            v.attrs["positive_in_file"] = str(pol.get("positive_in_file", "up"))
            v.attrs["sign"] = int(pol.get("sign", 1))
            v.attrs["polarity"] = str(pol.get("polarity", ""))
            attach_dims(v, t)
    return attrs


def process_records(
    batch: Sequence[Mapping],
    records: Sequence[str | os.PathLike],
    pulses: Sequence[str | os.PathLike],
    *,
    pulse: Mapping,
) -> None:
    """Rule ``process_record`` (one job per batch of records:
    :func:`~isorock.control.plan.process_batches`): of each
    record in turn, :func:`process_record`, then :func:`extract_pulse`, in one Python process.

    Parameters
    ----------
    batch : sequence of mapping
        The parameters of :func:`process_record` of each record
        (:func:`~isorock.control.plan.params_process`).
    records, pulses : sequence of path-like
        The files written for each record of ``batch``, in its order: processed record, pulse.
    pulse : mapping
        The parameters of :func:`extract_pulse` (:func:`~isorock.control.plan.params_pulse`).

    Raises
    ------
    IsorockError
        A record could not be processed (the message names it); the batch stops there.
    """
    if not len(batch) == len(records) == len(pulses):
        raise IsorockError(
            f"process_records: {len(batch)} records, {len(records)} record files and {len(pulses)} pulse "
            "files: one of each per record"
        )
    for p, rec, pul in zip(batch, records, pulses, strict=True):
        process_record(out=rec, **p)
        extract_pulse(rec, pul, **pulse)


def read_job_record(path: str | os.PathLike, *, vertical: bool = False) -> tuple[str, GroundMotion, dict]:
    """(id, GroundMotion, attrs) of the one record of a ``process_record`` output; with ``vertical``
    (the configuration's ``records.vertical``) the ground motion carries the record's vertical when
    it has one (``attrs["vertical_component"]`` names it; empty: horizontal only)."""
    with h5py.File(path, "r") as h:
        (rid,) = list(h["records"].keys())
        g = h["records"][rid]
        acc = g["acc"][()]
        dt = float(g["acc"].attrs["dt_s"])
        attrs = attrs_dict(g)
        vert = g["vertical"][()] if vertical and "vertical" in g else None
    return rid, GroundMotion(dt=dt, acc=acc, name=rid, vertical=vert), attrs


def extract_pulse(
    record_h5: str | os.PathLike, out: str | os.PathLike, *, pulse: Mapping | None = None
) -> dict:
    """Rule ``process_record``, second step: velocity pulse and Tp of a processed record ->
    ``/records/<id>/pulse``.

    Parameters
    ----------
    record_h5 : path-like
        Output of :func:`process_record`.
    out : path-like
        HDF5 file written with ``/records/<id>`` (the ``extract_pulse`` attributes of
        :data:`isorock.store.RECORD_ATTRS`: ``Tp_s`` (wavelet), ``Tp_mp_s``, ``Tp_br_s`` [s],
        ``tp_method`` (the definition of the catalog's Tp: ``mp``, ``br``, or ``wavelet`` for a record
        without one), ``Tp_method_s`` (Tp by it) [s], ``pulse_like``, ``pulse_indicator``) and
        ``/records/<id>/pulse`` (summary attributes, velocity histories [m/s]).
    pulse : mapping, optional
        ``tp_min_s``, ``tp_max_s`` [s], ``fit_mp``.

    Returns
    -------
    dict
        :meth:`isorock.pulse.PulseResult.summary`.
    """
    from isorock.pulse import PulseConfig, tp_by_method, tp_method_of
    from isorock.pulse import extract_pulse as _extract_pulse

    pulse = dict(pulse or {})
    cfg = PulseConfig(
        tp_min=float(pulse.get("tp_min_s", 0.25)),
        tp_max=float(pulse.get("tp_max_s", 15.0)),
        fit_mp=bool(pulse.get("fit_mp", True)),
    )
    rid, gm, rattrs = read_job_record(record_h5)
    res = _extract_pulse((gm.dt, gm.acc), cfg)
    summ = res.summary()
    method = tp_method_of(rattrs.get("tp_source"))
    tp_m = tp_by_method(res, method)
    summ["tp_method"] = method
    summ["Tp_method_s"] = tp_m
    say(
        f"{rid}: Tp = {res.Tp_s:.3f} s (wavelet), {summ['Tp_mp_s'] or math.nan:.3f} s (MP), "
        f"{res.Tp_br_s:.3f} s (BR); pulse-like {res.pulse_like} (PI {res.pulse_indicator:.2f})"
    )
    with atomic_path(out) as tmp, h5py.File(tmp, "w") as h:
        stamp(h)
        g = h.create_group(f"records/{rid}")
        values = {
            "Tp_s": summ["Tp_s"],
            "Tp_mp_s": summ["Tp_mp_s"],
            "Tp_br_s": summ["Tp_br_s"],
            "tp_method": method,
            "Tp_method_s": tp_m,
            "pulse_like": summ["pulse_like"],
            "pulse_indicator": summ["pulse_indicator"],
        }
        set_attrs(g, record_attrs_in_order(values, "extract_pulse"))
        p = g.create_group("pulse")
        set_attrs(p, summ)
        set_attrs(
            p,
            {
                "config_hash": config_hash(pulse),
                "record_sha256": rattrs.get("record_sha256", ""),
                "method": "db4 wavelet (Baker 2007) and Mavroeidis-Papageorgiou (2003) fit; isorock.pulse",
                "units": json.dumps(
                    {
                        "Tp_s": "s",
                        "Tp_mp_s": "s",
                        "Tp_br_s": "s",
                        "Tp_method_s": "s",
                        "pgv_m_s": "m/s",
                        "mp_A_m_s": "m/s",
                        "mp_fp_hz": "Hz",
                        "mp_nu_rad": "rad",
                        "mp_t0_s": "s",
                        "t_pulse_s": "s",
                    }
                ),
            },
        )
        t = time_coordinate(p, len(res.velocity), gm.dt)  # layout 5: the samples of acc (/records/<id>)
        for name, arr in (
            ("velocity", res.velocity),
            ("pulse_velocity", res.pulse_velocity),
            ("mp_velocity", res.mp_velocity),
        ):
            d = p.create_dataset(name, data=np.asarray(arr, dtype=float), compression="gzip")
            d.attrs["units"] = "m/s"
            d.attrs["dt_s"] = gm.dt
            attach_dims(d, t)
    return summ


def search_row(
    system: System, excitation: Excitation, search: Mapping, polarities: tuple[float, ...] = (1.0,)
) -> dict:
    """The result columns of one minimum-overturning search (``search``: amp_max_g [g], growth, rtol).

    With ``polarities`` ``(1, -1)`` (an asymmetric body) the excitation is searched as given and
    reversed, and the smaller minimum overturning amplitude is kept (nothing overturning counts as
    beyond ``amp_max_g``), with ``n_analyses`` and ``stalls`` of both searches.
    """
    found = [
        min_overturn_amplitude(
            system,
            excitation,
            amp_max=float(search["amp_max_g"]),
            growth=float(search["growth"]),
            rtol=float(search["rtol"]),
            polarity=p,
        )
        for p in polarities
    ]
    m = min(found, key=lambda r: math.inf if r.min_overturn_g is None else r.min_overturn_g)
    if len(found) > 1:
        m = dataclasses.replace(
            m,
            n_analyses=sum(r.n_analyses for r in found),
            stalls=sum(r.stalls for r in found),
            uplift_g=min(r.uplift_g for r in found),
        )
    tan_a = system.block.tan_alpha
    mo = math.nan if m.min_overturn_g is None else float(m.min_overturn_g)
    row = {
        "min_overturn_g": mo,
        "overturns": m.min_overturn_g is not None,
        "min_overturn_over_tan_alpha": mo / tan_a,
        "uplift_g": float(m.uplift_g),
        "uplift_over_tan_alpha": float(m.uplift_g) / tan_a,
        "n_analyses": int(m.n_analyses),
        "amp_max_g": float(m.amp_max_g),
        "resolution": math.nan if m.resolution is None else float(m.resolution),
        "stalls": int(m.stalls),
    }
    if len(found) > 1:
        # an asymmetric body: the search of each direction (NaN where nothing overturns)
        for r, key in zip(found, ("min_overturn_as_recorded_g", "min_overturn_reversed_g"), strict=True):
            row[key] = math.nan if r.min_overturn_g is None else float(r.min_overturn_g)
    return row


def block_columns(block: Block) -> dict:
    """The block columns of the tables: lambda_ (the slenderness), R_m, b_m, h_m, tan_alpha."""
    return {
        "lambda_": float(block.lam),
        "R_m": float(block.R),
        "b_m": float(block.b),
        "h_m": float(block.h),
        "tan_alpha": float(block.tan_alpha),
    }


def min_overturn(
    record_h5: str | os.PathLike,
    out: str | os.PathLike,
    *,
    lambdas: Sequence[float],
    Rs: Sequence[float],
    cases: Sequence[Mapping],
    search: Mapping,
    pulse_h5: str | os.PathLike | None = None,
    vertical: bool = False,
) -> Any:
    """Rule ``min_overturn``: minimum overturning PGA of a record per block and isolation case.

    For every slenderness ``lambda`` [-], size ``R`` [m] and isolation case, the record is scaled by
    the engine's search (:func:`isorock.physics.overturning.min_overturn_amplitude`: upward scan from the
    uplift
    PGA, then bisection) to the smallest PGA that overturns the block. ``min_overturn_g`` includes the
    record's vertical when ``vertical`` (``records.vertical``) and the record has one (column
    ``with_vertical``); a record with a vertical also gets the search the other way, so that both
    ``min_overturn_h_g`` (horizontal only) and ``min_overturn_hv_g`` (with its vertical, scaled with
    the horizontal) are there: the vertical's effect (NaN where the record has none).

    Parameters
    ----------
    record_h5 : path-like
        Output of :func:`process_record`.
    out : path-like
        HDF5 file written with the pandas table ``/overturn/<id>`` (columns
        :data:`isorock.store.OVERTURN_COLUMNS`).
    lambdas, Rs : sequence of float
        Block slenderness values [-] and sizes (half-diagonal) [m].
    cases : sequence of mapping
        Isolation cases (:class:`IsolationCase` fields).
    search : mapping
        ``amp_max_g`` [g], ``growth`` [-], ``rtol`` [-].
    pulse_h5 : path-like, optional
        Output of :func:`extract_pulse`; its Tp is copied into the table's attributes.

    Returns
    -------
    pandas.DataFrame
        The table.
    """
    rid, gm_hv, rattrs = read_job_record(record_h5, vertical=True)
    gm_h = gm_hv.horizontal_only()
    has_v = gm_hv.vertical is not None
    use_v = vertical and has_v
    gm = gm_hv if use_v else gm_h
    tp = math.nan
    if pulse_h5 is not None:
        with h5py.File(pulse_h5, "r") as h:
            tp = float(h[f"records/{rid}"].attrs.get("Tp_s", math.nan))
    pga = gm.pga_g
    rows = []
    t0 = time.perf_counter()
    objs = [case_from(c) for c in cases]
    for lam in lambdas:
        for R in Rs:
            block = Block.from_lambda_R(lam, R)
            for case in objs:
                try:
                    system = System(block, case.isolation())
                except ValueError as exc:
                    say(f"{rid}: lambda={lam:g} R={R:g} {case.name}: skipped: {exc}")
                    continue
                row = {
                    "record": rid,
                    **block_columns(block),
                    **case.columns(),
                    **search_row(system, gm, search),
                }
                row["record_pga_g"] = pga
                row["scale_min"] = row["min_overturn_g"] / pga
                other = search_row(system, gm_h if use_v else gm_hv, search) if has_v else None
                row["with_vertical"] = use_v
                row["min_overturn_h_g"] = (
                    other["min_overturn_g"] if use_v and other else row["min_overturn_g"]
                )
                row["min_overturn_hv_g"] = (
                    row["min_overturn_g"] if use_v else (other["min_overturn_g"] if other else math.nan)
                )
                rows.append(row)
    df = pd.DataFrame(rows, columns=list(OVERTURN_COLUMNS))
    secs = time.perf_counter() - t0
    say(
        f"{rid}: {len(rows)} minimum-overturning searches, {int(df['n_analyses'].sum())} analyses "
        f"in {secs:.1f} s"
    )
    attrs = {
        "record": rid,
        "record_sha256": rattrs.get("record_sha256", ""),
        "record_pga_g": pga,
        "Tp_s": tp,
        "config_hash": config_hash(
            {"lambdas": list(lambdas), "Rs": list(Rs), "cases": list(cases), "search": dict(search)}
            | ({"vertical": True} if vertical else {})
        ),
        "search": dict(search),
        "seconds": secs,
        "isorock_version": __version__,
        "description": "minimum overturning PGA of the record scaled by the search of "
        "isorock.physics.overturning.min_overturn_amplitude; NaN: no overturn up to amp_max_g",
    }
    with atomic_path(out) as tmp:
        write_tables(tmp, {f"overturn/{rid}": df}, {f"overturn/{rid}": attrs})
    return df


def _map_amplitude(amplitude: str | float, table1_pga_g: float | None, pga_g: float) -> tuple[float, str]:
    if isinstance(amplitude, (int, float)) and not isinstance(amplitude, bool):
        return float(amplitude), "config"
    if amplitude == "table1" and table1_pga_g:
        return float(table1_pga_g), "table1"
    return float(pga_g), "record"


def map_name_lr(case: str) -> str:
    """Name of a lambda-R map of an isolation case: ``lambda_R-<case>``."""
    return f"lambda_R-{case}"


def _map_name_tx(lam: float, R: float) -> str:
    """Name of a Tb-xi map of a block: ``Tb_xi-lam<lambda>-R<R>``."""
    return f"Tb_xi-lam{lam:g}-R{R:g}"


def regime_maps(
    record_h5: str | os.PathLike,
    out: str | os.PathLike,
    *,
    amplitude: str | float,
    table1_pga_g: float | None,
    lambda_R: Mapping,
    Tb_xi: Mapping,
    threads: int = 1,
    pulse_h5: str | os.PathLike | None = None,
    vertical: bool = False,
) -> list[str]:
    """Rule ``regime_maps``: response-regime maps of a record (lambda-R per case, Tb-xi per block).

    Parameters
    ----------
    record_h5 : path-like
        Output of :func:`process_record`.
    out : path-like
        HDF5 file written with ``/maps/<id>/lambda_R-<case>`` and ``/maps/<id>/Tb_xi-lam<l>-R<R>``.
    amplitude : {"table1", "record"} or float
        PGA of the record in the maps: its Table 1 PGA (else its own), its own, or this value [g].
    table1_pga_g : float or None
        Table 1 PGA of the record [g].
    lambda_R : mapping
        ``lambdas`` [-], ``Rs`` [m], ``cases`` (isolation cases).
    Tb_xi : mapping
        ``Tbs`` [s], ``xis`` [-], ``rho`` [-], ``blocks`` (``lambda``, ``R_m``).
    threads : int
        Threads of the compiled engine.
    pulse_h5 : path-like, optional
        Output of :func:`extract_pulse` (Tp copied into the attributes).

    Returns
    -------
    list of str
        The map paths written.
    """
    from isorock.physics.regime_maps import regime_map_lambda_R, regime_map_Tb_xi

    rid, gm, rattrs = read_job_record(record_h5, vertical=vertical)
    amp, amp_source = _map_amplitude(amplitude, table1_pga_g, gm.pga_g)
    tp = math.nan
    if pulse_h5 is not None:
        with h5py.File(pulse_h5, "r") as h:
            tp = float(h[f"records/{rid}"].attrs.get("Tp_s", math.nan))
    chash = config_hash(
        {
            **({"vertical": True} if vertical else {}),
            "amplitude": amplitude,
            "table1_pga_g": table1_pga_g,
            "lambda_R": dict(lambda_R),
            "Tb_xi": dict(Tb_xi),
        }
    )
    common = {
        "source": rid,
        "source_kind": "record",
        "amp_source": amp_source,
        "record_pga_g": gm.pga_g,
        "record_sha256": rattrs.get("record_sha256", ""),
        "Tp_s": tp,
        "config_hash": chash,
    }
    written = []
    with atomic_path(out) as tmp, h5py.File(tmp, "w") as h:
        stamp(h)
        root = h.create_group(f"maps/{rid}")
        for c in lambda_R["cases"]:
            case = case_from(c)
            m = regime_map_lambda_R(
                gm, case.isolation(), lambda_R["lambdas"], lambda_R["Rs"], amp, threads=threads
            )
            name = map_name_lr(case.name)
            write_map(root.create_group(name), m, {**common, "map": name, **case.columns()})
            written.append(f"/maps/{rid}/{name}")
            say(f"{rid}: {name} at {amp:.3g} g ({amp_source}): {m.counts()} in {m.seconds:.1f} s")
        for b in Tb_xi["blocks"]:
            block = Block.from_lambda_R(b["lambda"], b["R_m"])
            m = regime_map_Tb_xi(gm, block, Tb_xi["Tbs"], Tb_xi["xis"], Tb_xi["rho"], amp, threads=threads)
            name = _map_name_tx(b["lambda"], b["R_m"])
            extra = {
                "map": name,
                "case": "",
                "isolation": "linear",
                "rho": Tb_xi["rho"],
                "lambda": b["lambda"],
                "R_m": b["R_m"],
            }
            write_map(root.create_group(name), m, {**common, **extra})
            written.append(f"/maps/{rid}/{name}")
            say(f"{rid}: {name} at {amp:.3g} g ({amp_source}): {m.counts()} in {m.seconds:.1f} s")
    return written
