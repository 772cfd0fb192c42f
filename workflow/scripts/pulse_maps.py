"""Rule pulse_maps: lambda-R regime maps under one pulse (isorock.pipeline.pulse_maps)."""

from isorock import pipeline

with pipeline.script_logging(snakemake.log[0], f"pulse_maps {snakemake.wildcards.src}"):
    pipeline.pulse_maps(snakemake.output[0], threads=snakemake.threads, **snakemake.params.p)
