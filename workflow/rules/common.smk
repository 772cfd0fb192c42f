# Shared set-up: the run plan (records present, pulse jobs), paths and wildcard constraints.

import math
import os
import sys

from isorock import pipeline
from isorock.errors import IsorockError
from isorock.control.memory import job_memory_mb

try:
    PLAN = pipeline.plan(config)  # relative paths of the configuration: the working directory
except IsorockError as _exc:  # one line, no traceback
    sys.exit(f"isorock: error: {_exc}")
# what isorock report has already said (isorock.control.run.SAID_ENV): the warnings of the records
# check, before the run; the run's status line too, when this parse is the report's (snakemake --report)
_SAID = os.environ.get("ISOROCK_SAID", "")
for _w in PLAN.warnings if _SAID not in ("warnings", "all") else ():
    print(f"isorock: warning: {_w}", file=sys.stderr)
if _SAID != "all":
    print(
        f"isorock: {len(PLAN.records)} record(s) from {PLAN.source}; studies: "
        f"{', '.join(config['studies']) or 'none'}; "
        + (
            f"assessment of {len(config['assessment']['objects'])} object(s) on "
            f"{len(config['assessment']['cases'])} isolation case(s)"
            if config.get("assessment")
            else "no assessment"
        ),
        file=sys.stderr,
    )

RECORDS = PLAN.ids
# the configuration's name (the last --configfile, else the default config.yaml), written in the store
CONFIG_FILES = [str(f) for f in workflow.overwrite_configfiles] or ["config/config.yaml"]
CONFIG_NAME = os.path.splitext(os.path.basename(CONFIG_FILES[-1]))[0]
# the report of this configuration, as `isorock report` names it: the pages of results/report link to it
REPORT = pipeline.default_report_name(CONFIG_FILES[-1])
JOBS = "results/jobs"
STORE = "results/isorock.h5"
MAP_THREADS = int(config["resources"]["map_threads"])
# the records of each assessment job: block name (b0, b1, ...) -> record ids (resources.records_per_job)
BLOCKS = pipeline.record_blocks(RECORDS, int(config["resources"]["records_per_job"]))
# the records of each process_record job: batch name (p0, p1, ...) -> record ids (at most
# resources.records_per_job, over at least resources.map_threads jobs where there are enough records)
PROCESS_BATCHES = pipeline.process_batches(RECORDS, int(config["resources"]["records_per_job"]), MAP_THREADS)


def _input_mb(files):
    """The size of a job's input files that exist [MB] (not Snakemake's input.size_mb, which warns of
    an unawaited coroutine when the report evaluates it)."""
    total = 0
    for f in files:
        try:
            total += os.path.getsize(f)
        except OSError:  # not made yet: Snakemake evaluates the resources again before the job runs
            pass
    return total / 2**20


def _largest_input_mb(files):
    """The size of the largest of a job's input files that exist [MB]."""
    return max((_input_mb([f]) for f in files), default=0.0)


def _sized(rule, minutes, largest=False):
    """Cluster resources of one job: memory (MB: at least the rule's floor, more for long records, from
    the size of its input, or of its largest input file for a job that reads its records one after
    the other: isorock.control.memory) and run time (min, a number or a function of the wildcards),
    both doubled on each retry (the slurm profile's restart-times)."""
    runtime = minutes if callable(minutes) else (lambda wildcards: minutes)
    size = _largest_input_mb if largest else _input_mb
    return {
        "mem_mb": lambda wildcards, input, attempt: job_memory_mb(rule, size(input)) * attempt,
        "runtime": lambda wildcards, attempt: runtime(wildcards) * attempt,
    }


def _stripes_minutes(wildcards):
    """Run time of one stripes job: 5 s per record of its block (its stripes and first-overturning
    search; measured: 0.1 to 0.3 s), plus 4 min to start."""
    return 4 + math.ceil(len(BLOCKS[wildcards.block]) * 5 / 60)


def _design_minutes(wildcards):
    """Run time of one design-search job: 20 ms per run (isolator x level x record of its block;
    measured: about 4 ms per run and thread for a friction pendulum, docs/scaling.md) on its threads,
    plus 4 min to start."""
    runs = pipeline.design_runs(config, wildcards.obj) * len(BLOCKS[wildcards.block])
    return 4 + math.ceil(runs * 0.020 / MAP_THREADS / 60)


def _extend_minutes(wildcards):
    """Run time of one grid extension: at most pipeline.design_search.MAX_ROUNDS rounds of one line of
    isolators on every record; sized as one design job of every record per round it is likely to need
    (a few), plus the rankings (seconds each) and 4 min to start."""
    runs = pipeline.design_runs(config, wildcards.obj) * max(len(RECORDS), 1)
    return 4 + math.ceil(3 * runs * 0.020 / MAP_THREADS / 60)


