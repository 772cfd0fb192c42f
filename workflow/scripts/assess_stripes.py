"""Rule assess_stripes: one object, one isolation case, one record, every stripe
(isorock.pipeline.assess_record)."""

from isorock import pipeline

w = snakemake.wildcards
with pipeline.script_logging(snakemake.log[0], f"assess_stripes {w.obj} {w.case} {w.rec}"):
    pipeline.assess_record(
        snakemake.input[0], snakemake.output[0], threads=snakemake.threads, **snakemake.params.p
    )
