"""``isorock info`` and ``isorock pulse``: intensity measures and velocity pulse of a record.

Both commands read a record file through :func:`isorock.records.motion.load_record` (the path every command
and the workflow take), or, with ``--id ID [--records DIR]``, the component of a Table 1 row as the
workflow chooses it (:func:`isorock.records.components.choose_component`: rotated to SN/SP when two
components are there), processed with the default steps of ``processing.yaml`` (or
``--processing YAML``; ``--raw`` analyses the record as read), then print either a short summary or,
with ``--json``, one JSON object with the record's provenance under ``record``. With ``--id``,
``pulse`` reports as ``Tp_s`` the period by the definition of the row's published source
(``method``: ``mp`` for Mavroeidis & Papageorgiou, ``br`` for Bray & Rodriguez-Marek), the other
definitions under their own keys; for a file, ``Tp_s`` is the wavelet period (``method: wavelet``).
``isorock info --versions`` reads no record: it prints the versions of Python, the numerical packages
and the platform (:func:`isorock.environment.versions`, the store's ``version_*`` root attributes).
``info`` also says the sense taken for a vertical (issue 34, docs/model.md §17): of the file itself when
it is a vertical (``DWN``: positive down, its sign reversed), of the recording's vertical with ``--id``
(JSON key ``vertical``: ``component``, ``positive_in_file``, ``sign``, ``polarity``).
"""

from __future__ import annotations

import argparse
from typing import Any, NamedTuple

from isorock.cli.options import (
    add_json_option,
    add_record_options,
    choice_from_args,
    load_from_args,
    processing_text,
    record_arg,
)
from isorock.cli.output import print_json
from isorock.errors import IsorockError

__all__ = ["register"]


def _add_options(p: argparse.ArgumentParser) -> None:
    add_record_options(p, positional=True)
    # --config: the name of --processing before isorock 0.2, kept as a hidden alias
    p.add_argument("--config", dest="processing", default=None, help=argparse.SUPPRESS)
    add_json_option(p)


class LoadedInput(NamedTuple):
    """The record of ``FILE`` or ``--id`` (:func:`_load`).

    Attributes
    ----------
    record : LoadedRecord
        The record read and processed (:mod:`isorock.records.motion`).
    keys : dict
        The JSON keys of its identity (file and component, or the Table 1 row and its component).
    label : str
        How the text output names it.
    choice : ComponentChoice or None
        For ``--id``, the component chosen (:func:`isorock.records.components.choose_component`).
    files : tuple of RecordFile
        For ``--id``, the files of the record's recording (where its vertical is looked for).
    """

    record: Any
    keys: dict
    label: str
    choice: Any = None
    files: tuple = ()


def _load(a: argparse.Namespace, pairs: bool = False) -> LoadedInput:
    """The record of ``FILE`` or ``--id``, with its identity (:class:`LoadedInput`)."""
    path = record_arg(a)
    if path is not None:
        rec = load_from_args(path, a)
        path = rec.source.file if path == "-" else path  # standard input: "<stdin>"
        label = path + (f" [{rec.source.component}]" if rec.source.component else "")
        return LoadedInput(rec, {"file": path, "component": rec.source.component or None}, label)
    spec, ch = choice_from_args(a, pairs=pairs)
    keys = {
        "id": spec.id,
        "label": spec.label,
        **ch.to_dict(),
        "table1_pga_g": spec.table1_pga_g,
        "table1_pgv_m_s": spec.table1_pgv_m_s,
        "table1_tp_s": spec.table1_tp_s,
        "tp_source": spec.tp_source or None,
    }
    label = f"{spec.id} ({spec.label})"
    return LoadedInput(ch.record, keys, label, ch, tuple(spec.files))


def _vertical(loaded: LoadedInput) -> dict | None:
    """The vertical and the sense taken for it (docs/model.md §17, issue 34): for a file that is a
    vertical, its own; for ``--id``, the one found beside the component chosen
    (:func:`isorock.records.vertical.find_vertical`); None for a horizontal file."""
    from pathlib import Path

    from isorock.records.naming import is_vertical, vertical_polarity
    from isorock.records.vertical import find_vertical

    rec, choice = loaded.record, loaded.choice
    if choice is None:
        comp = rec.source.component or ""
        if not is_vertical(comp):
            return None
        return {"component": comp, **vertical_polarity(comp).to_dict()}
    found = find_vertical(loaded.files, rec.raw, choice.file.path)
    if found.found is None:
        return {"component": "", "note": found.describe()}
    vc = found.found
    return {"component": f"{Path(vc.file).name}:{vc.component}", **vc.polarity.to_dict()}


