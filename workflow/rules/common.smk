# Shared set-up: the run plan (records present, pulse jobs), paths and wildcard constraints.

import os
import sys

from isorock import pipeline
from isorock.errors import IsorockError

try:
    PLAN = pipeline.plan(config)  # relative paths of the configuration: the working directory
except IsorockError as _exc:  # one line, no traceback
    sys.exit(f"isorock: error: {_exc}")
for _w in PLAN.warnings:
    print(f"isorock: warning: {_w}", file=sys.stderr)
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
JOBS = "results/jobs"
STORE = "results/isorock.h5"
MAP_THREADS = int(config["resources"]["map_threads"])


wildcard_constraints:
    rec="[A-Za-z0-9][A-Za-z0-9_.+-]*",
    obj="[A-Za-z0-9][A-Za-z0-9_.+-]*",
    case="[A-Za-z0-9][A-Za-z0-9_.+]*",
    shape="rect|halfsine|fullsine",
    src="pulse-[a-z]+-td[0-9.e+-]+",


def record_files(wildcards):
    """The candidate files of a record (inputs of process_record: a changed file reruns it)."""
    files = [f.path for f in PLAN.spec(wildcards.rec).files]
    return files + ([PLAN.processing] if PLAN.processing else [])


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
    for obj in ASSESSMENT.get("objects", []):
        for case in ASSESSMENT["cases"]:
            out += [f"{JOBS}/assess/{obj['name']}/{case}/{rec}.h5" for rec in RECORDS]
        if ASSESSMENT.get("design_grid"):
            out += [f"{JOBS}/design/{obj['name']}/{rec}.h5" for rec in RECORDS]
    return out


def final_targets():
    return [
        STORE,
        "results/report/records.html",
        "results/report/assessment.html",
        "results/report/landing.rst",
        "results/report/overturn.html",
        "results/report/maps.html",
        "results/report/records",
        "results/figures",
    ]
