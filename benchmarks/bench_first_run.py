"""The first analysis after an install: how long it waits for numba to compile the engine (issues 18, 25).

Runs, in fresh processes with an empty numba cache (a temporary ``NUMBA_CACHE_DIR``, so that the
checkout's own cache is not touched):

1. ``isorock simulate`` of a short pulse on a linear isolator: the first analysis after an install
   (it compiles the engine's entry point of the linear isolator, rocking mode);
2. the same command again: the cache is loaded;
3. the first analysis of each other kind, each with its own empty cache: the fixed base, the friction
   pendulum, and the sliding mode (``--friction`` below ``tan(alpha)``), which compile their own entry
   points (``--no-models`` leaves them out);
4. ``isorock --warm-up`` with another empty cache: compiles every entry point of ``simulate`` and the
   parallel batch kernel of the workflow, as an install script or a cluster job would; then the
   command of 1, which loads the cache.

and prints the wall times, the CPU time of each process (user + system: the compilation itself, less
sensitive than the wall time to other work on a shared machine) and whether the first one said
"compiling the engine" on stderr. ``--repeat N`` runs each cold measurement N times and reports the
medians.

Usage::

    python benchmarks/bench_first_run.py [--repeat 3] [--no-models] [--json out.json]

Absolute times depend on the machine and its load; the ratio cold / warm is the figure to quote, and
a comparison of two versions of the engine is made on the same machine, their runs alternated.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

BLOCK = ["--lambda", "4", "--R", "1.5"]
PULSE = ["--pulse", "fullsine", "--td", "0.5", "--pga", "0.4", "--json"]
LINEAR = ["--isolation", "linear", "--Tb", "3", "--xi", "0.2", "--rho", "0.5"]
SIMULATE = ["simulate", *BLOCK, *LINEAR, *PULSE]
# the first analysis of each other kind (the block's tan(alpha) is 0.25: friction 0.1 slides)
MODELS = {
    "fixed base": ["simulate", *BLOCK, "--isolation", "none", *PULSE],
    "friction pendulum": ["simulate", *BLOCK, "--isolation", "fp", "--Tb", "3", "--mu", "0.1", "--rho", "0.5",
                          *PULSE],
    "sliding (linear)": ["simulate", *BLOCK, *LINEAR, "--friction", "0.1", *PULSE],
}  # fmt: skip


def _isorock(args: list[str], cache: str) -> tuple[float, float, str]:
    """Wall and CPU time [s] of one ``isorock`` process with the numba cache ``cache``, and its stderr."""
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.run(
        [sys.executable, "-m", "isorock.cli", *args], env=env, capture_output=True, text=True, check=True
    )
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    return wall, cpu, p.stderr


def _median(values: list[float]) -> float:
    return statistics.median(values)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=1, help="cold runs of each measurement (medians)")
    ap.add_argument("--no-models", action="store_true", help="leave out the other kinds' first analyses")
    ap.add_argument("--json", help="write the figures to this JSON file")
    a = ap.parse_args()
    rows: dict = {"repeat": a.repeat}
    first, first_cpu, second = [], [], []
    for _ in range(a.repeat):
        with tempfile.TemporaryDirectory() as cache:
            wall, cpu, err = _isorock(SIMULATE, cache)
            first.append(wall)
            first_cpu.append(cpu)
            rows["said_compiling"] = "compiling the engine" in err
            wall, _, err2 = _isorock(SIMULATE, cache)
            second.append(wall)
            rows["second_said_compiling"] = "compiling the engine" in err2
    rows["first_simulate_s"] = _median(first)
    rows["first_simulate_cpu_s"] = _median(first_cpu)
    rows["second_simulate_s"] = _median(second)
    models: dict = {}
    if not a.no_models:
        for name, args in MODELS.items():
            walls, cpus = [], []
            for _ in range(a.repeat):
                with tempfile.TemporaryDirectory() as cache:
                    wall, cpu, _ = _isorock(args, cache)
                    walls.append(wall)
                    cpus.append(cpu)
            models[name] = {"wall_s": _median(walls), "cpu_s": _median(cpus)}
    rows["first_simulate_by_kind"] = models
    warm, warm_cpu, after = [], [], []
    for _ in range(a.repeat):
        with tempfile.TemporaryDirectory() as cache:
            wall, cpu, err = _isorock(["--warm-up"], cache)
            warm.append(wall)
            warm_cpu.append(cpu)
            rows["warm_up_message"] = err.strip().splitlines()[-1] if err.strip() else ""
            after.append(_isorock(SIMULATE, cache)[0])
    rows["warm_up_s"] = _median(warm)
    rows["warm_up_cpu_s"] = _median(warm_cpu)
    rows["after_warm_up_simulate_s"] = _median(after)
    ratio = rows["first_simulate_s"] / rows["second_simulate_s"]
    n = f", median of {a.repeat}" if a.repeat > 1 else ""
    lines = [
        (f"first isorock simulate, linear (empty cache{n})", rows["first_simulate_s"],
         rows["first_simulate_cpu_s"], f"said 'compiling the engine': {rows['said_compiling']}"),
        ("second isorock simulate (cache loaded)", rows["second_simulate_s"], None,
         f"said it again: {rows['second_said_compiling']}"),
        *((f"first isorock simulate, {name} (empty cache)", m["wall_s"], m["cpu_s"], "")
          for name, m in models.items()),
        ("isorock --warm-up (empty cache)", rows["warm_up_s"], rows["warm_up_cpu_s"],
         rows["warm_up_message"]),
        ("isorock simulate after --warm-up", rows["after_warm_up_simulate_s"], None, ""),
    ]  # fmt: skip
    for label, wall, cpu, note in lines:
        cpu_text = f"CPU {cpu:5.1f} s" if cpu is not None else " " * 11
        print(f"{label:58s} {wall:6.1f} s  {cpu_text}  {note}".rstrip())
    print(f"{'cold / warm':58s} {ratio:6.1f}")
    if a.json:
        Path(a.json).write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
