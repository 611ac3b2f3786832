"""CapFrame workflow: synthetic benchmark scenes, instructions, the method and its oracle variant, evaluation.

Run with `make run` (or `snakemake --cores 2 --workflow-profile workflow/profiles/default`).
Every stage is a `capframe` verb; outputs live under results/.
"""


configfile: "config/config.yaml"


report: "workflow/report/workflow.rst"


include: "workflow/rules/common.smk"
include: "workflow/rules/synth.smk"
include: "workflow/rules/method.smk"
include: "workflow/rules/refine.smk"
include: "workflow/rules/paper.smk"
include: "workflow/rules/evaluate.smk"
include: "workflow/rules/report.smk"


onstart:
    start_warm_server()


onsuccess:
    stop_warm_server()


onerror:
    stop_warm_server()


rule all:
    input:
        # Listed so that every scene's instructions are scheduled at once (an input function can
        # only report one incomplete checkpoint at a time).
        CONSTRAINTS,
        # The parse checkpoints before the results that depend on them (see parse_outputs()).
        [parse_outputs(method) for method in VARIANTS],
        # Every method's per-instruction result and check are targets, so that deleting one of
        # them reruns it and what is built from it (Snakemake does not regenerate a deleted
        # intermediate file while the files built from it exist).
        [per_instruction(pattern) for pattern in METHOD_RESULTS.values()],
        [per_instruction(f"results/check/{method}/{{scene}}/{{instruction}}.json") for method in METHOD_RESULTS],
        "results/tables/runtime.csv",
        "results/tables/quantitative.csv",
