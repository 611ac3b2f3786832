"""The report: `snakemake --report results/report.html` (or `make report`) collects the tables,
the error-against-run-time plot and one image grid per instruction."""


rule grid:
    input:
        results=lambda wc: [METHOD_RESULTS[m].format(scene=wc.scene, instruction=wc.instruction) for m in REPORT_METHODS],
        checks=lambda wc: [f"results/check/{m}/{wc.scene}/{wc.instruction}.json" for m in REPORT_METHODS],
        constraints="results/instructions/{scene}/constraints.json",
    output:
        report(
            "results/report/grid/{scene}/{instruction}.png",
            caption="../report/grid.rst",
            category="Renders",
            subcategory="{scene}",
        ),
    log:
        "results/logs/grid/{scene}/{instruction}.log",
    benchmark:
        "results/benchmarks/grid/{scene}/{instruction}.tsv"
    priority: EVALUATE_PRIORITY
    params:
        text=instruction_text,
        methods=REPORT_METHODS,
    shell:
        "capframe grid --text {params.text:q} --methods {params.methods:q} --results {input.results:q} "
        "--checks {input.checks:q} -o {output:q} > {log:q} 2>&1"
