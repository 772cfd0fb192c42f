"""``isorock info`` and ``isorock pulse``: intensity measures and velocity pulse of a record.

Both commands read the record through :func:`isorock.motion.load_record` (the path every command
and the workflow take), processed with the default steps of ``processing.yaml`` (or
``--processing YAML``; ``--raw`` analyses the record as read), then print either a short summary or,
with ``--json``, one JSON object with the record's provenance under ``record``.
"""

from __future__ import annotations

import argparse

from .options import add_json_option, add_record_options, load_from_args, processing_text
from .output import print_json

__all__ = ["register"]


def _add_options(p: argparse.ArgumentParser) -> None:
    add_record_options(p, positional=True)
    # --config: the name of --processing before isorock 0.2, kept as a hidden alias
    p.add_argument("--config", dest="processing", default=None, help=argparse.SUPPRESS)
    add_json_option(p)


def _label(a: argparse.Namespace, source) -> str:
    return f"{a.file}" + (f" [{source.component}]" if source.component else "")


def _qa(tr) -> dict:
    from ..processing import qa_passed, qa_reasons

    return {"qa_passed": qa_passed(tr), "qa_reasons": qa_reasons(tr)}


def _print_qa(q: dict) -> None:
    if not q["qa_passed"]:
        for r in q["qa_reasons"]:
            print(f"QA warning: {r}")


def cmd_info(a: argparse.Namespace) -> int:
    """``isorock info``: intensity measures of the processed record."""
    from ..processing import metrics

    rec = load_from_args(a.file, a)
    m = metrics(rec.trace)
    out = {
        "file": a.file,
        "component": rec.source.component or None,
        **m,
        "pga_raw_g": metrics(rec.raw)["pga_g"],
        **_qa(rec.trace),
        "record": rec.source.to_dict(),
    }
    if a.json:
        print_json(out)
        return 0
    print(f"record: {_label(a, rec.source)}, {processing_text(rec.source)}")
    print(f"samples: {m['npts']}, dt = {m['dt_s']:g} s, duration {m['duration_s']:.2f} s")
    print(f"PGA: {m['pga_g']:.4f} g ({m['pga_m_s2']:.4f} m/s^2; as read {out['pga_raw_g']:.4f} g)")
    print(f"PGV: {m['pgv_m_s']:.4f} m/s   PGD: {m['pgd_m']:.4f} m")
    print(f"Arias intensity: {m['arias_m_s']:.4f} m/s   D5-95: {m['d5_95_s']:.2f} s")
    _print_qa(out)
    return 0


def cmd_pulse(a: argparse.Namespace) -> int:
    """``isorock pulse``: velocity pulse and its period (three methods)."""
    from ..pulse import extract_pulse

    rec = load_from_args(a.file, a)
    res = extract_pulse(rec.trace)
    out = {
        "file": a.file,
        "component": rec.source.component or None,
        **res.summary(),
        **_qa(rec.trace),
        "record": rec.source.to_dict(),
    }
    if a.json:
        print_json(out)
        return 0
    print(f"record: {_label(a, rec.source)}, {processing_text(rec.source)}")
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
        "and significant duration D5-95.",
    )
    _add_options(p)
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
