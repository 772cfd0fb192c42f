"""How the workflow scales on a cluster, simulated from the job times of a measured run.

Every rule of the workflow writes a Snakemake ``benchmark:`` file per job
(``results/benchmarks/<rule>/<wildcards>.tsv``: wall time ``s`` and peak memory ``max_rss`` in MB).
This script reads them from the working directory of a finished run, rebuilds the job graph (per
record: process_record (and its pulse) -> min_overturn, regime_maps; per block of records the assessment
jobs (their records read from their job files); the pulse
studies on their own; merge after every job, then figures, then report_tables) and schedules it, by
list scheduling with the longest remaining path first, on 1, 4, 16 and 64 nodes of ``--cores`` CPUs
each (a job holds its threads' CPUs for its measured time). It prints the DAG's width, the critical
path, the per-rule times and memory, and the makespan on each cluster size, in Markdown
(``docs/scaling.md`` quotes it).

Usage::

    python benchmarks/scaling.py RUN_DIR [RUN_DIR ...] [--cores 32] [--overhead 5] [--objects N]

``--overhead`` adds seconds to every SLURM job (queueing, the job's Snakemake start-up). Both ways of
submitting are simulated: one SLURM job per Snakemake job, and the grouping of
``workflow/profiles/slurm`` (the jobs of 8 records in one SLURM job, 4 assessment jobs in one, the pulse
studies in one, merge-figures-report tables in one; each on at most 8 CPUs), which pays the overhead
once per group. ``--objects N`` repeats the assessment jobs of the run for N objects (a collection).

The measured times come from a run on the machine that ran it, with as many jobs at once as it had
cores: a job's time includes its Python start-up and the loading of the compiled engine. A cluster's
nodes and their load differ; the ratios between the cluster sizes are what to read.
"""

from __future__ import annotations

import argparse
import csv
import heapq
import json
import math
import re
from collections import defaultdict
from dataclasses import dataclass, field
from pathlib import Path

import h5py

PER_RECORD_AFTER_PULSE = {"min_overturn", "regime_maps"}
PER_RECORD_AFTER_PROCESS = {"extract_pulse", "assess_stripes", "assess_design"}
#: the {block} wildcard of the assessment jobs (resources.records_per_job records each)
BLOCK = re.compile(r"b[0-9]+")
#: the folder of each assessment rule's job files
JOB_FOLDER = {"assess_stripes": "assess", "assess_design": "design"}
FINAL = ("merge", "figures", "report_tables")
THREADED = {"regime_maps", "pulse_maps", "assess_design"}  # on resources.map_threads; the others on 1
GROUP = {
    "process_record": "record",
    "extract_pulse": "record",
    "min_overturn": "record",
    "regime_maps": "record",
    "assess_stripes": "assess",
    "assess_design": "assess",
    "pulse_overturn": "pulses",
    "pulse_maps": "pulses",
    "merge": "final",
    "figures": "final",
    "report_tables": "final",
}


@dataclass
class Job:
    """One job of a measured run: its rule, wildcards, wall time (s), peak memory (MB) and threads."""

    rule: str
    key: str
    seconds: float
    max_rss_mb: float
    threads: int
    record: str | None = None
    deps: list[int] = field(default_factory=list)

    @property
    def group(self) -> str:
        return GROUP.get(self.rule, self.rule)


def read_jobs(run_dir: Path) -> list[Job]:
    """The jobs of the run in ``run_dir``, with their dependencies."""
    bench = run_dir / "results" / "benchmarks"
    if not bench.is_dir():
        raise SystemExit(f"{bench}: no benchmark files (run the workflow there first)")
    with h5py.File(run_dir / "results" / "isorock.h5", "r") as f:
        threads = int(json.loads(f.attrs["config_json"])["resources"]["map_threads"])
    jobs: list[Job] = []
    for tsv in sorted(bench.rglob("*.tsv")):
        rule = tsv.relative_to(bench).parts[0]
        key = str(tsv.relative_to(bench / rule).with_suffix(""))
        with open(tsv) as fh:
            row = next(csv.DictReader(fh, delimiter="\t"))
        rss = float(row["max_rss"]) if row.get("max_rss", "NA") not in ("NA", "-", "") else math.nan
        record = key.rsplit("/", 1)[-1] if GROUP[rule] in ("record", "assess") else None
        jobs.append(Job(rule, key, float(row["s"]), rss, threads if rule in THREADED else 1, record))
    index = {(j.rule, j.key): i for i, j in enumerate(jobs)}
    finals = {r: index.get((r, r)) for r in FINAL}
    for j in jobs:
        if j.rule in PER_RECORD_AFTER_PROCESS:
            recs = [j.record]
            if j.rule in JOB_FOLDER and BLOCK.fullmatch(j.record or ""):  # a block: its records
                recs = block_records(run_dir / "results" / "jobs" / JOB_FOLDER[j.rule] / f"{j.key}.h5")
            j.deps += [index[("process_record", r)] for r in recs]
        elif j.rule in PER_RECORD_AFTER_PULSE:  # the pulse: its own job in runs before issue 18
            j.deps.append(index.get(("extract_pulse", j.record), index[("process_record", j.record)]))
        elif j.rule == "merge":
            j.deps += [k for k, o in enumerate(jobs) if o.rule not in FINAL]
        elif j.rule in ("figures", "report_tables"):
            j.deps.append(finals["merge"])
            if j.rule == "report_tables":
                j.deps.append(finals["figures"])
    return jobs


