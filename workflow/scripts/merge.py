"""Rule merge: the job files -> results/isorock.h5 (isorock.jobs.merge)."""

from isorock import pipeline

with pipeline.script_logging(snakemake.log[0], "merge"):
    pipeline.merge(
        snakemake.input,
        snakemake.output[0],
        config=snakemake.params.config,
        source=snakemake.params.source,
        config_name=snakemake.params.config_name,
        threads=snakemake.threads,
    )
