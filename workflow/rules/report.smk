# Tables of the results for the Snakemake report (snakemake --report report.html).


rule report_tables:
    input:
        store=STORE,
        figures="results/figures",
    output:
        landing="results/report/landing.rst",
        assessment=report(
            "results/report/assessment.html",
            caption="../report/assessment.rst",
            category="Assessment",
        ),
        records=report(
            "results/report/records.html",
            caption="../report/records.rst",
            category="Records",
        ),
        overturn=report(
            "results/report/overturn.html",
            caption="../report/overturn.rst",
            category="Minimum overturning PGA",
        ),
        maps=report(
            "results/report/maps.html",
            caption="../report/maps.rst",
            category="Regime maps",
        ),
        pages=report(
            directory("results/report/records"),
            patterns=["{record}.html"],
            caption="../report/record.rst",
            category="Records",
            subcategory="Per record",
        ),
    resources:
        **RESOURCES["report_tables"],
    group:
        "final"
    benchmark:
        "results/benchmarks/report_tables/report_tables.tsv"
    log:
        "logs/report_tables.log",
    script:
        "../scripts/report_tables.py"