def block_records(job_file: Path) -> list[str]:
    """The records of an assessment job's block: the ``record`` attribute of each table in its file."""
    out: list[str] = []
    with h5py.File(job_file, "r") as h:
        h.visititems(lambda _name, obj: out.append(obj.attrs["record"]) if "record" in obj.attrs else None)
    return [r.decode() if isinstance(r, bytes) else str(r) for r in out]


def _children(jobs: list[Job]) -> dict[int, list[int]]:
    """The jobs that wait for each job."""
    children = defaultdict(list)
    for i, j in enumerate(jobs):
        for d in j.deps:
            children[d].append(i)
    return children


def _tail(jobs: list[Job]) -> list[float]:
    """Each job's longest path to the end of the run (its own time included), in s."""
    children = _children(jobs)
    order = _topological(jobs)
    tail = [0.0] * len(jobs)
    for i in reversed(order):
        tail[i] = jobs[i].seconds + max((tail[c] for c in children[i]), default=0.0)
    return tail


def _topological(jobs: list[Job]) -> list[int]:
    indeg = [len(j.deps) for j in jobs]
    children = _children(jobs)
    ready = [i for i, n in enumerate(indeg) if n == 0]
    out = []
    while ready:
        i = ready.pop()
        out.append(i)
        for c in children[i]:
            indeg[c] -= 1
            if indeg[c] == 0:
                ready.append(c)
    return out


def width(jobs: list[Job], threads: bool = False) -> int:
    """The most jobs (``threads``: their threads) running at once with unlimited CPUs, each job started
    as soon as its inputs are there."""
    start = [0.0] * len(jobs)
    for i in _topological(jobs):
        start[i] = max((start[d] + jobs[d].seconds for d in jobs[i].deps), default=0.0)
    weight = [j.threads if threads else 1 for j in jobs]
    events = sorted(
        [(start[i] + j.seconds, -weight[i]) for i, j in enumerate(jobs)]
        + [(start[i], weight[i]) for i in range(len(jobs))]
    )  # at equal times, ends before starts
    run = best = 0
    for _, e in events:
        run += e
        best = max(best, run)
    return best


def simulate(jobs: list[Job], cpus: int, overhead_s: float = 0.0) -> float:
    """Makespan (s) of list scheduling on ``cpus`` CPUs, longest remaining path first; ``overhead_s``
    is added to every job's time."""
    tail = _tail(jobs)
    indeg = [len(j.deps) for j in jobs]
    children = _children(jobs)
    ready = [(-tail[i], i) for i, n in enumerate(indeg) if n == 0]
    heapq.heapify(ready)
    running: list[tuple[float, int]] = []
    free, now = cpus, 0.0
    waiting: list[tuple[float, int]] = []
    while ready or running or waiting:
        # start whatever fits, most urgent first
        skipped = []
        while ready:
            p, i = heapq.heappop(ready)
            need = min(jobs[i].threads, cpus)
            if need <= free:
                free -= need
                heapq.heappush(running, (now + jobs[i].seconds + overhead_s, i))
            else:
                skipped.append((p, i))
        for s in skipped:
            heapq.heappush(ready, s)
        if not running:
            break
        now, i = heapq.heappop(running)
        free += min(jobs[i].threads, cpus)
        for c in children[i]:
            indeg[c] -= 1
            if indeg[c] == 0:
                heapq.heappush(ready, (-tail[c], c))
    return now


def _subgraph(jobs: list[Job], members: list[int]) -> list[Job]:
    pos = {m: k for k, m in enumerate(members)}
    return [
        Job(
            jobs[m].rule,
            jobs[m].key,
            jobs[m].seconds,
            jobs[m].max_rss_mb,
            jobs[m].threads,
            jobs[m].record,
            [pos[d] for d in jobs[m].deps if d in pos],
        )  # fmt: skip
        for m in members
    ]


