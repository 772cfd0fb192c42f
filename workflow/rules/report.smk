# Tables of the results for the Snakemake report (snakemake --report report.html).
#
# Every page is written; a page is put in the report only when its study ran (an assessment-only run
# has no 'Regime maps' or 'Minimum overturning PGA' category, a run without assessment no 'Assessment').
# The report embeds every page as a data URL: isorock.report.build keeps each under 1 MiB (Chromium
# shows none over 2 MiB) and attaches the long tables as CSV files.
# _page (a page flagged for the report only when its study ran) is in workflow/rules/common.smk.

rule report_tables:
    input:
        store=STORE,
        figures="results/figures",
    output:
        landing="results/report/landing.rst",
        assessment=_page(
            "results/report/assessment.html",
            "assessment",
            caption="../report/assessment.rst",
            category="Assessment",
        ),
        paper=report(
            "results/report/paper.html",
            caption="../report/paper.rst",
            category="The paper",
        ),
        records=report(
            "results/report/records.html",
            caption="../report/records.rst",
            category="Records",
            subcategory="All records",
        ),
        overturn=_page(
            "results/report/overturn.html",
            "overturn",
            caption="../report/overturn.rst",
            category="Minimum overturning PGA",
        ),
        overturn_csv=_page(
            "results/report/overturn.csv",
            "overturn",
            caption="../report/overturn_csv.rst",
            category="Minimum overturning PGA",
        ),
        maps=_page(
            "results/report/maps.html",
            "maps",
            caption="../report/maps.rst",
            category="Regime maps",
        ),
        maps_csv=_page(
            "results/report/maps.csv",
            "maps",
            caption="../report/maps_csv.rst",
            category="Regime maps",
        ),
        pages=report(
            directory("results/report/records"),
            patterns=["{record}.html"],
            caption="../report/record.rst",
            category="Records",
            subcategory="Per record",
        ),
    params:
        report=REPORT,
    resources:
        **RESOURCES["report_tables"],
    group:
        "final"
    benchmark:
        "results/benchmarks/report_tables/report_tables.tsv"
    log:
        "logs/report_tables.log",
    conda:
        "../envs/isorock.yaml"
    script:
        "../scripts/report_tables.py"
