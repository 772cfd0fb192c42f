"""Pulse periods of the Table 1 records against the published values, through the product.

For every Table 1 row with a file in the records directory, the component the workflow analyses is
chosen by :func:`isorock.records.components.choose_component` (the paper's SN/SP direction: rotated from two
recorded components, provided by the data source, or a recorded one with a QA mark), processed with
the packaged steps and passed to :func:`isorock.pulse.extract_pulse`. The table gives the direction
used, the three pulse periods (db4 wavelet, Baker 2007; Mavroeidis-Papageorgiou (MP) fit; Bray &
Rodriguez-Marek (BR) 2004), the published Tp and the error of the definition of its source
(``tp_source`` of the catalog), then the fraction of rows within 15 % (rows whose only file is a
substitute station are listed but not counted). It is the same choice and the same numbers as
``isorock pulse --id ID`` and the workflow's ``/summary/records``.

``--synthetic N`` runs instead the check quoted in :mod:`isorock.pulse` on N synthetic records with a
known period (MP pulse of 0.6-8 s, ``1.2 <= gamma <= 3``, random phase, plus omega-square stochastic
motion of 30-90 % of the pulse PGV; processed like the real records): error of the MP fit with and
without the displacement term, and of the wavelet period.

Usage::

    python benchmarks/tp_table.py [--records DIR] [--csv OUT.csv]
    python benchmarks/tp_table.py --synthetic 60
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TOLERANCE = 0.15


def records_dir(arg: str | None) -> Path:
    """``--records``, else ``$ISOROCK_RECORDS``, else ``../shared/records`` beside the repository."""
    if arg:
        return Path(arg)
    env = os.environ.get("ISOROCK_RECORDS", "").strip()
    return Path(env) if env else (ROOT / ".." / "shared" / "records").resolve()


def table(records: Path) -> list[dict]:
    """One row per Table 1 row with a file: direction used and the three periods against Table 1."""
    from isorock.errors import IsorockError
    from isorock.pulse import extract_pulse, tp_by_method, tp_method_of
    from isorock.records.catalog import load_catalog
    from isorock.records.components import choose_component
    from isorock.records.lookup import catalog_record

    rows = []
    for rid in load_catalog()["id"]:
        try:
            spec = catalog_record(rid, records)
        except IsorockError:
            continue
        t0 = time.perf_counter()
        ch = choose_component(
            spec.files, spec.target, table1_pga_g=spec.table1_pga_g, table1_pgv_m_s=spec.table1_pgv_m_s
        )
        res = extract_pulse(ch.record.trace)
        method = tp_method_of(spec.tp_source)
        pub = spec.table1_tp_s or math.nan

        def err(x: float | None, pub: float = pub) -> float:
            return math.nan if x is None else 100.0 * (x / pub - 1.0)

        rows.append(
            {
                "table1_id": rid,
                "component": ch.component,
                "azimuth_deg": math.nan if ch.azimuth_deg is None else ch.azimuth_deg,
                "direction": ch.method,
                "substitute": any(f.substitute for f in spec.files),
                "pgv_m_s": res.pgv_m_s,
                "table1_pgv_m_s": spec.table1_pgv_m_s,
                "tp_pub_s": pub,
                "method": method,
                "tp_wavelet_s": res.Tp_s,
                "err_wavelet_pct": err(res.Tp_s),
                "tp_mp_s": res.Tp_mp_s if res.mp is not None else math.nan,
                "err_mp_pct": err(res.Tp_mp_s if res.mp is not None else None),
                "tp_br_s": res.Tp_br_s,
                "err_br_pct": err(res.Tp_br_s),
                "err_source_pct": err(tp_by_method(res, method)),
                "pulse_like": bool(res.pulse_like),
                "qa_mark": "; ".join(x for x in (ch.qa_mark, ch.table1_check) if x),
                "description": ch.description,
                "seconds": time.perf_counter() - t0,
            }
        )
    return rows


def synthetic_record(seed: int):
    """(dt [s], acceleration [m/s^2], true Tp [s]) of one synthetic pulse-like record."""
    import numpy as np
    from scipy.integrate import cumulative_trapezoid

    from isorock.pulse import mp_acceleration

    rng = np.random.default_rng(seed)
    tp = math.exp(rng.uniform(math.log(0.6), math.log(8.0)))
    gamma, nu, amp = rng.uniform(1.2, 3.0), rng.uniform(0.0, 2.0 * math.pi), rng.uniform(0.3, 1.2)
    dt = 0.01 if tp < 3.0 else 0.02
    t = np.arange(0.0, max(40.0, 40.0 + gamma * tp), dt)
    t0 = 5.0 + gamma * tp / 2 + rng.uniform(0.0, 5.0)
    pulse = mp_acceleration(t, amp, 1.0 / tp, nu, gamma, t0)
    # omega-square (Brune) acceleration spectrum, corner 0.2-2 Hz, under an envelope starting
    # near the pulse arrival
    fc = math.exp(rng.uniform(math.log(0.2), math.log(2.0)))
    tm = t0 - gamma * tp / 2 + rng.uniform(-2.0, 2.0)
    x = (t - tm + 2.0) / 4.0
    env = np.where(x > 0, x**2 * np.exp(-2.0 * (x - 1.0)), 0.0)
    spec = np.fft.rfft(rng.normal(size=t.size) * env)
    f = np.fft.rfftfreq(t.size, dt)
    noise = np.fft.irfft(spec * (f / fc) ** 2 / (1.0 + (f / fc) ** 2), t.size)
    noise *= rng.uniform(0.3, 0.9) * amp / np.max(np.abs(cumulative_trapezoid(noise, dx=dt, initial=0.0)))
    return dt, pulse + noise, tp


def synthetic(n: int) -> int:
    import numpy as np
    from obspy import Trace

    from isorock.processing import process
    from isorock.pulse import PulseConfig, extract_pulse

    err: dict[str, list[float]] = {
        "MP fit, velocity + displacement": [],
        "MP fit, velocity only": [],
        "db4": [],
    }
    for seed in range(1000, 1000 + n):
        dt, acc, tp = synthetic_record(seed)
        tr = process(Trace(acc, header={"delta": dt}))
        both = extract_pulse(tr)
        vel = extract_pulse(tr, PulseConfig(mp_displacement=False))
        err["MP fit, velocity + displacement"].append(abs(both.Tp_mp_s / tp - 1.0))
        err["MP fit, velocity only"].append(abs(vel.Tp_mp_s / tp - 1.0))
        err["db4"].append(abs(both.Tp_s / tp - 1.0))
    print(f"{n} synthetic records (seeds 1000-{999 + n}), |Tp / true - 1|:")
    for name, e in err.items():
        a = np.array(e)
        print(
            f"  {name:32s} median {100 * np.median(a):5.1f} %, "
            f"90th percentile {100 * np.quantile(a, 0.9):5.1f} %, "
            f"within 15 %: {100 * np.mean(a <= TOLERANCE):5.1f} %"
        )
    return 0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--records", default=None, help="records directory (default $ISOROCK_RECORDS or ../shared/records)"
    )
    ap.add_argument("--csv", default=None, help="also write the table to this CSV file")
    ap.add_argument(
        "--synthetic", type=int, default=0, metavar="N", help="run the check on N synthetic records instead"
    )
    a = ap.parse_args(argv)
    if a.synthetic > 0:
        return synthetic(a.synthetic)
    rec = records_dir(a.records)
    if not (rec / "manifest.csv").is_file():
        print(f"no records manifest in {rec}: set ISOROCK_RECORDS", file=sys.stderr)
        return 2
    rows = table(rec)
    head = (
        f"{'table1_id':10s} {'comp':>5s} {'az':>5s} {'direction':>11s} {'PGV':>4s} {'/T1':>4s} "
        f"{'Tp pub':>6s} {'src':>3s} {'db4':>5s} {'err%':>6s} {'MP':>5s} {'err%':>6s} {'BR':>5s} "
        f"{'err%':>6s} {'pulse':>5s}  QA mark"
    )
    print(head)
    print("-" * len(head))
    for r in rows:
        az = "    ?" if math.isnan(r["azimuth_deg"]) else f"{r['azimuth_deg']:5.1f}"
        sub = " (substitute)" if r["substitute"] else ""
        print(
            f"{r['table1_id']:10s} {r['component']:>5s} {az} {r['direction']:>11s} {r['pgv_m_s']:4.2f} "
            f"{r['table1_pgv_m_s'] or math.nan:4.2f} {r['tp_pub_s']:6.2f} {r['method'].upper():>3s} "
            f"{r['tp_wavelet_s']:5.2f} {r['err_wavelet_pct']:+6.1f} {r['tp_mp_s']:5.2f} "
            f"{r['err_mp_pct']:+6.1f} {r['tp_br_s']:5.2f} {r['err_br_pct']:+6.1f} "
            f"{'yes' if r['pulse_like'] else 'no':>5s}  {r['qa_mark']}{sub}"
        )
    print("-" * len(head))
    print(
        "comp, az: direction analysed and its azimuth [deg]; direction: how it was obtained (provided by the "
        "data source, rotated from two recorded components, aligned = a recorded one within 5 deg, as "
        "recorded);\nPGV, /T1: PGV [m/s] of the processed record and of Table 1; src: definition of the "
        "published Tp (MP: Mavroeidis & Papageorgiou fit, BR: Bray & Rodriguez-Marek)"
    )
    counted = [r for r in rows if not r["substitute"]]
    n = len(counted)
    parts = []
    for name, key in (
        ("db4 wavelet", "err_wavelet_pct"),
        ("MP fit", "err_mp_pct"),
        ("BR", "err_br_pct"),
        ("method of the source (src)", "err_source_pct"),
    ):
        k = sum(1 for r in counted if abs(r[key]) <= 100 * TOLERANCE)
        parts.append(f"{name} {k}/{n} ({100 * k / max(n, 1):.0f} %)")
    print(f"within {100 * TOLERANCE:.0f} % over {n} Table 1 rows (substitutes left out): " + ", ".join(parts))
    slowest = max(r["seconds"] for r in rows)
    print(f"time per row (reading, rotation, processing, pulse): {slowest:.2f} s at most")
    if a.csv:
        with open(a.csv, "w", newline="") as fh:
            wr = csv.DictWriter(fh, fieldnames=list(rows[0]))
            wr.writeheader()
            wr.writerows(rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
