"""The control of a run: its configuration, its plan and its bounds, its cost, its lock and its
integrity checks, and the run itself (``snakemake``, then its report).

:mod:`~.config` (the configuration, validated against ``workflow/schemas/config.schema.yaml``),
:mod:`~.bounds` (the plausible ranges of its values), :mod:`~.plan` (records present, the jobs and
their parameters), :mod:`~.lengths`, :mod:`~.memory` and :mod:`~.cost` (what the jobs will cost),
:mod:`~.runlock`, :mod:`~.integrity` and :mod:`~.caches` (stale or foreign state), :mod:`~.joblog`
(how a job reports to the run) and :mod:`~.run` (:func:`~isorock.control.run.run_workflow`).
"""
