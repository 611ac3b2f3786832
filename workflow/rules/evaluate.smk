"""Ground-truth checks and tables, for every method alike."""


wildcard_constraints:
    method="|".join(map(re.escape, METHOD_RESULTS)),


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
    priority: EVALUATE_PRIORITY
    shell:
        "capframe check {input.scene:q} {input.result:q}/result.json --constraints {input.constraints:q} "
        "--id {wildcards.instruction:q} --cache results/truth/{wildcards.scene:q} -o {output:q} > {log:q} 2>&1"


rule aggregate:
    input:
        # First: the parse checkpoints enter the DAG before the results that depend on them.
        parsed=lambda wc: parse_outputs(wc.method)(wc),
        constraints=CONSTRAINTS,
        checks=lambda wc: per_instruction(f"results/check/{wc.method}/{{scene}}/{{instruction}}.json")(wc),
        results=lambda wc: per_instruction(METHOD_RESULTS[wc.method])(wc),
    output:
        "results/tables/{method}.csv",
    log:
        "results/logs/aggregate/{method}.log",
    benchmark:
        "results/benchmarks/tables/{method}.tsv"
    params:
        results=lambda wc, input: [f"{r}/result.json" for r in input.results],
    shell:
        "capframe aggregate --method {wildcards.method:q} --checks {input.checks:q} --results {params.results:q} "
        "-o {output:q} > {log:q} 2>&1"


rule compare:
    input:
        expand("results/tables/{method}.csv", method=METHOD_RESULTS),
    output:
        table=report("results/tables/methods.csv", caption="../report/methods.rst", category="Tables"),
        markdown="results/tables/methods.md",
    log:
        "results/logs/aggregate/methods.log",
    benchmark:
        "results/benchmarks/tables/methods.tsv"
    shell:
        "capframe compare {input:q} -o {output.table:q} > {log:q} 2>&1"


rule groups:
    input:
        tables=expand("results/tables/{method}.csv", method=GROUP_METHODS),
        metrics=METRIC_FILES,
    output:
        table=report("results/tables/groups.csv", caption="../report/groups.rst", category="Tables"),
        markdown="results/tables/groups.md",
    log:
        "results/logs/aggregate/groups.log",
    benchmark:
        "results/benchmarks/tables/groups.tsv"
    params:
        groups=[f"{scene}={SCENES[scene].group}" for scene in SCENES],
        metrics=["--metrics", *METRIC_FILES] if METRIC_FILES else [],
        missing=MISSING_COLUMNS,
    shell:
        "capframe groups {input.tables:q} --group {params.groups:q} {params.metrics:q} -o {output.table:q} > {log:q} 2>&1"


VARIANT_NAMES = [v for v in VARIANTS if v != "capframe"]


rule sensitivity:
    input:
        constraints=CONSTRAINTS,
        checks=lambda wc: [c for v in VARIANTS for c in per_instruction(f"results/check/{v}/{{scene}}/{{instruction}}.json")(wc)],
        results=lambda wc: [r for v in VARIANTS for r in per_instruction(METHOD_RESULTS[v])(wc)],
        metrics=METRIC_FILES,
    output:
        table=report("results/tables/sensitivity.csv", caption="../report/sensitivity.rst", category="Tables"),
        markdown="results/tables/sensitivity.md",
    log:
        "results/logs/aggregate/sensitivity.log",
    benchmark:
        "results/benchmarks/tables/sensitivity.tsv"
    params:
        variants=[f"{v}=results/refine/{v}" for v in VARIANT_NAMES],
        metrics=["--metrics", *METRIC_FILES] if METRIC_FILES else [],
        missing=MISSING_COLUMNS,
    shell:
        "capframe sensitivity --reference results/refine/capframe --variant {params.variants:q} --checks-root results/check "
        "--scenes-root results/scenes {params.metrics:q} -o {output.table:q} > {log:q} 2>&1"


rule scene_table:
    input:
        scenes=expand("results/scenes/{scene}", scene=SCENES),
        colmap=[f"results/colmap/{s}" for s in SCENES if not SCENES[s].poses],
        gravity=[f"results/gravity/{s}.json" for s in SCENES if not aligned(s)],
    output:
        table=report("results/tables/scenes.csv", caption="../report/scenes.rst", category="Tables"),
        markdown="results/tables/scenes.md",
    log:
        "results/logs/aggregate/scenes.log",
    benchmark:
        "results/benchmarks/tables/scenes.tsv"
    shell:
        "capframe scene-table --scenes-root results/scenes --colmap-root results/colmap --gravity-root results/gravity "
        "-o {output.table:q} > {log:q} 2>&1"


rule runtime:
    input:
        # Last: every job's benchmark file exists once these do.
        "results/tables/groups.csv",
        "results/tables/scenes.csv",
        "results/tables/quantitative.csv",
        ["results/tables/sensitivity.csv"] if VARIANT_NAMES else [],
        per_instruction("results/report/grid/{scene}/{instruction}.png"),
        CONSTRAINTS,
        methods="results/tables/methods.csv",
    output:
        table=report("results/tables/runtime.csv", caption="../report/runtime.rst", category="Tables"),
        methods="results/tables/runtime_methods.csv",
        markdown="results/tables/runtime.md",
        mllm=report("results/tables/runtime_mllm.csv", caption="../report/runtime_mllm.rst", category="Tables"),
        points="results/tables/runtime_pareto.csv",
        plot=report("results/tables/runtime_pareto.png", caption="../report/pareto.rst", category="Tables"),
    log:
        "results/logs/aggregate/runtime.log",
    benchmark:
        "results/benchmarks/tables/runtime.tsv"
    shell:
        "capframe runtime --benchmarks results/benchmarks --methods-table {input.methods:q} --results-root results "
        "-o {output.table:q} > {log:q} 2>&1"
