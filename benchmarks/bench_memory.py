"""Peak memory of the record jobs against the record's length: the model of the memory each rule
declares (``isorock.resources.job_memory_mb``).

For each length, a synthetic record (a decaying 1 Hz sine of 0.3 g plus noise, dt 0.005 s) is written
as a one-column text file and added to a records folder of its own; each record job
(``process_record`` with its pulse extraction, ``min_overturn``, ``regime_maps``, ``assess_stripes``)
then runs in a fresh Python process on the grids of ``config/ci.yaml`` (and the objects of
``config/assessment.yaml``), which prints its peak resident memory (``ru_maxrss``). The input sizes
are those Snakemake sees (``input.size_mb``).

Run: ``python benchmarks/bench_memory.py`` (a few minutes; ``--samples 6000 24000`` for other
lengths). It prints one table: rule, samples, input MB, peak MB, and the MB per input MB above the
interpreter's own (the shortest record's peak).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DT = 0.005

JOB = r"""
import json, resource, sys
from pathlib import Path
from isorock import pipeline
from isorock.pipeline import load_config, plan
a = json.loads(sys.argv[1])
lim = {"max_samples": 10**8, "max_duration_s": 1e6}
cfg = load_config(a["config"], {"records": {"dir": a["records"], "select": [], "include": ["added"], **lim}})
p = plan(cfg)
spec = p.records[0]
work = Path(a["work"])
rec, pulse = work / "record.h5", work / "pulse.h5"
rule = a["rule"]
if rule == "process_record":
    pipeline.process_record(out=rec, **pipeline.params_process(cfg, spec, None))
    pipeline.extract_pulse(rec, pulse, **pipeline.params_pulse(cfg))
elif rule == "min_overturn":
    pipeline.min_overturn(rec, work / "o.h5", pulse_h5=pulse, **pipeline.params_overturn(cfg, spec.id))
elif rule == "regime_maps":
    pipeline.regime_maps(rec, work / "m.h5", pulse_h5=pulse, threads=1, **pipeline.params_maps(cfg, spec))
print(json.dumps({"peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def _record(folder: Path, n: int) -> Path:
    rng = np.random.default_rng(n)
    t = np.arange(n) * DT
    a = 0.3 * np.sin(2 * np.pi * t) * np.exp(-t / (0.3 * t[-1])) * np.minimum(t, 1.0)
    a += 0.02 * rng.standard_normal(n)
    path = folder / f"long{n}.txt"
    np.savetxt(path, a, fmt="%.6e")
    return path


def _run(rule: str, records: Path, work: Path) -> float:
    arg = json.dumps({"config": str(ROOT / "config" / "ci.yaml"), "records": str(records),
                      "work": str(work), "rule": rule})  # fmt: skip
    res = subprocess.run([sys.executable, "-c", JOB, arg], capture_output=True, text=True, cwd=ROOT)
    if res.returncode != 0:
        raise SystemExit(f"{rule}: {res.stderr[-2000:]}")
    return json.loads(res.stdout.strip().splitlines()[-1])["peak_mb"]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, nargs="+", default=[6000, 24000, 60000, 120000])
    args = ap.parse_args()
    from isorock.records.adding import add_records

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in args.samples:
            base = Path(tmp) / f"n{n}"
            base.mkdir()
            src = _record(base, n)
            records = base / "records"
            add_records([src], records, dt=DT, units="g", max_samples=n, max_duration_s=n * DT)
            work = base / "work"
            work.mkdir()
            for rule in ("process_record", "min_overturn", "regime_maps"):
                size = src.stat().st_size if rule == "process_record" else (work / "record.h5").stat().st_size
                size += 0 if rule == "process_record" else (work / "pulse.h5").stat().st_size
                rows.append((rule, n, size / 2**20, _run(rule, records, work)))
    base = {r[0]: r for r in rows if r[1] == min(args.samples)}
    print(f"{'rule':16s} {'samples':>8s} {'input MB':>9s} {'peak MB':>8s} {'MB per input MB':>16s}")
    for rule, n, size, peak in rows:
        b = base[rule]
        slope = (peak - b[3]) / (size - b[2]) if size > b[2] else float("nan")
        print(f"{rule:16s} {n:8d} {size:9.2f} {peak:8.0f} {slope:16.1f}")


if __name__ == "__main__":
    main()
