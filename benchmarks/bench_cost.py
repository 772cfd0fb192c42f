"""CPU time per analysis of each kind the workflow runs: the constants of isorock.control.cost.

Measured in one process after a warm-up (the first call loads the compiled engine, about 0.2 s), on one
thread, on the synthetic 40 s record of ``bench_engine.py`` (no record files needed) and a 0.5 s
full-sine pulse:

* minimum-overturning searches (lambda 4, R 0.5 to 12 m, amp_max 5 g for the record, 10 g for the
  pulse, the paper's growth 1.005 and rtol 1e-6), per isolation kind;
* regime-map points (a 100 x 60 lambda-R map at 0.5 g, per kind; a pulse's map);
* full runs of the assessment (20 systems x 20 levels 0.05 to 1 g, per kind).

Usage::

    python benchmarks/bench_cost.py [--json out.json]

The figures are ms of one core per analysis; isorock.control.cost states the ones it uses and where.
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np
from bench_engine import synthetic_record

from isorock import Block, LinearIsolation, NoIsolation, Pulse, System
from isorock.assessment.stripes import run_levels
from isorock.physics.model import make_isolation
from isorock.physics.overturning import min_overturn_amplitude
from isorock.physics.regime_maps import regime_map_lambda_R

ISOLATIONS = {
    "none": NoIsolation(),
    "linear": LinearIsolation(Tb=3.0, xi_b=0.35, rho=0.5),
    "fp": make_isolation("fp", mu_b=0.11, R_b_m=2.24, rho=0.5),
}


def search_ms(exc, iso, amp_max: float) -> tuple[float, float]:
    """(ms per analysis, analyses per search) of minimum-overturning searches on lambda 4 blocks."""
    min_overturn_amplitude(System(Block.from_lambda_R(4.0, 3.0), iso), exc, amp_max=amp_max)  # warm-up
    n, t0 = 0, time.perf_counter()
    sizes = (0.5, 1.0, 2.0, 3.0, 5.0, 8.0, 12.0)
    for R in sizes:
        n += min_overturn_amplitude(System(Block.from_lambda_R(4.0, R), iso), exc, amp_max=amp_max).n_analyses
    return 1e3 * (time.perf_counter() - t0) / n, n / len(sizes)


def map_ms(exc, iso) -> float:
    """ms per point of a 100 x 60 lambda-R map at 0.5 g, one thread."""
    lams, Rs = np.linspace(1.5, 8.0, 100), np.linspace(0.5, 15.0, 60)
    regime_map_lambda_R(exc, iso, lams[:2], Rs[:2], 0.5, threads=1)  # warm-up
    t0 = time.perf_counter()
    m = regime_map_lambda_R(exc, iso, lams, Rs, 0.5, threads=1)
    return 1e3 * (time.perf_counter() - t0) / m.n_analyses


def full_ms(gm, iso) -> float:
    """ms per full run: 20 systems (lambda 3 to 5, R 1 m) x 20 levels, one thread."""
    systems = [System(Block.from_lambda_R(lam, 1.0), iso) for lam in np.linspace(3.0, 5.0, 20)]
    levels = [0.05 * k for k in range(1, 21)]
    run_levels(systems[:1], gm, levels[:2], 0.7, threads=1, slide_allow_m=None)  # warm-up
    t0 = time.perf_counter()
    runs = run_levels(systems, gm, levels, 0.7, threads=1, slide_allow_m=None)
    return 1e3 * (time.perf_counter() - t0) / len(runs)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--json", help="write the figures to this JSON file")
    a = ap.parse_args()
    rec = synthetic_record()
    pulse = Pulse("fullsine", 0.5, 1.0)
    out: dict[str, dict[str, float]] = {}
    for kind, iso in ISOLATIONS.items():
        s_ms, per = search_ms(rec, iso, 5.0)
        p_ms, p_per = search_ms(pulse, iso, 10.0)
        out[kind] = {
            "search_ms": s_ms,
            "analyses_per_search": per,
            "pulse_search_ms": p_ms,
            "pulse_analyses_per_search": p_per,
            "full_run_ms": full_ms(rec, iso),
        }
        out[kind]["map_ms"] = map_ms(rec, iso)
        out[kind]["pulse_map_ms"] = map_ms(pulse, iso)
        print(kind, ", ".join(f"{k} {v:.3g}" for k, v in out[kind].items()))
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(out, fh, indent=2)


if __name__ == "__main__":
    main()
