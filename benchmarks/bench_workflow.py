"""What the workflow costs beside its analyses (issue 18: an assessment costs what its analyses cost).

Measured in one run, on the same machine and records:

1. **In-process**: the analyses of the worked assessment (``config/assessment.yaml``) in this one
   Python process: the package functions that the job scripts call (``workflow/scripts/*.py``), over
   every job of the workflow, with the same parameters (:mod:`isorock.control.plan`) and the same
   blocks of records (``resources.records_per_job``): process and pulse of every record, the stripes
   of every object, case and block, the design search of every object and block, the merge, the
   figures and the report tables.
2. **Workflow**: ``isorock assess config/assessment.yaml --cores N`` (Snakemake, then its report) in
   a temporary copy of the working directory.

It prints both, their ratio, the jobs Snakemake ran, and whether the two ``/assessment`` tables of the
two stores hold the same numbers. ``--main`` also times the main job, ``isorock report --cores N``
with the default configuration on the pyslammer samples (no records directory), once to warm the
numba cache unless ``--no-warm``, then from a clean working directory.

Usage::

    python benchmarks/bench_workflow.py                          # records: $ISOROCK_RECORDS
    python benchmarks/bench_workflow.py --records ../shared/records --main

Both runs load the compiled engine from the numba cache (run once before: the first run compiles it,
about 20 s); absolute times depend on the machine and its load, so compare the ratio.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

from isorock import pipeline
from isorock.resources import workflow_root

ROOT = workflow_root()
CONFIG = ROOT / "config" / "assessment.yaml"


def in_process(records: Path, work: Path) -> tuple[dict[str, float], Path, int]:
    """The analyses of every job of the worked assessment, in this process, in ``work``.

    Returns
    -------
    dict of str to float
        Seconds per rule (and ``total``).
    Path
        The store written (``work/results/isorock.h5``).
    int
        The number of job bodies run.
    """
    config = pipeline.workflow_config(CONFIG, {"records": {"dir": str(records)}})
    plan = pipeline.plan(config, basedir=work)
    threads = int(config["resources"]["map_threads"])
    blocks = pipeline.record_blocks(plan.ids, int(config["resources"]["records_per_job"]))
    a = config["assessment"]
    jobs = work / "results" / "jobs"
    times: dict[str, float] = {}
    count = 0

    def timed(rule: str, fn, *args, **kw) -> None:
        nonlocal count
        t0 = time.perf_counter()
        with pipeline.script_logging(work / "in-process.log", rule):  # as in the jobs: to a log file
            fn(*args, **kw)
        times[rule] = times.get(rule, 0.0) + time.perf_counter() - t0
        count += 1

    outputs: list[Path] = []
    for spec in plan.records:
        rec, pulse = jobs / "records" / f"{spec.id}.h5", jobs / "pulse" / f"{spec.id}.h5"
        for p in (rec, pulse):
            p.parent.mkdir(parents=True, exist_ok=True)
        timed("process_record", pipeline.process_record, out=rec,
              **pipeline.params_process(config, spec, plan.processing))  # fmt: skip
        timed("extract_pulse", pipeline.extract_pulse, rec, pulse, **pipeline.params_pulse(config))
        outputs += [rec, pulse]
    for obj in (o["name"] for o in a["objects"]):
        for case in a["cases"]:
            for b, ids in blocks.items():
                out = jobs / "assess" / obj / case / f"{b}.h5"
                out.parent.mkdir(parents=True, exist_ok=True)
                timed("assess_stripes", pipeline.assess_records,
                      [jobs / "records" / f"{r}.h5" for r in ids], out, threads=threads,
                      **pipeline.params_assess(config, obj, case))  # fmt: skip
                outputs.append(out)
        if a.get("design_grid"):
            design = []
            for b, ids in blocks.items():
                out = jobs / "design" / obj / f"{b}.h5"
                out.parent.mkdir(parents=True, exist_ok=True)
                timed("assess_design", pipeline.design_records,
                      [jobs / "records" / f"{r}.h5" for r in ids], out, threads=threads,
                      **pipeline.params_design(config, obj))  # fmt: skip
                outputs.append(out)
                design.append(out)
            if a["design_grid"].get("extend", True):
                out = jobs / "design_extend" / f"{obj}.h5"
                out.parent.mkdir(parents=True, exist_ok=True)
                timed("assess_design_extend", pipeline.design_extend, design,
                      [jobs / "records" / f"{r}.h5" for r in plan.ids], out, threads=threads,
                      **pipeline.params_extend(config, obj))  # fmt: skip
                outputs.append(out)
    store = work / "results" / "isorock.h5"
    timed("merge", pipeline.merge, outputs, store, config=config, source=plan.source, config_name=CONFIG.stem)
    figs = work / "results" / "figures"
    timed("figures", pipeline.figures, store, figs)
    timed("report_tables", pipeline.report_tables, store, work / "results" / "report", figdir=figs)
    times["total"] = sum(times.values())
    return times, store, count


def snakemake_jobs(text: str) -> int | None:
    """The total of the first 'Job stats' table of a Snakemake output."""
    m = re.search(r"^total\s+(\d+)$", text, re.M)
    return int(m.group(1)) if m else None


def workflow(args: list[str], work: Path, env: dict[str, str] | None = None) -> tuple[float, int | None]:
    """Seconds of ``isorock ARGS`` in ``work`` and the jobs Snakemake ran (its output in ``work/run.log``)."""
    t0 = time.perf_counter()
    res = subprocess.run(
        [sys.executable, "-m", "isorock.cli", *args], cwd=work, env=env, capture_output=True, text=True
    )
    secs = time.perf_counter() - t0
    (work / "run.log").write_text(res.stdout + res.stderr)
    if res.returncode != 0:
        raise SystemExit(f"isorock {' '.join(args)} failed in {work}:\n{res.stderr[-3000:]}")
    return secs, snakemake_jobs(res.stderr + res.stdout)


def same_assessment(a: Path, b: Path) -> list[str]:
    """The /assessment tables that differ between two stores (empty: the same numbers)."""
    with pd.HDFStore(a, "r") as sa, pd.HDFStore(b, "r") as sb:
        keys = sorted(k for k in set(sa.keys()) | set(sb.keys()) if k.startswith("/assessment/"))
        bad = []
        for k in keys:
            if k not in sa or k not in sb:
                bad.append(k)
                continue
            x, y = sa[k], sb[k]
            if list(x.columns) != list(y.columns) or x.shape != y.shape:
                bad.append(k)
                continue
            for c in x.columns:
                u, v = x[c].to_numpy(), y[c].to_numpy()
                if u.dtype.kind == "f" and v.dtype.kind == "f":
                    ok = np.array_equal(u, v, equal_nan=True)
                else:
                    ok = [str(e) for e in u] == [str(e) for e in v]
                if not ok:
                    bad.append(f"{k}:{c}")
        return bad


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--records", type=Path, default=os.environ.get("ISOROCK_RECORDS"),
                    help="records directory (default: $ISOROCK_RECORDS)")  # fmt: skip
    ap.add_argument("--cores", type=int, default=2)
    ap.add_argument("--main", action="store_true", help="also time the main job (isorock report)")
    ap.add_argument("--no-warm", action="store_true", help="--main: no warm-up run first")
    ap.add_argument("--keep", type=Path, default=None, help="keep the working directories under this folder")
    a = ap.parse_args()
    if a.records is None or not Path(a.records).is_dir():
        raise SystemExit("give the records directory: --records DIR or $ISOROCK_RECORDS")
    records = Path(a.records).resolve()
    if a.keep:
        a.keep.mkdir(parents=True, exist_ok=True)
    base = Path(tempfile.mkdtemp(prefix="bench-workflow-", dir=a.keep))
    try:
        inproc = base / "in-process"
        inproc.mkdir()
        times, store_a, n_bodies = in_process(records, inproc)
        print(f"in-process: {n_bodies} job bodies in {times['total']:.1f} s")
        for rule, s in times.items():
            if rule != "total":
                print(f"  {rule:15s} {s:6.1f} s")
        wd = base / "workflow"
        (wd / "config").mkdir(parents=True)
        shutil.copy2(CONFIG, wd / "config" / CONFIG.name)
        args = ["assess", f"config/{CONFIG.name}", "--cores", str(a.cores), "--records", str(records)]
        secs, n_jobs = workflow(args, wd)
        print(f"workflow:   isorock assess --cores {a.cores}: {n_jobs} jobs in {secs:.1f} s (and its report)")
        print(f"ratio workflow / in-process: {secs / times['total']:.2f}")
        diff = same_assessment(store_a, wd / "results" / "isorock.h5")
        same = "the same numbers" if not diff else f"differ: {diff}"
        print(f"/assessment tables of the two stores: {same}")
        if a.main:
            env = {k: v for k, v in os.environ.items() if k != "ISOROCK_RECORDS"}
            main_wd = base / "main"
            main_wd.mkdir()
            if not a.no_warm:
                workflow(["report", "--cores", str(a.cores)], main_wd, env)  # warms the numba cache
                for p in ("results", ".snakemake/metadata", "logs"):  # a clean rerun, the same cache
                    shutil.rmtree(main_wd / p, ignore_errors=True)
                (main_wd / "report.html").unlink(missing_ok=True)
            secs, n_jobs = workflow(["report", "--cores", str(a.cores)], main_wd, env)
            print(f"main job:   isorock report --cores {a.cores} (samples): {n_jobs} jobs in {secs:.1f} s")
    finally:
        if a.keep is None:
            shutil.rmtree(base, ignore_errors=True)
        else:
            print(f"kept: {base}")


if __name__ == "__main__":
    main()
