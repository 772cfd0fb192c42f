"""Rule process_record: read, process and check each record of a batch (isorock.pipeline.process_record),
then extract its velocity pulse and Tp (isorock.pipeline.extract_pulse): isorock.pipeline.process_records."""

from isorock import pipeline

with pipeline.script_logging(snakemake.log[0], f"process_record {snakemake.params.batch}"):
    pipeline.process_records(
        snakemake.params.p, snakemake.output.records, snakemake.output.pulses, pulse=snakemake.params.pulse
    )
