"""Friction pendulum against linear isolation, per analysis on real records (issue 18), in one run.

For every record (the built-in pyslammer sample motions, plus the Table 1 records of
``$ISOROCK_RECORDS`` when it is set), every block and every PGA below, one analysis on a friction
pendulum and one on a linear isolator of the same period (Tb = 3 s: R_b = 2.24 m) are timed (median
of ``--repeat`` runs each, engine compiled, one thread) and their ratio FP / linear printed, with the
integrator's step counts. The summary gives the median and the 90th percentile of the per-analysis
ratio and the ratio of the summed times.

Usage::

    python benchmarks/bench_fp.py [--repeat 7] [--json out.json] [--records DIR]

Absolute times depend on the machine; quote the ratios, which are measured in the same run.
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path

import numpy as np
from bench_engine import timed

from isorock import Block, FPIsolation, LinearIsolation, System
from isorock.physics.engine import set_threads, simulate
from isorock.records.directory import sample_records
from isorock.records.motion import load_motion

BLOCKS = {"lambda 3, R 0.95 m (statue)": (3.0, 0.95), "lambda 4, R 1.5 m": (4.0, 1.5)}
PGAS_G = (0.3, 0.5)
MU_B = (0.06, 0.11)
TB_S = 3.0
XI_B = 0.2
RHO = 0.5


def records(extra: str | None) -> list[tuple[str, object]]:
    """(name, ground motion) of the sample motions and of the Table 1 files of ``extra``."""
    out = [(s.name, load_motion(s.path)) for s in sample_records()]
    if extra:
        from isorock.records.components import choose_component
        from isorock.records.lookup import find_records

        for spec in find_records({"dir": extra, "include": ["table1"]}).records:
            choice = choose_component(spec.files, spec.target)
            out.append((spec.id, choice.record.motion))
    return out


def one_case(gm, blk: Block, pga: float, lin, fps, repeat: int) -> list[dict]:
    """The rows of one record, block and PGA: linear, then each friction pendulum."""
    scale = pga / gm.pga_g
    t_l, r_l = timed(lambda: simulate(System(blk, lin), gm, scale=scale), repeat)
    rows = []
    for fp in fps:
        t_f, r_f = timed(lambda f=fp: simulate(System(blk, f), gm, scale=scale), repeat)
        rows.append(
            {
                "pga_g": pga, "mu_b": fp.mu_b, "linear_ms": 1e3 * t_l, "fp_ms": 1e3 * t_f,
                "ratio": t_f / t_l, "linear_outcome": r_l.outcome, "fp_outcome": r_f.outcome,
                "linear_steps": r_l.n_steps, "fp_steps": r_f.n_steps,
            }
        )  # fmt: skip
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=7, help="runs per analysis (median)")
    ap.add_argument("--records", default=os.environ.get("ISOROCK_RECORDS"), help="Table 1 records too")
    ap.add_argument("--json", help="write every row to this JSON file")
    a = ap.parse_args()
    set_threads(1)
    recs = records(a.records)
    lin = LinearIsolation(Tb=TB_S, xi_b=XI_B, rho=RHO)
    fps = [FPIsolation.from_period(mu_b=m, Tb=TB_S, rho=RHO) for m in MU_B]
    simulate(System(Block.from_lambda_R(3.0, 1.0), fps[0]), recs[0][1], scale=1.0)  # compile
    rows = []
    print(f"{len(recs)} records x {len(BLOCKS)} blocks x PGA {PGAS_G} g x mu_b {MU_B}; Tb = {TB_S} s")
    print(f"{'record':44s} {'linear ms':>9s} {'FP ms':>7s} {'FP/lin':>6s} {'steps lin':>9s} {'steps FP':>8s}")
    for name, gm in recs:
        mine = []
        for bname, (lam, R) in BLOCKS.items():
            for pga in PGAS_G:
                for row in one_case(gm, Block.from_lambda_R(lam, R), pga, lin, fps, a.repeat):
                    mine.append(dict(row, record=name, block=bname))
        lin_ms = float(np.mean([r["linear_ms"] for r in mine]))
        fp_ms = float(np.mean([r["fp_ms"] for r in mine]))
        steps_l = float(np.mean([r["linear_steps"] for r in mine]))
        steps_f = float(np.mean([r["fp_steps"] for r in mine]))
        print(
            f"{name[:44]:44s} {lin_ms:9.3f} {fp_ms:7.3f} {fp_ms / lin_ms:6.1f} {steps_l:9.0f} {steps_f:8.0f}"
        )
        rows += mine
    ratios = np.array([r["ratio"] for r in rows])
    rocks = np.array([r["linear_outcome"] != "no_uplift" for r in rows])
    tot = sum(r["fp_ms"] for r in rows) / sum(r["linear_ms"] for r in rows)
    print(
        f"FP / linear per analysis ({len(rows)}): median {np.median(ratios):.1f}, 90th percentile "
        f"{np.percentile(ratios, 90):.1f}; summed times {tot:.1f}"
    )
    if rocks.any():
        print(
            f"  where the block rocks on the linear isolator ({rocks.sum()}): "
            f"median {np.median(ratios[rocks]):.1f}"
        )
    steps = sum(r["fp_steps"] for r in rows) / sum(r["linear_steps"] for r in rows)
    print(f"integrator steps FP / linear: {steps:.2f}")
    if a.json:
        Path(a.json).write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
