"""Speed of an isolation design search (issue: minutes, not hours, on 2 cores), measured in one run.

A design search (:mod:`isorock.assessment.design`) runs every isolator of a grid under every record
scaled to every stripe, in full runs (peaks, isolator displacement and contact forces over the whole
motion), through :func:`isorock.assessment.stripes.run_levels` (the workflow's ``assess_design`` job,
parallel threads of :func:`isorock.physics.engine.run_many`). The issue's size: a 20 x 10 grid, 22 records and
20 stripes, 88,000 analyses. The records are synthetic and deterministic (40 s at 0.005 s, band-limited
noise under an envelope plus a velocity pulse, as in ``bench_engine.py``; 22 seeds), so that the
benchmark runs on a fresh clone.

Usage::

    python benchmarks/bench_assess.py                 # linear grid in full, FP on a 2 x 10 part of it
    python benchmarks/bench_assess.py --fp-full       # the FP grid in full too (several minutes)
    python benchmarks/bench_assess.py --records 4     # fewer records (a quick look)

Absolute times depend on the machine and its load; the per-analysis costs of the two isolators are
measured in the same run, so their ratio is what to compare.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
from bench_engine import synthetic_record

from isorock import Block, FPIsolation, LinearIsolation, System
from isorock.assessment.stripes import run_levels


def grid(kind: str, n_tb: int, n_second: int) -> list:
    """The isolators of a design grid: linear (Tb x xi_b) or FP (mu_b x R_b)."""
    if kind == "linear":
        return [
            LinearIsolation(tb, xi, 0.5)
            for tb in np.linspace(1.5, 4.0, n_tb)
            for xi in np.linspace(0.05, 0.4, n_second)
        ]
    return [
        FPIsolation(mu, rb, 0.5)
        for rb in np.linspace(0.56, 4.0, n_tb)
        for mu in np.linspace(0.03, 0.12, n_second)
    ]


def search(kind: str, isos: list, records: list, stripes: np.ndarray) -> tuple[float, int, int]:
    """(seconds, analyses, overturning analyses) of the design search over ``records``."""
    block = Block.from_lambda_R(3.0, 0.5 * np.hypot(1.8, 0.6))  # the 1.8 m x 0.6 m statue
    systems = [System(block, iso) for iso in isos]
    t0 = time.perf_counter()
    n = n_over = 0
    for k, gm in enumerate(records):
        runs = run_levels(systems, gm, stripes, friction=0.5, slide_allow_m=None)
        n += len(runs)
        n_over += int((runs["outcome_code"] == 2).sum())
        elapsed = time.perf_counter() - t0
        print(f"  {kind}: record {k + 1}/{len(records)}: {len(runs)} analyses, {elapsed:.1f} s", flush=True)
    return time.perf_counter() - t0, n, n_over


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--records", type=int, default=22, help="records (default 22)")
    ap.add_argument("--stripes", type=int, default=20, help="stripes (default 20, 0.05-1.0 g)")
    ap.add_argument("--fp-full", action="store_true", help="the FP grid in full (default: a 2 x 10 part)")
    a = ap.parse_args()
    records = []
    for seed in range(1, a.records + 1):
        r = synthetic_record(seed=seed)
        records.append(r.with_pga(1.0))
    stripes = np.linspace(0.05, 1.0, a.stripes)
    print(f"{a.records} records of {records[0].duration:.0f} s at {records[0].dt} s, {a.stripes} stripes, "
          f"threads: {os.environ.get('NUMBA_NUM_THREADS', 'all cores')}")  # fmt: skip
    lin = grid("linear", 20, 10)
    t_lin, n_lin, o_lin = search("linear", lin, records, stripes)
    fp = grid("fp", 20, 10) if a.fp_full else grid("fp", 2, 10)
    t_fp, n_fp, o_fp = search("fp", fp, records, stripes)
    per_lin, per_fp = t_lin / n_lin, t_fp / n_fp
    print()
    print(f"linear, 20 x 10 grid: {n_lin} analyses ({o_lin} overturn) in {t_lin:.1f} s: ", end="")
    print(f"{1e3 * per_lin:.3f} ms per analysis")
    what = "20 x 10 grid" if a.fp_full else "2 x 10 part of the grid"
    print(
        f"FP, {what}: {n_fp} analyses ({o_fp} overturn) in {t_fp:.1f} s: {1e3 * per_fp:.3f} ms per analysis"
    )
    if not a.fp_full:
        print(f"FP, 20 x 10 grid (extrapolated from the part): {per_fp * n_lin:.0f} s")
    print(f"FP / linear cost per analysis (same run): {per_fp / per_lin:.1f}")


if __name__ == "__main__":
    main()
