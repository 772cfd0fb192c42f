"""Sliding against linear rocking, per analysis on real records (issue 24), in one run.

For every record (the built-in pyslammer sample motions, plus the Table 1 records of
``$ISOROCK_RECORDS`` / ``--records`` when given), every base and every PGA below, one sliding analysis
of a squat object (friction 0.35 < tan(alpha) = 0.417, the worked example's showcase) and one rocking
analysis of the same block without the friction (the paper's analysis) are timed: median of
``--repeat`` runs each, engine compiled, one thread. Printed: the ratio sliding / rocking per case,
its median and 90th percentile and the ratio of the summed times, for each base. The issue's target
is the linear base: sliding within 2x the cost of the linear rocking analysis of the same record.

Usage::

    python benchmarks/bench_sliding.py [--repeat 7] [--json out.json] [--records DIR]

Absolute times depend on the machine; quote the ratios, which are measured in the same run.
"""

from __future__ import annotations

import argparse
import json
import os

import numpy as np
from bench_engine import timed
from bench_fp import records

from isorock import Block, FPIsolation, LinearIsolation, NoIsolation, System
from isorock.engine import set_threads, simulate

BLOCK = Block(b=0.25, h=0.6)  # height 1.2 m, width 0.5 m: tan(alpha) = 0.417
FRICTION = 0.35
PGAS_G = (0.3, 0.6)
BASES = {
    "linear": LinearIsolation(Tb=2.5, xi_b=0.1, rho=0.8),
    "none": NoIsolation(),
    "fp": FPIsolation.from_period(mu_b=0.06, Tb=3.0, rho=0.8),
}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=7, help="runs per analysis (median taken)")
    ap.add_argument("--records", default=os.environ.get("ISOROCK_RECORDS"), help="Table 1 records folder")
    ap.add_argument("--json", help="write the figures to this JSON file")
    a = ap.parse_args()
    set_threads(1)
    recs = records(a.records)
    out: dict = {"friction": FRICTION, "tan_alpha": BLOCK.tan_alpha, "bases": {}}
    for kind, iso in BASES.items():
        system = System(BLOCK, iso)
        simulate(system, recs[0][1], friction=FRICTION)  # compile
        rows = []
        for name, gm in recs:
            for pga in PGAS_G:
                scale = pga / gm.pga_g
                t_s, r_s = timed(
                    lambda g=gm, s=scale, y=system: simulate(y, g, scale=s, friction=FRICTION), a.repeat
                )
                t_r, r_r = timed(lambda g=gm, s=scale, y=system: simulate(y, g, scale=s), a.repeat)
                rows.append(
                    {
                        "record": name,
                        "pga_g": pga,
                        "sliding_s": t_s,
                        "rocking_s": t_r,
                        "ratio": t_s / t_r,
                        "n_slips": r_s.n_slips,
                        "rocking_outcome": r_r.outcome,
                    }
                )
                print(
                    f"{kind:6s} {name[:40]:40s} {pga:.1f} g  sliding/rocking {t_s / t_r:5.2f}  "
                    f"slips {r_s.n_slips:3d}  rocking: {r_r.outcome}"
                )
        ratios = np.array([r["ratio"] for r in rows])
        summed = sum(r["sliding_s"] for r in rows) / sum(r["rocking_s"] for r in rows)
        out["bases"][kind] = {
            "rows": rows,
            "median_ratio": float(np.median(ratios)),
            "p90_ratio": float(np.percentile(ratios, 90)),
            "summed_ratio": float(summed),
        }
        print(
            f"== {kind}: sliding / rocking per analysis: median {np.median(ratios):.2f}, "
            f"90th percentile {np.percentile(ratios, 90):.2f}, summed times {summed:.2f} ({len(rows)} cases)"
        )
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(out, fh, indent=1)


if __name__ == "__main__":
    main()
