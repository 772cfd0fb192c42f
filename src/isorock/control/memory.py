"""The memory a workflow job declares, from the size of its inputs (the length of its records).

A job's peak memory is the interpreter with the numerical libraries (about 230 MB) plus what its
records take: ``python benchmarks/bench_memory.py`` measured, for records of 6,000 to 120,000 samples
(one-column text, 13 bytes a sample), about 90 MB per MB of record file for ``process_record`` (the
reading, the processing and the wavelet transform of the pulse extraction: about 1.1 kB a sample) and
about 1 MB per MB of input for the jobs that read the processed records (``min_overturn``,
``regime_maps``: the engine keeps no history). A job declares (Snakemake's ``mem_mb``, what a cluster
reserves and kills beyond) the larger of its rule's floor and :data:`BASE_MB` plus
:data:`PER_INPUT_MB` times the size of its input files in MB, times its attempt
(the slurm profile retries a failed job). A text record of 13 bytes a sample is about the most
compact, so the declared memory of a record of another format lies above its need. Within the
default bounds on a record's length (:data:`isorock.records.directory.MAX_SAMPLES`) every job fits
its floor; a record allowed to be longer raises what its jobs declare.
"""

from __future__ import annotations

__all__ = ["FLOOR_MB", "BASE_MB", "PER_INPUT_MB", "job_memory_mb"]

#: the least memory a job of each rule declares [MB] (the benchmark files of the measured runs in
#: docs/scaling.md peaked below 400 MB; the merge and the figures hold the whole store)
FLOOR_MB = {
    "process_record": 1000,
    "min_overturn": 1000,
    "regime_maps": 1000,
    "assess_stripes": 1000,
    "assess_design": 1000,
    "assess_design_extend": 2000,
    "pulse_overturn": 1000,
    "pulse_maps": 1000,
    "merge": 2000,
    "figures": 2000,
    "report_tables": 1000,
}

#: the memory of a job before its records [MB] (measured about 230 MB, with a margin)
BASE_MB = 300
#: memory per MB of a job's input [MB/MB]: process_record measured 87 to 97, the others about 1
PER_INPUT_MB = {"process_record": 100.0}
#: the same for the rules not named in :data:`PER_INPUT_MB` [MB/MB]
DEFAULT_PER_INPUT_MB = 2.0


def job_memory_mb(rule: str, input_mb: float) -> int:
    """The memory a job of ``rule`` declares [MB]: ``max(FLOOR_MB[rule], BASE_MB + k input_mb)``.

    Parameters
    ----------
    rule : str
        The rule (``process_record``, ``min_overturn`` ...).
    input_mb : float
        The size of the job's input files [MB] (0 where Snakemake does not know it yet).
    """
    k = PER_INPUT_MB.get(rule, DEFAULT_PER_INPUT_MB)
    try:
        need = BASE_MB + k * float(input_mb)
    except (TypeError, ValueError):  # not known yet
        need = 0.0
    return int(max(FLOOR_MB[rule], -(-need // 1)))
