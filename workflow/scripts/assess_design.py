"""Rule assess_design: one object, a block of records, every isolator of the design grid
(isorock.pipeline.design_records)."""

from isorock import pipeline

w = snakemake.wildcards
with pipeline.script_logging(snakemake.log[0], f"assess_design {w.obj} {w.block}"):
    pipeline.design_records(
        list(snakemake.input), snakemake.output[0], threads=snakemake.threads, **snakemake.params.p
    )
