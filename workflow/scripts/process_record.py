"""Rule process_record: read, process and check one record (isorock.pipeline.process_record)."""

from isorock import pipeline

with pipeline.script_logging(snakemake.log[0], f"process_record {snakemake.wildcards.rec}"):
    pipeline.process_record(out=snakemake.output[0], **snakemake.params.p)
