"""Rule min_overturn: minimum overturning PGA of one record (isorock.pipeline.min_overturn)."""

from isorock import pipeline

with pipeline.script_logging(snakemake.log[0], f"min_overturn {snakemake.wildcards.rec}"):
    pipeline.min_overturn(
        snakemake.input.record,
        snakemake.output[0],
        pulse_h5=snakemake.input.pulse,
        **snakemake.params.p,
    )
