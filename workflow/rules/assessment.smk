# Assessment of real objects (config "assessment"): one job per object, isolation case and block of
# records (every stripe, full runs), one per object and block for the isolation design search. The
# blocks (BLOCKS, workflow/rules/common.smk) hold resources.records_per_job records at most: a job
# that lasts seconds rather than one that spends most of its time starting Python. The design search
# runs on resources.map_threads threads; one job per object then extends its grid where the best
# isolator lies on an edge (assess_design_extend, isorock.jobs.design).


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
    conda:
        "../envs/isorock.yaml"
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
    conda:
        "../envs/isorock.yaml"
    script:
        "../scripts/assess_design.py"


rule assess_design_extend:
    input:
        design=lambda wc: [f"{JOBS}/design/{wc.obj}/{b}.h5" for b in BLOCKS],
        records=[f"{JOBS}/records/{rec}.h5" for rec in RECORDS],
    output:
        f"{JOBS}/design_extend/{{obj}}.h5",
    params:
        p=lambda wc: pipeline.params_extend(config, wc.obj),
    threads: MAP_THREADS
    resources:
        **RESOURCES["assess_design_extend"],
    # after every design block of its object, before the merge: with the serial tail (in the "assess"
    # group it would join all of an object's design blocks into one cluster job)
    group:
        "final"
    benchmark:
        "results/benchmarks/assess_design_extend/{obj}.tsv"
    log:
        "logs/assess_design_extend/{obj}.log",
    conda:
        "../envs/isorock.yaml"
    script:
        "../scripts/assess_design_extend.py"
