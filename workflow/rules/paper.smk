"""The paper's learned-model evaluation of every method's final frame, and its Table 1.

Image-text metrics (CLIP, SigLIP 2) and MLLM judges run only when their models are in the models
config (`models:` in the config; entries `metrics-clip`, `metrics-siglip`, `judge`, `judge-2`):
one job per scene each, so a model is loaded once per scene, not per image. Without them the
tables hold the ground-truth columns and name what adds the others.
"""

from capframe.backends.models import read_models_config
from capframe.evaluate.judging import JUDGE_HINT, configured_judges
from capframe.evaluate.metrics import METRIC_HINT, METRIC_NAMES, configured_metrics

MODELS = read_models_config(config.get("models"))
METRIC_COLUMNS = configured_metrics(MODELS)
JUDGES = configured_judges(MODELS)
# Metrics score every method and variant (Table 2 compares Retrieve with Refine, Table 3 the
# variants); the judges compare the methods a user can run (the paper's Table 1 rows).
METRIC_METHODS = list(METHOD_RESULTS)
JUDGED_METHODS = ["capframe", *BASELINES]
# Table 1's rows: the methods, then Retrieve alone and Refine from oracle labels for reference.
TABLE1_METHODS = [*JUDGED_METHODS, "retrieve", "oracle"]
METRIC_FILES = [f"results/metrics/{scene}.csv" for scene in SCENES] if METRIC_COLUMNS else []
JUDGE_FILES = [f"results/judges/{scene}.json" for scene in SCENES] if JUDGES else []
# What each absent column needs (the tables' captions).
MISSING_COLUMNS = [f"{METRIC_NAMES[c]}: {METRIC_HINT[c]}" for c in METRIC_HINT if c not in METRIC_COLUMNS]
MISSING_COLUMNS += [] if JUDGES else [f"judge AS and WR: {JUDGE_HINT}"]
# The user study's table, written by `capframe userstudy import` (another tool; optional input).
USERSTUDY = "results/tables/userstudy.csv"
USERSTUDY_NOTE = "user-study rating and preference: run `capframe userstudy import` to add them"


def scene_results(methods):
    """Input function: the result folder of each of ``methods`` for every instruction of the scene."""

    def folders(wildcards):
        ids = instruction_ids(wildcards.scene)
        return [METHOD_RESULTS[m].format(scene=wildcards.scene, instruction=i) for m in methods for i in ids]

    return folders


def method_specs(methods):
    """Params function: ``NAME=DIR`` per method, DIR holding the scene's ``<id>/render.png`` folders."""
    return lambda wc: [f"{m}={os.path.dirname(METHOD_RESULTS[m].format(scene=wc.scene, instruction='x'))}" for m in methods]


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


def userstudy_input(wildcards):
    """The user study's table when `capframe userstudy import` has written it: optional, so the
    workflow never asks for it (and reruns Table 1 once it appears)."""
    return [USERSTUDY] if os.path.exists(USERSTUDY) else []


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
