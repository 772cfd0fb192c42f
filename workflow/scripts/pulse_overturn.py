"""Rule pulse_overturn: minimum overturning amplitude under one pulse shape (isorock.pipeline)."""

from isorock import pipeline

with pipeline.script_logging(snakemake.log[0], f"pulse_overturn {snakemake.wildcards.shape}"):
    pipeline.pulse_overturn(snakemake.output[0], **snakemake.params.p)
