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

``--statue`` instead times the README's statue (``mystatue.yaml`` of README.md's "Assess your
object": the 18 pyslammer sample records, no records directory): ``isorock assess mystatue.yaml
--cores N`` in a clean working directory, after a warm-up run (the numba cache) unless
``--no-warm``, ``--repeat`` times. It prints, per rule, its jobs and their seconds (wall and CPU, from
the Snakemake ``benchmark:`` file of every job, ``results/benchmarks/<rule>/*.tsv``: each job's own
process, whatever else runs on the machine), the total wall time, and the floor: the same analyses
in this one process (the stripes, the design search and its extension, the merge's fits and
bootstrap; and the processing of the records). ``--old DIR`` runs a second source tree (``DIR/src``
on ``PYTHONPATH``, a ``git worktree`` of an earlier commit) alternately with this one, prints both
tables and their ratios, and whether the two stores' ``/assessment`` tables hold the same numbers.

Usage::

    python benchmarks/bench_workflow.py                          # records: $ISOROCK_RECORDS
    python benchmarks/bench_workflow.py --records ../shared/records --main
    python benchmarks/bench_workflow.py --statue [--old /tmp/old97] [--repeat 2]

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


def in_process(
    records: Path | None, work: Path, config_file: Path = CONFIG
) -> tuple[dict[str, float], Path, int]:
    """The analyses of every job of an assessment (default: the worked one), in this process, in ``work``.

    Returns
    -------
    dict of str to float
        Seconds per rule (and ``total``).
    Path
        The store written (``work/results/isorock.h5``).
    int
        The number of job bodies run.
    """
    config = pipeline.workflow_config(config_file, {"records": {"dir": str(records)}} if records else {})
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
    timed("merge", pipeline.merge, outputs, store, config=config, source=plan.source,
          config_name=config_file.stem)  # fmt: skip
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


def readme_statue() -> str:
    """The text of ``mystatue.yaml``, as README.md's "Assess your object" gives it."""
    text = (ROOT / "README.md").read_text()
    m = re.search(r"```yaml\n(# mystatue\.yaml.*?)```", text, re.S)
    if m is None:
        raise SystemExit("README.md: no ```yaml block starting '# mystatue.yaml'")
    return m.group(1)


def per_rule(work: Path) -> dict[str, tuple[int, float, float]]:
    """Rule -> (jobs, seconds, CPU seconds) of a run in ``work``, from the ``benchmark:`` file of every
    job (``results/benchmarks/<rule>/...tsv``: the job's own process, its start-up included)."""
    out: dict[str, tuple[int, float, float]] = {}
    root = work / "results" / "benchmarks"
    for f in sorted(root.rglob("*.tsv")):
        rule = f.relative_to(root).parts[0]
        row = pd.read_csv(f, sep="\t").iloc[-1]
        n, secs, cpu = out.get(rule, (0, 0.0, 0.0))
        out[rule] = (n + 1, secs + float(row["s"]), cpu + float(row["cpu_time"]))
    return out


def run_statue(work: Path, cores: int, src: Path | None, warm: bool) -> tuple[float, dict]:
    """``isorock assess mystatue.yaml --cores N`` in a clean ``work`` (after a warm-up run there unless
    ``warm`` is False), with ``src`` first on ``PYTHONPATH`` (another source tree) if given: its wall
    seconds and :func:`per_rule`."""
    env = {k: v for k, v in os.environ.items() if k != "ISOROCK_RECORDS"}
    if src is not None:
        env["PYTHONPATH"] = str(src / "src") + os.pathsep + env.get("PYTHONPATH", "")
    work.mkdir(parents=True, exist_ok=True)
    (work / "mystatue.yaml").write_text(readme_statue())
    args = ["assess", "mystatue.yaml", "--cores", str(cores)]
    if warm:
        workflow(args, work, env)  # the numba cache (a source tree of its own compiles once)
    for p in ("results", ".snakemake", "logs"):
        shutil.rmtree(work / p, ignore_errors=True)
    for p in work.glob("report-*.html"):
        p.unlink()
    secs, _ = workflow(args, work, env)
    return secs, per_rule(work)


def print_rules(title: str, secs: float, rules: dict, other: tuple[float, dict] | None = None) -> None:
    """The table of one statue run (and the ratio to ``other``'s, per rule, where given)."""
    print(f"{title}: {secs:.1f} s wall" + (f" (ratio to the other: {secs / other[0]:.2f})" if other else ""))
    print(f"  {'rule':22s} {'jobs':>4s} {'seconds':>8s} {'cpu s':>7s}" + ("  cpu ratio" if other else ""))
    for rule, (n, s, cpu) in sorted(rules.items(), key=lambda kv: -kv[1][2]):
        ratio = ""
        if other and rule in other[1]:
            ratio = f"  {cpu / max(other[1][rule][2], 1e-9):9.2f}"
        print(f"  {rule:22s} {n:4d} {s:8.1f} {cpu:7.1f}{ratio}")
    tot = sum(v[2] for v in rules.values())
    jobs, wall = sum(v[0] for v in rules.values()), sum(v[1] for v in rules.values())
    ratio = f"  {tot / max(sum(v[2] for v in other[1].values()), 1e-9):9.2f}" if other else ""
    print(f"  {'all jobs':22s} {jobs:4d} {wall:8.1f} {tot:7.1f}{ratio}")


def statue(cores: int, old: Path | None, repeat: int, warm: bool, base: Path) -> None:
    """The README's statue: per rule, before (``old``) and now, alternately; then the floor."""
    runs: dict[str, list[tuple[float, dict]]] = {"now": [], "old": []}
    trees = [("now", None)] + ([("old", old)] if old else [])
    for k in range(repeat):
        for name, src in trees:
            secs, rules = run_statue(base / name, cores, src, warm and k == 0)
            runs[name].append((secs, rules))
            print_rules(f"statue, {name} (run {k + 1})", secs, rules, runs["old"][k] if name == "now" and
                        len(runs["old"]) > k else None)  # fmt: skip
            if name == "old":
                print_rules(f"statue, now (run {k + 1}) against old", *runs["now"][k], other=runs["old"][k])
    if old:
        diff = same_assessment(
            base / "old" / "results" / "isorock.h5", base / "now" / "results" / "isorock.h5"
        )
        print(f"/assessment tables, old and now: {'the same numbers' if not diff else f'differ: {diff}'}")
    floor = base / "floor"
    floor.mkdir()
    (floor / "mystatue.yaml").write_text(readme_statue())
    times, _, n = in_process(None, floor, floor / "mystatue.yaml")
    analyses = sum(
        times.get(r, 0.0) for r in ("assess_stripes", "assess_design", "assess_design_extend", "merge")
    )
    print(f"in-process ({n} job bodies, one Python process): " + ", ".join(
        f"{r} {t:.1f} s" for r, t in times.items() if r != "total"))  # fmt: skip
    best = min(secs for secs, _ in runs["now"])
    print(f"floor (the analyses: stripes, design search and extension, the merge's fits and bootstrap): "
          f"{analyses:.1f} s; with the records' processing, the figures and report: {times['total']:.1f} s; "
          f"the workflow now: {best:.1f} s, {best / analyses:.1f} x the floor")  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--records", type=Path, default=os.environ.get("ISOROCK_RECORDS"),
                    help="records directory (default: $ISOROCK_RECORDS)")  # fmt: skip
    ap.add_argument("--cores", type=int, default=2)
    ap.add_argument("--main", action="store_true", help="also time the main job (isorock report)")
    ap.add_argument("--no-warm", action="store_true", help="--main: no warm-up run first")
    ap.add_argument("--keep", type=Path, default=None, help="keep the working directories under this folder")
    ap.add_argument("--statue", action="store_true", help="time the README's statue per rule (no records)")
    ap.add_argument("--old", type=Path, default=None, help="--statue: also an older source tree, alternately")
    ap.add_argument("--repeat", type=int, default=1, help="--statue: runs of each tree")
    a = ap.parse_args()
    if a.statue:
        if a.keep:
            a.keep.mkdir(parents=True, exist_ok=True)
        base = Path(tempfile.mkdtemp(prefix="bench-statue-", dir=a.keep))
        try:
            statue(a.cores, a.old.resolve() if a.old else None, a.repeat, not a.no_warm, base)
        finally:
            if a.keep is None:
                shutil.rmtree(base, ignore_errors=True)
        return
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
