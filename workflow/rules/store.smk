# Merge the job files into the store, then draw the figures from it.


rule merge:
    input:
        job_outputs(),
    output:
        STORE,
    params:
        config=config,
        source=PLAN.source,
        config_name=CONFIG_NAME,
    # the fits of the assessment's bases are independent: made by as many processes
    threads: MAP_THREADS
    resources:
        **RESOURCES["merge"],
    group:
        "final"
    benchmark:
        "results/benchmarks/merge/merge.tsv"
    log:
        "logs/merge.log",
    conda:
        "../envs/isorock.yaml"
    script:
        "../scripts/merge.py"


rule figures:
    input:
        STORE,
    output:
        report(
            directory("results/figures"),
            patterns=["{name}.png"],
            caption="../report/figures.rst",
            category="Figures",
            subcategory=lambda wildcards: figure_group(wildcards),  # workflow/rules/common.smk
        ),
    # the figures are independent: drawn by as many processes (20 s alone at the end of the main job)
    threads: MAP_THREADS
    resources:
        **RESOURCES["figures"],
    group:
        "final"
    benchmark:
        "results/benchmarks/figures/figures.tsv"
    log:
        "logs/figures.log",
    conda:
        "../envs/isorock.yaml"
    script:
        "../scripts/figures.py"
