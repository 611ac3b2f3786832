"""Ground-truth checks and tables, for every method alike."""


wildcard_constraints:
    method="|".join(METHOD_RESULTS),


rule check:
    input:
        scene="results/scenes/{scene}",
        result=lambda wc: METHOD_RESULTS[wc.method].format(scene=wc.scene, instruction=wc.instruction),
        constraints="results/instructions/{scene}/constraints.json",
    output:
        "results/check/{method}/{scene}/{instruction}.json",
    log:
        "results/logs/check/{method}/{scene}/{instruction}.log",
    benchmark:
        "results/benchmarks/check/{method}/{scene}/{instruction}.tsv"
    shell:
        "capframe check {input.scene} {input.result}/result.json --constraints {input.constraints} "
        "--id {wildcards.instruction} -o {output} > {log} 2>&1"


rule aggregate:
    input:
        checks=lambda wc: per_instruction(f"results/check/{wc.method}/{{scene}}/{{instruction}}.json")(wc),
        results=lambda wc: per_instruction(METHOD_RESULTS[wc.method])(wc),
    output:
        "results/tables/{method}.csv",
    log:
        "results/logs/aggregate/{method}.log",
    params:
        results=lambda wc, input: [f"{r}/result.json" for r in input.results],
    shell:
        "capframe aggregate --method {wildcards.method} --checks {input.checks} --results {params.results} "
        "-o {output} > {log} 2>&1"


rule compare:
    input:
        expand("results/tables/{method}.csv", method=METHOD_RESULTS),
    output:
        table=report("results/tables/methods.csv", caption="../report/methods.rst", category="Tables"),
        markdown="results/tables/methods.md",
        plot=report("results/tables/methods_pareto.png", caption="../report/pareto.rst", category="Tables"),
    log:
        "results/logs/aggregate/methods.log",
    shell:
        "capframe compare {input} -o {output.table} > {log} 2>&1"
