"""Rule regime_maps: response-regime maps of one record (isorock.pipeline.regime_maps)."""

from isorock import pipeline

with pipeline.script_logging(snakemake.log[0], f"regime_maps {snakemake.wildcards.rec}"):
    pipeline.regime_maps(
        snakemake.input.record,
        snakemake.output[0],
        pulse_h5=snakemake.input.pulse,
        threads=snakemake.threads,
        **snakemake.params.p,
    )
