# One job per record and step: process and pulse -> minimum overturning PGA, regime maps.


rule process_record:
    # the record processed, then its velocity pulse: two files, one job (a job's Python start-up
    # takes longer than either step)
    input:
        record_files,
    output:
        record=f"{JOBS}/records/{{rec}}.h5",
        pulse=f"{JOBS}/pulse/{{rec}}.h5",
    params:
        p=lambda wc: pipeline.params_process(config, PLAN.spec(wc.rec), PLAN.processing),
        pulse=pipeline.params_pulse(config),
    resources:
        **RESOURCES["process_record"],
    group:
        "record"
    benchmark:
        "results/benchmarks/process_record/{rec}.tsv"
    log:
        "logs/process_record/{rec}.log",
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
