"""The rules' functions: what each Snakemake rule's script calls (``workflow/scripts/*.py``).

:mod:`~.record` (process a record, extract its pulse, its minimum overturning search and regime
maps), :mod:`~.pulses` (the paper's pulse studies), :mod:`~.assessment` (the stripes and the design
runs of an assessment), :mod:`~.design` (the design search's extension and verdicts) and
:mod:`~.merge` (every job's file into ``results/isorock.h5``). They read the run's configuration and
plan (:mod:`isorock.control`), never the other way round.
"""
