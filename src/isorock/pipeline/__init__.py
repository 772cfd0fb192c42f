"""The science of the Snakemake workflow: one function per rule, taking configuration dicts and paths.

The workflow (``Snakefile``, ``workflow/rules/*.smk``) only wires these functions together; its
scripts (``workflow/scripts/*.py``) are a few lines that call them. Modules: :mod:`~.config` (the
configuration loader and validator, also used by the Snakefile), :mod:`~.plan` (records present,
pulse jobs, rule parameters), :mod:`~.jobs` and :mod:`~.pulse_jobs` (rule bodies), :mod:`~.merge`
(the store) and :mod:`~.report` (report tables, figures). The DAG::

    process_record (1 per record) -> extract_pulse (1 per record) -> min_overturn (1 per record)
                                                                  -> regime_maps (1 per record)
    pulse_overturn (1 per pulse shape), pulse_maps (1 per pulse of Fig 6)
    all of the above -> merge (results/isorock.h5) -> figures (results/figures/*.png)
                                                   -> report_tables (results/report/*.html)
    snakemake --report report.html  (captions in workflow/report/*.rst)

Records come from :func:`plan` (:mod:`isorock.pipeline.plan`). Every job writes one HDF5 file
atomically (:mod:`isorock.store`); :func:`merge` builds ``results/isorock.h5`` (layout in
:mod:`isorock.store`).

Configuration: ``config/config.yaml`` merged with the user's ``--configfile``, validated against
``workflow/schemas/config.schema.yaml`` (which also gives the defaults) by
:func:`~isorock.pipeline.config.validate_config`. Lengths in m, times in s, accelerations in g.
"""

from .config import (
    IsolationCase,
    grid_values,
    isolation_cases,
    load_config,
    validate_config,
    workflow_config,
)
from .jobs import extract_pulse, min_overturn, process_record, regime_maps, script_logging
from .merge import merge
from .plan import (
    Plan,
    RecordFile,
    RecordSpec,
    params_maps,
    params_overturn,
    params_process,
    params_pulse,
    params_pulse_maps,
    params_pulse_overturn,
    plan,
    pulse_source,
)
from .pulse_jobs import pulse_maps, pulse_overturn
from .report import figures, report_tables

__all__ = [
    "RecordFile",
    "RecordSpec",
    "IsolationCase",
    "Plan",
    "load_config",
    "workflow_config",
    "validate_config",
    "grid_values",
    "isolation_cases",
    "plan",
    "params_process",
    "params_pulse",
    "params_overturn",
    "params_maps",
    "params_pulse_overturn",
    "params_pulse_maps",
    "process_record",
    "extract_pulse",
    "min_overturn",
    "regime_maps",
    "pulse_overturn",
    "pulse_maps",
    "merge",
    "report_tables",
    "figures",
    "script_logging",
    "pulse_source",
]
