"""Rule figures: the paper's figures from the store (isorock.figures.make_all via isorock.pipeline)."""

from isorock import pipeline

with pipeline.script_logging(snakemake.log[0], "figures"):
    pipeline.figures(snakemake.input[0], snakemake.output[0], workers=snakemake.threads)
