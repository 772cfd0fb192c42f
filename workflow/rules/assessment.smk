# Assessment of real objects (config "assessment"): one job per object, isolation case and block of
# records (every stripe, full runs), one per object and block for the isolation design search. The
# blocks (BLOCKS, workflow/rules/common.smk) hold resources.records_per_job records at most: a job
# that lasts seconds rather than one that spends most of its time starting Python. The design search
# runs on resources.map_threads threads.


rule assess_stripes:
    input:
        block_records,
    output:
        f"{JOBS}/assess/{{obj}}/{{case}}/{{block}}.h5",
    params:
        p=lambda wc: pipeline.params_assess(config, wc.obj, wc.case),
    # one thread: a few levels per record, and the first-overturning search is sequential
    threads: 1
    resources:
        **RESOURCES["assess_stripes"],
    group:
        "assess"
    benchmark:
        "results/benchmarks/assess_stripes/{obj}/{case}/{block}.tsv"
    log:
        "logs/assess_stripes/{obj}/{case}/{block}.log",
    script:
        "../scripts/assess_stripes.py"


rule assess_design:
    input:
        block_records,
    output:
        f"{JOBS}/design/{{obj}}/{{block}}.h5",
    params:
        p=lambda wc: pipeline.params_design(config, wc.obj),
    threads: MAP_THREADS
    resources:
        **RESOURCES["assess_design"],
    group:
        "assess"
    benchmark:
        "results/benchmarks/assess_design/{obj}/{block}.tsv"
    log:
        "logs/assess_design/{obj}/{block}.log",
    script:
        "../scripts/assess_design.py"
