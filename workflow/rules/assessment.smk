# Assessment of real objects (config "assessment"): one job per object, isolation case and record
# (every stripe, full runs), one per object and record for the isolation design search.


rule assess_stripes:
    input:
        f"{JOBS}/records/{{rec}}.h5",
    output:
        f"{JOBS}/assess/{{obj}}/{{case}}/{{rec}}.h5",
    params:
        p=lambda wc: pipeline.params_assess(config, wc.obj, wc.case),
    threads: MAP_THREADS
    resources:
        **RESOURCES["assess_stripes"],
    group:
        "assess"
    benchmark:
        "results/benchmarks/assess_stripes/{obj}/{case}/{rec}.tsv"
    log:
        "logs/assess_stripes/{obj}/{case}/{rec}.log",
    script:
        "../scripts/assess_stripes.py"


rule assess_design:
    input:
        f"{JOBS}/records/{{rec}}.h5",
    output:
        f"{JOBS}/design/{{obj}}/{{rec}}.h5",
    params:
        p=lambda wc: pipeline.params_design(config, wc.obj),
    threads: MAP_THREADS
    resources:
        **RESOURCES["assess_design"],
    group:
        "assess"
    benchmark:
        "results/benchmarks/assess_design/{obj}/{rec}.tsv"
    log:
        "logs/assess_design/{obj}/{rec}.log",
    script:
        "../scripts/assess_design.py"
