"""Rule min_overturn: minimum overturning PGA of one record (isorock.pipeline.min_overturn)."""

from isorock import pipeline

with pipeline.script_logging(snakemake.log[0], f"min_overturn {snakemake.wildcards.rec}"):  # noqa: F821
    pipeline.min_overturn(
        snakemake.input.record,  # noqa: F821
        snakemake.output[0],  # noqa: F821
        pulse_h5=snakemake.input.pulse,  # noqa: F821
        **snakemake.params.p,  # noqa: F821
    )
