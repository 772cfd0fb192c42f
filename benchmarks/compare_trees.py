"""The engine's speed in two source trees, old and new alternated in one run.

Runs ``benchmarks/bench_engine.py --no-oracle`` (of this tree) against the sources of each tree in turn
(``PYTHONPATH=TREE/src``), ``--rounds`` times, alternating, so that both see the same machine load;
reports each case's median engine time per tree and the ratio new / old. The first round of each tree
compiles (or loads) its engine outside the timings (bench_engine.py warms up before timing).

Usage::

    git worktree add /tmp/old <rev>       # the old sources
    python benchmarks/compare_trees.py /tmp/old . [--rounds 6] [--repeat 20] [--json out.json]

Quote the ratios: absolute times depend on the machine.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

BENCH = Path(__file__).with_name("bench_engine.py")


def run_once(tree: Path, repeat: int) -> dict[str, float]:
    """Median engine time per case [ms] of one bench_engine.py run on the sources of ``tree``."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "rows.json"
        env = dict(os.environ, PYTHONPATH=str(tree.resolve() / "src"))
        subprocess.run(
            [sys.executable, str(BENCH), "--no-oracle", "--repeat", str(repeat), "--json", str(out)],
            check=True,
            env=env,
            stdout=subprocess.DEVNULL,
        )
        return {r["case"]: r["engine_ms"] for r in json.loads(out.read_text())}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("old", type=Path, help="the old source tree (holds src/isorock)")
    ap.add_argument("new", type=Path, help="the new source tree")
    ap.add_argument("--rounds", type=int, default=6, help="runs of each tree, alternated")
    ap.add_argument("--repeat", type=int, default=20, help="engine runs per case in each run")
    ap.add_argument("--json", help="write the figures to this JSON file")
    a = ap.parse_args()
    times: dict[str, dict[str, list[float]]] = {"old": {}, "new": {}}
    for rnd in range(a.rounds):
        for label, tree in (
            (("old", a.old), ("new", a.new)) if rnd % 2 == 0 else (("new", a.new), ("old", a.old))
        ):
            for case, ms in run_once(tree, a.repeat).items():
                times[label].setdefault(case, []).append(ms)
        print(f"round {rnd + 1}/{a.rounds} done", file=sys.stderr)
    rows = []
    print(f"{'case':32s} {'old ms':>9s} {'new ms':>9s} {'new/old':>8s}")
    for case in times["old"]:
        o = statistics.median(times["old"][case])
        n = statistics.median(times["new"][case])
        rows.append({"case": case, "old_ms": o, "new_ms": n, "ratio": n / o})
        print(f"{case:32s} {o:9.3f} {n:9.3f} {n / o:8.3f}")
    if a.json:
        Path(a.json).write_text(json.dumps(rows, indent=2))


if __name__ == "__main__":
    main()
