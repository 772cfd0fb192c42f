"""Rule process_record: read, process and check one record (isorock.pipeline.process_record), then
extract its velocity pulse and Tp (isorock.pipeline.extract_pulse)."""

from isorock import pipeline

with pipeline.script_logging(snakemake.log[0], f"process_record {snakemake.wildcards.rec}"):
    pipeline.process_record(out=snakemake.output.record, **snakemake.params.p)
    pipeline.extract_pulse(snakemake.output.record, snakemake.output.pulse, **snakemake.params.pulse)
