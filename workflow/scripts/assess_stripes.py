"""Rule assess_stripes: one object, one isolation case, a block of records, every stripe
(isorock.pipeline.assess_records)."""

from isorock import pipeline

w = snakemake.wildcards
with pipeline.script_logging(snakemake.log[0], f"assess_stripes {w.obj} {w.case} {w.block}"):
    pipeline.assess_records(
        list(snakemake.input), snakemake.output[0], threads=snakemake.threads, **snakemake.params.p
    )