def grouped(jobs: list[Job], records_per_job: int = 8, assess_per_job: int = 4, cpus: int = 8) -> list[Job]:
    """The jobs as the slurm profile submits them (``group-components``): the jobs of 8 records in one
    SLURM job, 4 assessment jobs in one, the pulse studies in one, merge-figures-report tables in one;
    each SLURM job on at most ``cpus`` CPUs (the profile's ``cores``), its time the makespan of its own
    jobs on them."""
    records = sorted({j.record for j in jobs if j.group == "record"})
    batches = {r: k // records_per_job for k, r in enumerate(records)}
    out: list[Job] = []

    def add(name: str, members: list[int], deps: list[int]) -> int:
        sub = _subgraph(jobs, members)
        n = min(cpus, width(sub, threads=True))
        out.append(Job("group", name, simulate(sub, n), max(j.max_rss_mb for j in sub), n, None, deps))
        return len(out) - 1

    group_of: dict[int, int] = {}  # a record job -> its SLURM job
    for b in sorted(set(batches.values())):
        members = [i for i, j in enumerate(jobs) if j.group == "record" and batches[j.record] == b]
        g = add(f"record-{b}", members, [])
        group_of.update(dict.fromkeys(members, g))
    assess = sorted(
        (i for i, j in enumerate(jobs) if j.group == "assess"), key=lambda i: (jobs[i].record, jobs[i].key)
    )
    for k in range(0, len(assess), assess_per_job):
        members = assess[k : k + assess_per_job]
        deps = sorted({group_of[d] for i in members for d in jobs[i].deps if d in group_of})
        add(f"assess-{k // assess_per_job}", members, deps)
    pulses = [i for i, j in enumerate(jobs) if j.group == "pulses"]
    if pulses:
        add("pulses", pulses, [])
    final = [i for i, j in enumerate(jobs) if j.rule in FINAL]
    t_final = sum(jobs[i].seconds for i in final)
    out.append(
        Job("final", "final", t_final, max(jobs[i].max_rss_mb for i in final), 1, None, list(range(len(out))))
    )
    return out


def more_objects(jobs: list[Job], n_objects: int) -> list[Job]:
    """The run with ``n_objects`` objects: the measured assessment jobs of its objects repeated (object
    k takes the jobs of measured object k mod n), the merge after all of them."""
    objs = sorted({j.key.split("/")[0] for j in jobs if j.group == "assess"})
    if not objs:
        raise SystemExit("--objects: the run has no assessment jobs")
    out = [Job(j.rule, j.key, j.seconds, j.max_rss_mb, j.threads, j.record, list(j.deps)) for j in jobs]
    for k in range(len(objs), n_objects):
        src = objs[k % len(objs)]
        for j in jobs:
            if j.group == "assess" and j.key.split("/")[0] == src:
                key = f"obj{k}/" + j.key.split("/", 1)[1]
                out.append(Job(j.rule, key, j.seconds, j.max_rss_mb, j.threads, j.record, list(j.deps)))
    merge = next(i for i, j in enumerate(out) if j.rule == "merge")
    out[merge].deps = [i for i, j in enumerate(out) if j.rule not in FINAL]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs", nargs="+", type=Path, help="working directories of finished runs")
    ap.add_argument("--cores", type=int, default=32, help="CPUs per node (default 32)")
    ap.add_argument("--overhead", type=float, default=5.0, help="s added to every SLURM job (default 5)")
    ap.add_argument("--objects", type=int, default=None, help="repeat the assessment jobs for N objects")
    a = ap.parse_args()
    for run in a.runs:
        jobs = read_jobs(run)
        if a.objects:
            jobs = more_objects(jobs, a.objects)
        per_rule: dict[str, list[Job]] = defaultdict(list)
        for j in jobs:
            per_rule[j.rule].append(j)
        total = sum(j.seconds * j.threads for j in jobs)
        print(f"## {run}" + (f", {a.objects} objects" if a.objects else "") + "\n")
        print(f"{len(jobs)} jobs, {total / 60:.1f} CPU-minutes in all; DAG width {width(jobs)} jobs; "
              f"critical path {max(_tail(jobs)):.0f} s\n")  # fmt: skip
        print("| rule | jobs | threads | median s | max s | max memory MB |")
        print("|---|---:|---:|---:|---:|---:|")
        for rule, js in sorted(per_rule.items(), key=lambda kv: -sum(j.seconds for j in kv[1])):
            ts = sorted(j.seconds for j in js)
            print(f"| {rule} | {len(js)} | {js[0].threads} | {ts[len(ts) // 2]:.1f} | {ts[-1]:.1f} | "
                  f"{max(j.max_rss_mb for j in js):.0f} |")  # fmt: skip
        print()
        g = grouped(jobs)
        print(f"| nodes ({a.cores} CPUs each) | makespan, one SLURM job per job (s) | "
              f"makespan, grouped as the slurm profile: {len(g)} SLURM jobs (s) |")  # fmt: skip
        print("|---:|---:|---:|")
        for nodes in (1, 4, 16, 64):
            cpus = nodes * a.cores
            t1 = simulate(jobs, cpus, a.overhead)
            t2 = simulate(g, cpus, a.overhead)
            print(f"| {nodes} | {t1:.0f} | {t2:.0f} |")
        print(f"\nfor reference, 2 CPUs: {simulate(jobs, 2):.0f} s (no overhead)\n")


if __name__ == "__main__":
    main()