# Memory (MB) and run time (min) of every rule's jobs on a cluster (threads: each rule's own), sized
# from the benchmark files (results/benchmarks/<rule>/*.tsv) of the measured runs in docs/scaling.md:
# every job there peaked below 400 MB, and the slowest took 48 s (min_overturn, paper run); the floors
# of 1 GB and 5-10 min leave room for a first job that compiles the engine (about a minute), longer
# records and larger grids. A job of a record longer than the default bounds (records.max_samples)
# declares more memory, from its input's size (isorock.control.memory, benchmarks/bench_memory.py).
# Locally these values only matter under --resources.
RESOURCES = {  # process_record's, per batch: workflow/rules/records.smk
    "min_overturn": _sized("min_overturn", 10),
    "regime_maps": _sized("regime_maps", 10),
    "assess_stripes": _sized("assess_stripes", _stripes_minutes),
    "assess_design": _sized("assess_design", _design_minutes),
    "assess_design_extend": _sized("assess_design_extend", _extend_minutes),
    "pulse_overturn": _sized("pulse_overturn", 5),
    "pulse_maps": _sized("pulse_maps", 5),
    "merge": _sized("merge", 10),
    "figures": _sized("figures", 10),
    "report_tables": _sized("report_tables", 5),
}


wildcard_constraints:
    rec="[A-Za-z0-9][A-Za-z0-9_.+-]*",
    obj="[A-Za-z0-9][A-Za-z0-9_.+-]*",
    case="[A-Za-z0-9][A-Za-z0-9_.+]*",
    shape="rect|halfsine|fullsine",
    src="pulse-[a-z]+-td[0-9.e+-]+",
    block="b[0-9]+",


def block_records(wildcards):
    """The processed records of an assessment job's block (inputs of assess_stripes, assess_design)."""
    return [f"{JOBS}/records/{rec}.h5" for rec in BLOCKS[wildcards.block]]


def batch_files(ids):
    """The candidate files of some records (inputs of a process_record job: a changed file reruns it)."""
    files = [f.path for rec in ids for f in PLAN.spec(rec).files]
    return list(dict.fromkeys(files)) + ([PLAN.processing] if PLAN.processing else [])


STUDIES = set(config["studies"])
ASSESSMENT = config.get("assessment") or {}


def job_outputs():
    """Every job file merged into the store."""
    out = []
    for rec in RECORDS:
        out += [f"{JOBS}/records/{rec}.h5", f"{JOBS}/pulse/{rec}.h5"]
        if "overturn" in STUDIES:
            out.append(f"{JOBS}/overturn/{rec}.h5")
        if "maps" in STUDIES:
            out.append(f"{JOBS}/maps/{rec}.h5")
    if "pulses" in STUDIES:
        out += [f"{JOBS}/pulses/overturn-{s}.h5" for s in PLAN.pulse_shapes]
        out += [f"{JOBS}/pulses/maps-{s}.h5" for s in PLAN.pulse_sources]
    for obj in ASSESSMENT.get("objects", []):  # in the order of the records (merge: /assessment/runs)
        for case in ASSESSMENT["cases"]:
            out += [f"{JOBS}/assess/{obj['name']}/{case}/{b}.h5" for b in BLOCKS]
        if ASSESSMENT.get("design_grid"):
            out += [f"{JOBS}/design/{obj['name']}/{b}.h5" for b in BLOCKS]
            if ASSESSMENT["design_grid"].get("extend", True):
                out.append(f"{JOBS}/design_extend/{obj['name']}.h5")
    return out


def final_targets():
    return [
        STORE,
        "results/report/records.html",
        "results/report/paper.html",
        "results/report/assessment.html",
        "results/report/landing.rst",
        "results/report/overturn.html",
        "results/report/maps.html",
        "results/report/records",
        "results/figures",
    ]


# The report (workflow/rules/report.smk): the pages of the studies that ran, and the subcategory of each
# figure (rule figures, workflow/rules/store.smk).
_STUDIES = set(config.get("studies", ("overturn", "maps", "pulses")))
_REPORTED = {
    "assessment": bool(config.get("assessment")),
    "overturn": "overturn" in _STUDIES,
    "maps": bool({"maps", "pulses"} & _STUDIES),
}


def figure_group(wildcards):
    """The subcategory of a figure of rule figures under 'Figures' (isorock.figures.figure_group)."""
    from isorock.figures import figure_group as group

    return group(wildcards.name)


def _page(path, study, **kw):
    """``path`` flagged for the report when ``study`` ran, else a plain output."""
    return report(path, **kw) if _REPORTED[study] else path
