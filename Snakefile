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
include: "workflow/rules/evaluate.smk"
include: "workflow/rules/report.smk"


rule all:
    input:
        # Listed so that every scene's instructions are scheduled at once (an input function can
        # only report one incomplete checkpoint at a time).
        expand("results/instructions/{scene}/constraints.json", scene=SCENES),
        "results/tables/runtime.csv",
