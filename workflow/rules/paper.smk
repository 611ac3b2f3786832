"""The paper's learned-model evaluation of every method's final frame, and its Table 1.

Image-text metrics (CLIP, SigLIP 2) and MLLM judges run only when their models are in the models
config (`models:` in the config; entries `metrics-clip`, `metrics-siglip`, `judge`, `judge-2`):
one job per scene each, so a model is loaded once per scene, not per image. Without them the
tables hold the ground-truth columns and name what adds the others.
"""


rule metrics:
    input:
        constraints="results/instructions/{scene}/constraints.json",
        results=scene_results(METRIC_METHODS),
    output:
        "results/metrics/{scene}.csv",
    log:
        "results/logs/metrics/{scene}.log",
    benchmark:
        "results/benchmarks/metrics/{scene}.tsv"
    params:
        methods=method_specs(METRIC_METHODS),
        models=config.get("models", ""),
    shell:
        "capframe metrics --scene {wildcards.scene:q} --constraints {input.constraints:q} --method {params.methods:q} "
        "--models {params.models:q} -o {output:q} > {log:q} 2>&1"


rule judge:
    input:
        constraints="results/instructions/{scene}/constraints.json",
        results=scene_results(JUDGED_METHODS),
    output:
        "results/judges/{scene}.json",
    log:
        "results/logs/judges/{scene}.log",
    benchmark:
        "results/benchmarks/judges/{scene}.tsv"
    params:
        methods=method_specs(JUDGED_METHODS),
        models=config.get("models", ""),
        seed=config.get("judge_seed", 0),
    shell:
        "capframe judge --scene {wildcards.scene:q} --constraints {input.constraints:q} --method {params.methods:q} "
        "--models {params.models:q} --cache results/views/{wildcards.scene:q} --seed {params.seed:q} -o {output:q} > {log:q} 2>&1"


rule quantitative:
    input:
        tables=expand("results/tables/{method}.csv", method=TABLE1_METHODS),
        metrics=METRIC_FILES,
        judgements=JUDGE_FILES,
        userstudy=userstudy_input,
    output:
        table=report("results/tables/quantitative.csv", caption="../report/quantitative.rst", category="Tables"),
        markdown="results/tables/quantitative.md",
    log:
        "results/logs/aggregate/quantitative.log",
    benchmark:
        "results/benchmarks/tables/quantitative.tsv"
    params:
        # The caption names what was not measured and what adds it.
        missing=lambda wc, input: MISSING_COLUMNS + ([] if input.userstudy else [USERSTUDY_NOTE]),
        metrics=lambda wc, input: ["--metrics", *input.metrics] if input.metrics else [],
        judgements=lambda wc, input: ["--judgements", *input.judgements] if input.judgements else [],
        userstudy=lambda wc, input: ["--userstudy", *input.userstudy] if input.userstudy else [],
    shell:
        "capframe quantitative {input.tables:q} {params.metrics:q} {params.judgements:q} {params.userstudy:q} "
        "-o {output.table:q} > {log:q} 2>&1"
