"""Rule report_tables: HTML tables of the results for the report (isorock.pipeline.report_tables)."""

from pathlib import Path

from isorock import pipeline

with pipeline.script_logging(snakemake.log[0], "report_tables"):
    pipeline.report_tables(
        snakemake.input.store,
        Path(snakemake.output.records).parent,
        figdir=snakemake.input.figures,
        report=snakemake.params.report,  # relative to the working directory, where the report is written
    )
