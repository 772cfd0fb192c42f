"""Rule merge: the job files -> results/isorock.h5 (isorock.pipeline.merge)."""

from isorock import pipeline

with pipeline.script_logging(snakemake.log[0], "merge"):  # noqa: F821
    pipeline.merge(
        snakemake.input,  # noqa: F821
        snakemake.output[0],  # noqa: F821
        config=snakemake.params.config,  # noqa: F821
        source=snakemake.params.source,  # noqa: F821
    )
