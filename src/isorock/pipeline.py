"""The workflow's Python API in one place: what the Snakefile, its scripts and users call.

This module only gathers names; it defines none. The code lives in three rooms, data flowing one way
(``report`` and ``jobs`` read ``control``; ``control`` reads neither):

- :mod:`isorock.control`: the configuration (:mod:`~isorock.control.config`, validated against
  ``workflow/schemas/config.schema.yaml``, which also gives the defaults), the plan (records present,
  the jobs and their parameters, :mod:`~isorock.control.plan`), the cost, lock and integrity of a run,
  and the run itself (:func:`run_workflow`: ``snakemake``, then ``snakemake --report``; what
  ``isorock report`` and ``isorock assess`` call);
- :mod:`isorock.jobs`: the rules' functions (the bodies of ``workflow/scripts/*.py``) and
  :func:`merge`, which builds ``results/isorock.h5`` (layout in :mod:`isorock.store`);
- :mod:`isorock.report`: the report's pages, landing page and Jinja2 templates (the assessment's text
  is :mod:`isorock.assessment.summary`).

The DAG::

    process_record (1 per batch of records: process_record, then extract_pulse, of each)
        -> min_overturn (1 per record)
        -> regime_maps (1 per record)
        -> assess_stripes (1 per object, isolation case and block of records)
        -> assess_design (1 per object and block of records)
    pulse_overturn (1 per pulse shape), pulse_maps (1 per pulse of Fig 6)
    all of the above -> merge (results/isorock.h5) -> figures (results/figures/*.png)
                                                   -> report_tables (results/report/*)
    snakemake --report report.html  (landing page results/report/landing.rst; captions workflow/report/*.rst)

Lengths in m, times in s, accelerations in g. The rule bodies are imported on first use: Snakemake
parses the Snakefile again for every job, and the parse needs only the configuration and the plan,
not the numerical modules of the rule bodies.
"""

from __future__ import annotations

import importlib
from typing import Any

# the configuration and the plan, imported now (the Snakefile's parse needs them); the rest on first use
from isorock.control.config import (
    IsolationCase,
    apply_studies_default,
    grid_values,
    isolation_cases,
    load_config,
    validate_config,
    workflow_config,
)
from isorock.control.plan import (
    Plan,
    RecordFile,
    RecordSpec,
    design_runs,
    params_assess,
    params_design,
    params_extend,
    params_maps,
    params_overturn,
    params_process,
    params_pulse,
    params_pulse_maps,
    params_pulse_overturn,
    plan,
    process_batches,
    pulse_source,
    record_blocks,
)
from isorock.control.run import RunResult, RunSettings, default_report_name, prepare_run, run_workflow

#: the rule bodies, imported on first use: public name -> module of this package
_WHERE = {
    "extract_pulse": "isorock.jobs.record",
    "min_overturn": "isorock.jobs.record",
    "process_record": "isorock.jobs.record",
    "process_records": "isorock.jobs.record",
    "regime_maps": "isorock.jobs.record",
    "script_logging": "isorock.control.joblog",
    "pulse_maps": "isorock.jobs.pulses",
    "pulse_overturn": "isorock.jobs.pulses",
    "assess_records": "isorock.jobs.assessment",
    "design_records": "isorock.jobs.assessment",
    "design_extend": "isorock.jobs.design",
    "merge": "isorock.jobs.merge",
    "figures": "isorock.report.build",
    "report_tables": "isorock.report.build",
}

__all__ = [
    "IsolationCase",
    "Plan",
    "RecordFile",
    "RecordSpec",
    "RunResult",
    "RunSettings",
    "apply_studies_default",
    "default_report_name",
    "assess_records",
    "design_records",
    "design_extend",
    "design_runs",
    "extract_pulse",
    "figures",
    "grid_values",
    "isolation_cases",
    "load_config",
    "merge",
    "min_overturn",
    "params_assess",
    "params_design",
    "params_extend",
    "params_maps",
    "params_overturn",
    "params_process",
    "params_pulse",
    "params_pulse_maps",
    "params_pulse_overturn",
    "plan",
    "prepare_run",
    "process_batches",
    "process_record",
    "process_records",
    "pulse_maps",
    "pulse_overturn",
    "pulse_source",
    "record_blocks",
    "regime_maps",
    "report_tables",
    "run_workflow",
    "script_logging",
    "validate_config",
    "workflow_config",
]


def __getattr__(name: str) -> Any:
    mod = _WHERE.get(name)
    if mod is None:
        raise AttributeError(f"module 'isorock.pipeline' has no attribute {name!r}")
    value = getattr(importlib.import_module(mod), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_WHERE))