def _print_vertical(v: dict | None) -> None:
    """One line: the vertical's sense and why, or why there is none (nothing for a horizontal file)."""
    if v is None:
        return
    if not v["component"]:
        print(f"vertical: none ({v['note']})")
    elif ":" in v["component"]:
        print(f"vertical: {v['component']}, {v['polarity']}")
    else:
        print(f"vertical polarity: {v['polarity']}")


def _print_marks(ch: Any) -> None:
    """The component chosen for ``--id`` and its QA marks (nothing for a file)."""
    if ch is None:
        return
    print(f"component: {ch.component} ({ch.method}): {ch.description}")
    if ch.qa_mark:
        print(f"QA mark: {ch.qa_mark}")
    if ch.table1_check:
        print(f"QA mark: {ch.table1_check}")


def _qa(tr) -> dict:
    from isorock.processing import qa_passed, qa_reasons

    return {"qa_passed": qa_passed(tr), "qa_reasons": qa_reasons(tr)}


def _print_qa(q: dict) -> None:
    if not q["qa_passed"]:
        for r in q["qa_reasons"]:
            print(f"QA warning: {r}")


def _print_versions(a: argparse.Namespace) -> int:
    """``isorock info --versions``: the versions of :func:`isorock.environment.versions` (no record)."""
    from isorock.environment import versions

    if record_given := [f for f, v in (("FILE", a.file), ("--id", a.table1_id)) if v]:
        raise IsorockError(f"--versions reads no record: leave out {' and '.join(record_given)}")
    v = versions()
    if a.json:
        print_json(v)
        return 0
    for name, text in v.items():
        print(f"{name} {text}")
    return 0


def cmd_info(a: argparse.Namespace) -> int:
    """``isorock info``: intensity measures of the processed record; with ``--versions``, the versions of
    Python, the numerical packages and the platform instead (:func:`_print_versions`)."""
    from isorock.processing import applied_steps, metrics

    if a.versions:
        return _print_versions(a)
    from isorock.processing.imt import INFO_MEASURES, rotd_of_traces

    loaded = _load(a, pairs=True)
    rec, keys, label, choice = loaded.record, loaded.keys, loaded.label, loaded.choice
    m = metrics(rec.trace)
    pair = getattr(choice, "pair", None)
    rot, left = (
        rotd_of_traces(pair, INFO_MEASURES) if pair is not None else ({"rotd50": {}, "rotd100": {}}, [])
    )
    out = {
        **keys,
        **m,
        "pga_raw_g": metrics(rec.raw)["pga_g"],
        **_qa(rec.trace),
        "record": rec.source.to_dict(),
        "rotd_pair": "" if pair is None else choice.pair_description,
        **rot,
    }
    vertical = _vertical(loaded)
    if vertical is not None:
        out["vertical"] = vertical
    if a.json:
        print_json(out)
        return 0
    print(f"record: {label}, {processing_text(rec.source, applied_steps(rec.trace))}")
    _print_marks(choice)
    print(f"samples: {m['npts']}, dt = {m['dt_s']:g} s, duration {m['duration_s']:.2f} s")
    print(f"PGA: {m['pga_g']:.4f} g ({m['pga_m_s2']:.4f} m/s^2; as read {out['pga_raw_g']:.4f} g)")
    print(f"PGV: {m['pgv_m_s']:.4f} m/s   PGD: {m['pgd_m']:.4f} m")
    print(f"Arias intensity: {m['arias_m_s']:.4f} m/s   D5-95: {m['d5_95_s']:.2f} s")
    if pair is None:
        why = (
            "one file: give --id for a record's two horizontals" if choice is None else "one horizontal only"
        )
        print(f"RotD50, RotD100: none ({why})")
    else:
        print(f"RotD50 / RotD100 of {out['rotd_pair']} (PGA, SA in g; PGV in cm/s):")
        print("  " + ", ".join(f"{k} {v:.4g} / {rot['rotd100'][k]:.4g}" for k, v in rot["rotd50"].items()))
        for line in left:
            print(f"  {line}")
    _print_vertical(vertical)
    _print_qa(out)
    return 0


