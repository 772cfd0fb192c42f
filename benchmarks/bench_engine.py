"""Speed of the compiled engine against the scipy oracle, measured in one run.

Cases (issue #2):
  (a) a 0.5 s full-sine pulse, linear isolation, a block that rocks;
  (b) a 40 s sampled record at dt = 0.005 s, linear isolation, a block that rocks.
Also reported: the same record with no isolation and with the FP isolator.

The record is synthetic and deterministic (band-limited noise under an envelope plus a
velocity pulse), so that the benchmark runs on a fresh clone without record files.

Usage::

    python benchmarks/bench_engine.py [--repeat 50] [--oracle-repeat 3] [--json out.json]

Absolute times depend on the machine; quote the ratios, which are measured in the same run.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time

import numpy as np

from isorock import Block, FPIsolation, GroundMotion, LinearIsolation, Pulse, System
from isorock.engine import simulate


def synthetic_record(duration: float = 40.0, dt: float = 0.005, seed: int = 1) -> GroundMotion:
    """Deterministic 40 s accelerogram with a strong-motion envelope and a 1.5 s velocity pulse [m/s^2]."""
    from scipy.signal import butter, sosfiltfilt

    rng = np.random.default_rng(seed)
    n = int(round(duration / dt)) + 1
    t = np.arange(n) * dt
    sos = butter(4, [0.2, 10.0], btype="band", fs=1.0 / dt, output="sos")
    noise = sosfiltfilt(sos, rng.standard_normal(n))
    env = (t / 3.0) ** 2 * np.exp(-t / 3.0) / (4.0 * np.exp(-2.0))
    acc = noise / np.max(np.abs(noise)) * env + 0.6 * np.sin(2 * np.pi * t / 1.5) * np.exp(
        -(((t - 8.0) / 1.5) ** 2)
    )
    acc = acc / np.max(np.abs(acc)) * 9.81
    return GroundMotion(dt, acc, "synthetic-40s")


def timed(fn, repeat: int) -> tuple[float, object]:
    """Median wall time of ``fn()`` over ``repeat`` calls [s], and its last result."""
    times = []
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=50, help="engine runs per case")
    ap.add_argument("--oracle-repeat", type=int, default=3, help="oracle runs per case")
    ap.add_argument("--no-oracle", action="store_true", help="time the engine only")
    ap.add_argument("--json", help="write the figures to this JSON file")
    a = ap.parse_args()

    rec = synthetic_record()
    lin = LinearIsolation(Tb=3.0, xi_b=0.35, rho=0.5)
    cases = [
        (
            "(a) full-sine 0.5 s, linear",
            System(Block.from_lambda_R(4.0, 1.0), lin),
            Pulse("fullsine", 0.5, 0.55),
            1.0,
        ),
        ("(b) 40 s record, linear", System(Block.from_lambda_R(4.0, 1.5), lin), rec, 0.7),
        ("(c) 40 s record, none", System(Block.from_lambda_R(4.0, 1.5)), rec, 0.3),
        (
            "(d) 40 s record, FP",
            System(Block.from_lambda_R(4.0, 1.5), FPIsolation(0.11, 2.24, 0.5)),
            rec,
            0.5,
        ),
    ]
    oracle = None
    if not a.no_oracle:
        from isorock.engine import oracle as oracle_mod

        oracle = oracle_mod.simulate

    simulate(cases[0][1], cases[0][2])  # compile (or load the cache) outside the timings
    rows = []
    print(f"{'case':32s} {'outcome':10s} {'engine ms':>10s} {'an./s':>9s} {'oracle ms':>11s} {'ratio':>8s}")
    for name, system, exc, scale in cases:
        t_e, r_e = timed(lambda s=system, e=exc, k=scale: simulate(s, e, scale=k), a.repeat)
        row = {
            "case": name,
            "outcome": r_e.outcome,
            "max_theta_over_alpha": r_e.max_theta_over_alpha,
            "engine_ms": 1e3 * t_e,
            "engine_per_s": 1.0 / t_e,
        }
        if oracle is not None:
            ex = exc.scaled(scale) if isinstance(exc, GroundMotion) else exc
            t_o, r_o = timed(lambda s=system, e=ex: oracle(s, e), a.oracle_repeat)
            row.update(
                oracle_ms=1e3 * t_o,
                oracle_outcome=r_o.outcome,
                ratio=t_o / t_e,
                oracle_max_theta_over_alpha=r_o.max_theta_over_alpha,
            )
        rows.append(row)
        o_ms = f"{row['oracle_ms']:11.1f}" if "oracle_ms" in row else f"{'-':>11s}"
        ratio = f"{row['ratio']:8.0f}" if "ratio" in row else f"{'-':>8s}"
        print(
            f"{name:32s} {r_e.outcome:10s} {row['engine_ms']:10.3f} {row['engine_per_s']:9.0f} {o_ms} {ratio}"
        )
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(rows, fh, indent=2)


if __name__ == "__main__":
    main()
