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
from isorock.physics.engine import set_threads, simulate

BLOCK = Block(b=0.25, h=0.6)  # height 1.2 m, width 0.5 m: tan(alpha) = 0.417
FRICTION = 0.35
PGAS_G = (0.3, 0.6)
BASES = {
    "linear": LinearIsolation(Tb=2.5, xi_b=0.1, rho=0.8),
    "none": NoIsolation(),
    "fp": FPIsolation.from_period(mu_b=0.06, Tb=3.0, rho=0.8),
}


def _case(kind: str, system: System, name: str, gm, pga: float, t_lin: float, repeat: int) -> dict:
    """Time one record at one PGA: the sliding analysis and the rocking one on the same base."""
    scale = pga / gm.pga_g
    t_s, r_s = timed(lambda: simulate(system, gm, scale=scale, friction=FRICTION), repeat)
    t_r, r_r = timed(lambda: simulate(system, gm, scale=scale), repeat)
    print(
        f"{kind:6s} {name[:40]:40s} {pga:.1f} g  sliding/rocking {t_s / t_r:5.2f}  sliding/linear rocking "
        f"{t_s / t_lin:5.2f}  slips {r_s.n_slips:3d}  rocking: {r_r.outcome}"
    )
    return {"record": name, "pga_g": pga, "sliding_s": t_s, "rocking_s": t_r, "linear_rocking_s": t_lin,
            "ratio": t_s / t_r, "ratio_linear": t_s / t_lin, "n_slips": r_s.n_slips,
            "rocking_outcome": r_r.outcome}  # fmt: skip


def _summary(kind: str, rows: list[dict], key: str, what: str) -> dict:
    """Median, 90th percentile and summed-time ratio of ``key`` over all the cases and over those with a
    slip; printed."""
    out = {}
    for sel, label in ((rows, "all"), ([r for r in rows if r["n_slips"] > 0], "slipping")):
        if not sel:
            continue
        r = np.array([x[key] for x in sel])
        den = "rocking_s" if key == "ratio" else "linear_rocking_s"
        summed = sum(x["sliding_s"] for x in sel) / sum(x[den] for x in sel)
        out[f"{key}_{label}"] = {"median": float(np.median(r)), "p90": float(np.percentile(r, 90)),
                                 "summed": float(summed), "n": len(sel)}  # fmt: skip
        print(
            f"== {kind}: sliding / {what}, {label} cases ({len(sel)}): median {np.median(r):.2f}, "
            f"90th percentile {np.percentile(r, 90):.2f}, summed times {summed:.2f}"
        )
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=7, help="runs per analysis (median taken)")
    ap.add_argument("--records", default=os.environ.get("ISOROCK_RECORDS"), help="Table 1 records folder")
    ap.add_argument("--json", help="write the figures to this JSON file")
    a = ap.parse_args()
    set_threads(1)
    recs = records(a.records)
    out: dict = {"friction": FRICTION, "tan_alpha": BLOCK.tan_alpha, "bases": {}}
    linear = System(BLOCK, BASES["linear"])
    simulate(linear, recs[0][1])  # compile
    # the yardstick: the linear-isolator rocking analysis of the same record at the same PGA
    lin_rock = {
        (name, pga): timed(lambda g=gm, s=pga / gm.pga_g: simulate(linear, g, scale=s), a.repeat)[0]
        for name, gm in recs
        for pga in PGAS_G
    }
    for kind, iso in BASES.items():
        system = System(BLOCK, iso)
        simulate(system, recs[0][1], friction=FRICTION)  # compile
        rows = [_case(kind, system, name, gm, pga, lin_rock[name, pga], a.repeat) for name, gm in recs
                for pga in PGAS_G]  # fmt: skip
        same = _summary(kind, rows, "ratio", "rocking on the same base")
        out["bases"][kind] = {"rows": rows, **same, **_summary(kind, rows, "ratio_linear", "linear rocking")}
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(out, fh, indent=1)


if __name__ == "__main__":
    main()
