"""The science of the Snakemake workflow: one function per rule, taking configuration dicts and paths.

The workflow (``Snakefile``, ``workflow/rules/*.smk``) only wires these functions together; its
scripts (``workflow/scripts/*.py``) are a few lines that call them. Modules: :mod:`~.config` (the
configuration loader and validator, also used by the Snakefile), :mod:`~.plan` (records present,
pulse jobs, rule parameters), :mod:`~.jobs`, :mod:`~.pulse_jobs` and :mod:`~.assessment_jobs` (rule
bodies), :mod:`~.merge` (the store), :mod:`~.report`, :mod:`~.landing` and :mod:`~.pages` (the
report: pages, landing page, their Jinja2 templates; the assessment's text is
:mod:`isorock.assessment.summary`), and :mod:`~.run`, the workflow run from Python
(:func:`run_workflow`: ``snakemake``, then ``snakemake --report``; what ``isorock report``
and ``isorock assess`` call). The DAG::

    process_record (1 per batch of records: process_record, then extract_pulse, of each)
        -> min_overturn (1 per record)
        -> regime_maps (1 per record)
        -> assess_stripes (1 per object, isolation case and block of records)
        -> assess_design (1 per object and block of records)
    pulse_overturn (1 per pulse shape), pulse_maps (1 per pulse of Fig 6)
    all of the above -> merge (results/isorock.h5) -> figures (results/figures/*.png)
                                                   -> report_tables (results/report/*)
    snakemake --report report.html  (landing page results/report/landing.rst; captions workflow/report/*.rst)

Records come from :func:`plan` (:mod:`isorock.pipeline.plan`). Every job writes one HDF5 file
atomically (:mod:`isorock.store`); :func:`merge` builds ``results/isorock.h5`` (layout in
:mod:`isorock.store`).

Configuration: ``config/config.yaml`` merged with the user's ``--configfile``, validated against
``workflow/schemas/config.schema.yaml`` (which also gives the defaults) by
:func:`~isorock.pipeline.config.validate_config`. Lengths in m, times in s, accelerations in g.

The rule bodies are imported on first use: Snakemake parses the Snakefile again for every job, and
the parse needs only the configuration and the plan, not the numerical modules of the rule bodies.
"""

from __future__ import annotations

import importlib
from typing import Any

# light modules, imported now: their names (plan, merge) are also functions, which must win over the
# submodules of the same name
from .config import (
    IsolationCase,
    apply_studies_default,
    grid_values,
    isolation_cases,
    load_config,
    validate_config,
    workflow_config,
)
from .merge import merge
from .plan import (
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
from .run import RunResult, RunSettings, prepare_run, run_workflow

#: the rule bodies, imported on first use: public name -> module of this package
_WHERE = {
    "extract_pulse": "jobs",
    "min_overturn": "jobs",
    "process_record": "jobs",
    "process_records": "jobs",
    "regime_maps": "jobs",
    "script_logging": "jobs",
    "pulse_maps": "pulse_jobs",
    "pulse_overturn": "pulse_jobs",
    "assess_records": "assessment_jobs",
    "design_records": "assessment_jobs",
    "design_extend": "design_search",
    "figures": "report",
    "report_tables": "report",
}

__all__ = [
    "IsolationCase",
    "Plan",
    "RecordFile",
    "RecordSpec",
    "RunResult",
    "RunSettings",
    "apply_studies_default",
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
    value = getattr(importlib.import_module(f".{mod}", __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_WHERE))
