"""Rule assess_design_extend: one object's design grid, extended where its best isolator lies on an
edge (isorock.pipeline.design_extend)."""

from isorock import pipeline

w = snakemake.wildcards
with pipeline.script_logging(snakemake.log[0], f"assess_design_extend {w.obj}"):
    pipeline.design_extend(
        list(snakemake.input.design),
        list(snakemake.input.records),
        snakemake.output[0],
        threads=snakemake.threads,
        **snakemake.params.p,
    )
