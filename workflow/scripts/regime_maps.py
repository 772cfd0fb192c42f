"""Rule regime_maps: response-regime maps of one record (isorock.pipeline.regime_maps)."""

from isorock import pipeline

with pipeline.script_logging(snakemake.log[0], f"regime_maps {snakemake.wildcards.rec}"):  # noqa: F821
    pipeline.regime_maps(
        snakemake.input.record,  # noqa: F821
        snakemake.output[0],  # noqa: F821
        pulse_h5=snakemake.input.pulse,  # noqa: F821
        threads=snakemake.threads,  # noqa: F821
        **snakemake.params.p,  # noqa: F821
    )
