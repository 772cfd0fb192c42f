"""The first analysis after an install: how long it waits for numba to compile the engine (issue 18).

Runs, in fresh processes with an empty numba cache (a temporary ``NUMBA_CACHE_DIR``, so that the
checkout's own cache is not touched):

1. ``isorock simulate`` of a short pulse: the first analysis after an install (compiles the engine);
2. the same command again: the cache is loaded;
3. ``isorock --warm-up`` with another empty cache: compiles both entry points (``simulate`` and the
   parallel batch kernel of the workflow), as an install script or a cluster job would.

and prints the wall times and whether the first one said "compiling the engine" on stderr.

Usage::

    python benchmarks/bench_first_run.py [--json out.json]

Absolute times depend on the machine and its load; the ratio cold / warm is the figure to quote.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SIMULATE = [
    "simulate", "--lambda", "4", "--R", "1.5", "--isolation", "linear", "--Tb", "3", "--xi", "0.2",
    "--rho", "0.5", "--pulse", "fullsine", "--td", "0.5", "--pga", "0.4", "--json",
]  # fmt: skip


def _isorock(args: list[str], cache: str) -> tuple[float, str]:
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    t0 = time.perf_counter()
    p = subprocess.run(
        [sys.executable, "-m", "isorock.cli", *args], env=env, capture_output=True, text=True, check=True
    )
    return time.perf_counter() - t0, p.stderr


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--json", help="write the figures to this JSON file")
    a = ap.parse_args()
    rows: dict = {}
    with tempfile.TemporaryDirectory() as cache:
        rows["first_simulate_s"], err = _isorock(SIMULATE, cache)
        rows["said_compiling"] = "compiling the engine" in err
        rows["second_simulate_s"], err2 = _isorock(SIMULATE, cache)
        rows["second_said_compiling"] = "compiling the engine" in err2
    with tempfile.TemporaryDirectory() as cache:
        rows["warm_up_s"], err = _isorock(["--warm-up"], cache)
        rows["warm_up_message"] = err.strip().splitlines()[-1] if err.strip() else ""
        rows["after_warm_up_simulate_s"], _ = _isorock(SIMULATE, cache)
    ratio = rows["first_simulate_s"] / rows["second_simulate_s"]
    print(f"first isorock simulate (empty cache)    {rows['first_simulate_s']:6.1f} s, "
          f"said 'compiling the engine': {rows['said_compiling']}")  # fmt: skip
    print(f"second isorock simulate (cache loaded)  {rows['second_simulate_s']:6.1f} s, "
          f"said it again: {rows['second_said_compiling']}")  # fmt: skip
    print(f"cold / warm                             {ratio:6.1f}")
    print(f"isorock --warm-up (empty cache)         {rows['warm_up_s']:6.1f} s ({rows['warm_up_message']})")
    print(f"isorock simulate after --warm-up        {rows['after_warm_up_simulate_s']:6.1f} s")
    if a.json:
        Path(a.json).write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