def cmd_pulse(a: argparse.Namespace) -> int:
    """``isorock pulse``: velocity pulse and its period (three methods)."""
    from isorock.processing import applied_steps
    from isorock.pulse import TP_METHODS, extract_pulse, tp_by_method, tp_method_of

    rec, keys, label, choice, _ = _load(a)
    res = extract_pulse(rec.trace)
    summ = res.summary()
    method = tp_method_of(keys.get("tp_source")) if "id" in keys else "wavelet"
    tp = tp_by_method(res, method)
    out = {
        **keys,
        "Tp_s": tp,
        "method": method,
        "method_name": TP_METHODS[method][0],
        "Tp_wavelet_s": summ["Tp_s"],
        **{k: v for k, v in summ.items() if k != "Tp_s"},
        **_qa(rec.trace),
        "record": rec.source.to_dict(),
    }
    t1 = keys.get("table1_tp_s")
    if t1 and tp:
        out["Tp_error_pct"] = 100.0 * (tp / t1 - 1.0)
    if a.json:
        print_json(out)
        return 0
    print(f"record: {label}, {processing_text(rec.source, applied_steps(rec.trace))}")
    _print_marks(choice)
    if "id" in keys:
        tp_txt = "not fitted" if tp is None else f"{tp:.3f} s"
        ref = f"; Table 1: {t1:.2f} s ({keys['tp_source']})" if t1 else ""
        err = f", {out['Tp_error_pct']:+.1f} %" if "Tp_error_pct" in out else ""
        print(f"Tp by the method of the Table 1 source ({TP_METHODS[method][0]}): {tp_txt}{ref}{err}")
    print(f"Tp (db4 wavelet, Baker 2007): {res.Tp_s:.3f} s at t = {res.t_pulse_s:.2f} s")
    if res.mp is not None:
        mp = res.mp
        print(
            f"Tp (Mavroeidis-Papageorgiou fit): {res.Tp_mp_s:.3f} s  "
            f"(A = {mp.A:.3f} m/s, fp = {mp.fp:.4f} Hz, nu = {mp.nu:.3f} rad, gamma = {mp.gamma:.3f}, "
            f"t0 = {mp.t0:.3f} s)"
        )
        w0, w1 = res.mp_window_s
        print(
            f"  MP fit over {w0:.2f}-{w1:.2f} s: RMS misfit / RMS record {res.mp_rms_ratio:.2f} (velocity), "
            f"{res.mp_disp_rms_ratio:.2f} (displacement)"
        )
    b0, b1 = res.br_half_cycle_s
    print(
        f"Tp (Bray & Rodriguez-Marek, twice the PGV half-cycle): {res.Tp_br_s:.3f} s "
        f"(zero crossings at {b0:.2f} and {b1:.2f} s)"
    )
    verdict = "pulse-like" if res.pulse_like else "not pulse-like"
    print(
        f"pulse indicator: {res.pulse_indicator:.3f} -> {verdict} "
        f"(PGV {res.pgv_m_s:.3f} m/s, PGV ratio {res.pgv_ratio:.3f}, energy ratio {res.energy_ratio:.3f}, "
        f"{'early' if res.early else 'late'} pulse)"
    )
    _print_qa(out)
    return 0


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``info`` and ``pulse`` to the ``isorock`` command."""
    p = subparsers.add_parser(
        "info",
        help="intensity measures of a record after processing",
        description="Read a record, process it, print PGA, PGV, PGD, Arias intensity "
        "and significant duration D5-95. With --versions, print instead the versions of Python, "
        "isorock, the numerical packages and Snakemake, and the platform (what the merge writes on the "
        "root of results/isorock.h5).",
    )
    _add_options(p)
    p.add_argument(
        "--versions",
        action="store_true",
        help="print the versions of Python, isorock, numpy, scipy, numba, llvmlite, obspy, h5py, pandas, "
        "snakemake and the platform, one 'name version' line each (with --json, one JSON object), and "
        "read no record",
    )
    p.set_defaults(func=cmd_info)
    p = subparsers.add_parser(
        "pulse",
        help="velocity-pulse period of a record (wavelet, MP fit, Bray & Rodriguez-Marek)",
        description="Read a record, process it, extract the velocity pulse (db4 wavelet, "
        "Baker 2007), fit the Mavroeidis-Papageorgiou pulse (velocity and displacement) and "
        "measure the Bray & Rodriguez-Marek (2004) period (twice the PGV half-cycle).",
    )
    _add_options(p)
    p.set_defaults(func=cmd_pulse)
