"""Rule extract_pulse: velocity pulse and Tp of one record (isorock.pipeline.extract_pulse)."""

from isorock import pipeline

with pipeline.script_logging(snakemake.log[0], f"extract_pulse {snakemake.wildcards.rec}"):
    pipeline.extract_pulse(snakemake.input[0], snakemake.output[0], **snakemake.params.p)
