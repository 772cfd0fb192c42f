# One job per record and step: process and pulse -> minimum overturning PGA, regime maps.


# process_record: one job per batch of records (PROCESS_BATCHES, workflow/rules/common.smk: at most
# resources.records_per_job records, and as many jobs as resources.map_threads where there are enough
# records): each record processed, then its velocity pulse, two files per record (a job's Python
# start-up takes longer than either step of a record). A rule per batch (process_record_p0, ...): a
# rule's outputs are the files of its records, which the per-record rules below take as inputs.
for _batch, _ids in PROCESS_BATCHES.items():

    rule:
        name:
            f"process_record_{_batch}"
        input:
            batch_files(_ids),
        output:
            records=[f"{JOBS}/records/{rec}.h5" for rec in _ids],
            pulses=[f"{JOBS}/pulse/{rec}.h5" for rec in _ids],
        params:
            batch=_batch,
            p=[pipeline.params_process(config, PLAN.spec(rec), PLAN.processing) for rec in _ids],
            pulse=pipeline.params_pulse(config),
        resources:
            **_sized("process_record", 4 + math.ceil(len(_ids) * 10 / 60), largest=True),
        group:
            "record"
        benchmark:
            f"results/benchmarks/process_record/{_batch}.tsv"
        log:
            f"logs/process_record/{_batch}.log",
        conda:
            "../envs/isorock.yaml"
        script:
            "../scripts/process_record.py"


rule min_overturn:
    input:
        record=f"{JOBS}/records/{{rec}}.h5",
        pulse=f"{JOBS}/pulse/{{rec}}.h5",
    output:
        f"{JOBS}/overturn/{{rec}}.h5",
    params:
        p=lambda wc: pipeline.params_overturn(config, wc.rec),
    resources:
        **RESOURCES["min_overturn"],
    group:
        "record"
    benchmark:
        "results/benchmarks/min_overturn/{rec}.tsv"
    log:
        "logs/min_overturn/{rec}.log",
    conda:
        "../envs/isorock.yaml"
    script:
        "../scripts/min_overturn.py"


rule regime_maps:
    input:
        record=f"{JOBS}/records/{{rec}}.h5",
        pulse=f"{JOBS}/pulse/{{rec}}.h5",
    output:
        f"{JOBS}/maps/{{rec}}.h5",
    params:
        p=lambda wc: pipeline.params_maps(config, PLAN.spec(wc.rec)),
    threads: MAP_THREADS
    resources:
        **RESOURCES["regime_maps"],
    group:
        "record"
    benchmark:
        "results/benchmarks/regime_maps/{rec}.tsv"
    log:
        "logs/regime_maps/{rec}.log",
    conda:
        "../envs/isorock.yaml"
    script:
        "../scripts/regime_maps.py"
