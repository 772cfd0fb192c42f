"""Rule assess_design: one object, one record, every isolator of the design grid
(isorock.pipeline.design_record)."""

from isorock import pipeline

w = snakemake.wildcards
with pipeline.script_logging(snakemake.log[0], f"assess_design {w.obj} {w.rec}"):
    pipeline.design_record(
        snakemake.input[0], snakemake.output[0], threads=snakemake.threads, **snakemake.params.p
    )
