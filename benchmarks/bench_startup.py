"""How long a command waits before it answers: the start-up of isorock's commands, in fresh processes.

Times, each in a new Python process (``python -m isorock.cli ...``, as the ``isorock`` command runs;
``--repeat`` runs each, median quoted):

* ``import isorock.records``, ``import isorock.physics.engine`` and ``import isorock.records.motion`` alone;
* ``isorock info FILE``: read one record file, process it, print its intensity measures;
* ``isorock info --id IMV79-EMO`` (with a records directory): the same for a Table 1 row, read from
  its two recorded components and rotated to strike-normal, as the workflow does;
* the 6000-analysis regime map of the issue: ``isorock map lambda-R`` (100 x 60, the default grid) of
  the 38.6 s record IMV79-EMO at 0.5 g on the linear isolator Tb 3 s, xi 0.35, rho 0.5 (the linear case
  of ``bench_cost.py``), with ``--json`` (no progress bar); the analyses' own time, which the command
  reports (``seconds``), is printed beside the wall time.

The records: ``--records DIR`` or ``$ISOROCK_RECORDS`` with the Table 1 row IMV79-EMO in its
``manifest.csv``; otherwise (a fresh clone) pyslammer's sample motion Coalinga 1983 PVB-045 (38.45 s,
dt 0.005 s), read as a file (``pip install 'isorock[samples]'``).

Every command runs once before the timing (the engine's numba cache compiled and loaded, the files in
the page cache: a warm machine). With ``--baseline-src DIR`` the same commands run also on another
source tree (``PYTHONPATH=DIR``, e.g. a ``git worktree`` of an older commit, same virtual environment),
alternated with this one run by run (the order swapped every run), so that both see the same load;
compare the ratios, which are measured in the same run.

Usage::

    python benchmarks/bench_startup.py [--repeat 7] [--baseline-src /tmp/old/src] [--records DIR]
                                       [--only info_file,map] [--json out.json]

The machine's load average is printed before and after: on a shared machine the absolute times
follow it. The targets of the issue (a warm machine): ``isorock info`` on a record within 1.2 s, the
6000-analysis map within 3 s.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src"
TABLE1_ID = "IMV79-EMO"  # Imperial Valley 1979, El Centro Meloland Overpass: 7720 x 0.005 s = 38.6 s
SAMPLE = "Coalinga_1983_PVB-045"  # pyslammer's sample of about the same length (38.45 s, dt 0.005 s)
MAP_OPTIONS = ["--pga", "0.5", "--isolation", "linear", "--Tb", "3", "--xi", "0.35", "--rho", "0.5", "--json"]
TARGETS_S = {"info_file": 1.2, "info_id": 1.2, "map": 3.0}


def _records_dir(given: str | None) -> Path | None:
    """The records directory holding the Table 1 row :data:`TABLE1_ID`, or None."""
    d = given or os.environ.get("ISOROCK_RECORDS")
    if not d:
        return None
    manifest = Path(d) / "manifest.csv"
    if not manifest.is_file():
        return None
    with open(manifest, newline="", encoding="utf-8") as fh:
        rows = [r for r in csv.DictReader(fh) if r.get("table1_id") == TABLE1_ID]
    return Path(d) if rows else None


def _file_options(records: Path) -> list[str]:
    """``FILE --format ... --units ... --dt ...`` of the first file of :data:`TABLE1_ID` in the manifest."""
    with open(records / "manifest.csv", newline="", encoding="utf-8") as fh:
        row = next(r for r in csv.DictReader(fh) if r.get("table1_id") == TABLE1_ID)
    opts = [str(records / row["file"])]
    for key, flag in (("format", "--format"), ("units", "--units"), ("dt_s", "--dt")):
        if row.get(key):
            opts += [flag, row[key]]
    return opts


def _sample_file() -> Path:
    import importlib.util

    spec = importlib.util.find_spec("pyslammer")
    if spec is None or not spec.submodule_search_locations:
        sys.exit("bench_startup: no records directory with IMV79-EMO, no pyslammer samples: give --records")
    for loc in spec.submodule_search_locations:
        hits = sorted(Path(loc).rglob(f"{SAMPLE}.csv"))
        if hits:
            return hits[0]
    sys.exit(f"bench_startup: pyslammer has no sample {SAMPLE}")


def commands(records: Path | None) -> dict[str, list[str]]:
    """The commands timed, by name: the arguments after ``python``."""
    cli = ["-m", "isorock.cli"]
    cmds = {
        "import_records": ["-c", "import isorock.records"],
        "import_engine": ["-c", "import isorock.physics.engine"],
        "import_motion": ["-c", "import isorock.records.motion"],
    }
    if records is not None:
        cmds["info_file"] = [*cli, "info", *_file_options(records)]
        cmds["info_id"] = [*cli, "info", "--id", TABLE1_ID, "--records", str(records)]
        cmds["map"] = [*cli, "map", "lambda-R", "--id", TABLE1_ID, "--records", str(records), *MAP_OPTIONS]
    else:
        sample = str(_sample_file())
        cmds["info_file"] = [*cli, "info", sample]
        cmds["map"] = [*cli, "map", "lambda-R", "--record", sample, *MAP_OPTIONS]
    return cmds


def run(args: list[str], src: Path) -> tuple[float, float | None]:
    """Wall time [s] of ``python args`` on the source tree ``src``, and the analyses' time of a map."""
    env = dict(os.environ, PYTHONPATH=str(src))
    t0 = time.perf_counter()
    p = subprocess.run([sys.executable, *args], env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit(f"bench_startup: {' '.join(args)} failed on {src}:\n{p.stderr[-2000:]}")
    seconds = None
    if "--json" in args and "map" in args:
        seconds = float(json.loads(p.stdout)["seconds"])
    return wall, seconds


def _load() -> str:
    try:
        return " ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:  # pragma: no cover - not on this platform
        return "n/a"


def measure(
    cmds: dict[str, list[str]], trees: dict[str, Path], repeat: int
) -> tuple[dict[str, dict[str, list[float]]], dict[str, list[float]]]:
    """Wall times of every command on every tree (after one warm-up run each), and the analyses' own
    times of the map; the trees alternate within a run, their order swapped every run."""
    for args in cmds.values():  # warm: numba cache compiled and loaded, files in the page cache
        for src in trees.values():
            run(args, src)
    times: dict[str, dict[str, list[float]]] = {name: {t: [] for t in trees} for name in cmds}
    analyses: dict[str, list[float]] = {t: [] for t in trees}
    for k in range(repeat):
        for name, args in cmds.items():
            for t in list(trees) if k % 2 == 0 else list(reversed(trees)):
                wall, secs = run(args, trees[t])
                times[name][t].append(wall)
                if secs is not None:
                    analyses[t].append(secs)
    return times, analyses


def report(times: dict[str, dict[str, list[float]]], analyses: dict[str, list[float]]) -> dict:
    """Print the medians (and the old / new ratio, and the targets); returns the medians."""
    trees = list(next(iter(times.values())))
    med = {name: {t: statistics.median(v) for t, v in per.items()} for name, per in times.items()}
    head = f"{'command':16s}" + "".join(f"{t + ' median':>14s}{t + ' min':>10s}" for t in trees)
    print(head + ("   old / new" if "old" in trees else "") + "   target")
    for name, per in times.items():
        line = f"{name:16s}" + "".join(f"{med[name][t]:12.3f} s{min(per[t]):8.3f} s" for t in trees)
        if "old" in trees:
            line += f"{med[name]['old'] / med[name]['new']:10.2f}x"
        if name in TARGETS_S:
            ok = "met" if med[name]["new"] <= TARGETS_S[name] else "not met"
            line += f"   {TARGETS_S[name]:g} s: {ok}"
        print(line)
    for t, v in analyses.items():
        if v:
            print(f"map: the analyses themselves ({t}) median {statistics.median(v):.3f} s of the wall time")
    return med


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=7, help="timed runs of each command and tree (default 7)")
    ap.add_argument("--baseline-src", help="another source tree to compare with (its src/ folder)")
    ap.add_argument("--records", help="records directory with IMV79-EMO (default $ISOROCK_RECORDS)")
    ap.add_argument("--only", help="comma-separated names of the commands to time (default all)")
    ap.add_argument("--json", help="write every time and the medians to this JSON file")
    a = ap.parse_args()
    records = _records_dir(a.records)
    cmds = commands(records)
    if a.only:
        wanted = a.only.split(",")
        unknown = [w for w in wanted if w not in cmds]
        if unknown:
            sys.exit(f"bench_startup: unknown command(s) {unknown}: valid {', '.join(cmds)}")
        cmds = {k: v for k, v in cmds.items() if k in wanted}
    trees = {"old": Path(a.baseline_src).resolve(), "new": SRC} if a.baseline_src else {"new": SRC}
    where = records or f"pyslammer sample {SAMPLE}"
    print(f"records: {where}; trees: " + ", ".join(f"{k} {v}" for k, v in trees.items()))
    load_before = _load()
    print(f"load average before: {load_before} ({os.cpu_count()} CPUs)")
    times, analyses = measure(cmds, trees, a.repeat)
    load_after = _load()
    med = report(times, analyses)
    print(f"load average after: {load_after}")
    if a.json:
        out = {
            "trees": {t: str(p) for t, p in trees.items()},
            "records": str(records) if records else f"pyslammer:{SAMPLE}",
            "commands": {name: " ".join(args) for name, args in cmds.items()},
            "repeat": a.repeat,
            "cpus": os.cpu_count(),
            "load_before": load_before,
            "load_after": load_after,
            "times_s": times,
            "median_s": med,
            "map_analyses_s": analyses,
            "map_analyses_median_s": {t: statistics.median(v) for t, v in analyses.items() if v},
            "targets_s": TARGETS_S,
        }
        Path(a.json).write_text(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
