"""The method per instruction, one rule per stage (retrieve, translate, refine), its variants, and the
per-scene stages it reads.

Stages a scene does not need are left out of its DAG (DESIGN §7): COLMAP only for a scene without
poses, gravity only for a scene that is not aligned; see posed_scene() and gravity_input().
"""


rule colmap:
    input:
        "results/scenes/{scene}",
    output:
        directory("results/colmap/{scene}"),
    log:
        "results/logs/colmap/{scene}.log",
    benchmark:
        "results/benchmarks/colmap/{scene}.tsv"
    shell:
        # Synthetic scenes: the recovered cameras are mapped into the generator's world, where
        # the Gaussians live (a real 3DGS would be trained on the COLMAP poses instead).
        "capframe colmap {input} -o {output} --align-ground-truth > {log} 2>&1"


rule gravity:
    input:
        posed_scene,
    output:
        "results/gravity/{scene}.json",
    log:
        "results/logs/gravity/{scene}.log",
    benchmark:
        "results/benchmarks/gravity/{scene}.tsv"
    shell:
        "capframe gravity {input} -o {output} > {log} 2>&1"


rule label_views:
    input:
        posed_scene,
    output:
        "results/views/{scene}/label_views.npz",
    log:
        "results/logs/views/{scene}.log",
    benchmark:
        "results/benchmarks/views/{scene}.tsv"
    shell:
        "capframe views {input} -o {output} > {log} 2>&1"


wildcard_constraints:
    variant="|".join(VARIANTS),
    baseline="|".join(BASELINES),


rule retrieve:
    input:
        scene=posed_scene,
        views="results/views/{scene}/label_views.npz",
        gravity=gravity_input,
        # The text param reads the instructions checkpoint's output, so it must be an input.
        constraints="results/instructions/{scene}/constraints.json",
    output:
        "results/retrieve/{variant}/{scene}/{instruction}.json",
    params:
        text=instruction_text,
        topk=lambda wc: stage_setting(wc.variant, "retrieve", "topk", 2),
        gravity=lambda wc, input: f"--gravity {input.gravity}" if input.gravity else "",
    log:
        "results/logs/retrieve/{variant}/{scene}/{instruction}.log",
    benchmark:
        "results/benchmarks/retrieve/{variant}/{scene}/{instruction}.tsv"
    shell:
        "capframe retrieve {input.scene} {params.text:q} -o {output} --topk {params.topk} "
        "--cache results/views/{wildcards.scene} {params.gravity} > {log} 2>&1"


rule translate:
    input:
        scene=posed_scene,
        views="results/views/{scene}/label_views.npz",
        gravity=gravity_input,
        retrieval=stage_file("retrieve", "results/retrieve/{key}/{scene}/{instruction}.json"),
    output:
        "results/translate/{variant}/{scene}/{instruction}.json",
    params:
        options=lambda wc: " ".join(
            f"--{flag.replace('_', '-')} {value}" for flag, value in VARIANTS[wc.variant].get("translate", {}).items()
        ),
        gravity=lambda wc, input: f"--gravity {input.gravity}" if input.gravity else "",
    log:
        "results/logs/translate/{variant}/{scene}/{instruction}.log",
    benchmark:
        "results/benchmarks/translate/{variant}/{scene}/{instruction}.tsv"
    shell:
        "capframe translate {input.scene} --retrieval {input.retrieval} -o {output} {params.options} "
        "--cache results/views/{wildcards.scene} {params.gravity} > {log} 2>&1"


rule refine_method:
    input:
        scene=posed_scene,
        labels=stage_file("translate", "results/translate/{key}/{scene}/{instruction}.json"),
        retrieval=stage_file("retrieve", "results/retrieve/{key}/{scene}/{instruction}.json"),
    output:
        directory("results/refine/{variant}/{scene}/{instruction}"),
    params:
        iterations=lambda wc: stage_setting(wc.variant, "refine", "iterations", config["refine"]["iterations"]),
        long_side=lambda wc: stage_setting(wc.variant, "refine", "long_side", config["refine"]["long_side"]),
        weights=lambda wc: (f"--weights {w}" if (w := stage_setting(wc.variant, "refine", "weights", "")) else ""),
    log:
        "results/logs/refine/{variant}/{scene}/{instruction}.log",
    benchmark:
        "results/benchmarks/refine/{variant}/{scene}/{instruction}.tsv"
    shell:
        "capframe refine {input.scene} --labels {input.labels} --init {input.retrieval} -o {output} "
        "--iterations {params.iterations} --long-side {params.long_side} {params.weights} > {log} 2>&1"


rule baseline:
    input:
        scene=posed_scene,
        views="results/views/{scene}/label_views.npz",
        gravity=gravity_input,
        constraints="results/instructions/{scene}/constraints.json",
    output:
        directory("results/baselines/{baseline}/{scene}/{instruction}"),
    params:
        text=instruction_text,
        gravity=lambda wc, input: f"--gravity {input.gravity}" if input.gravity else "",
    log:
        "results/logs/baselines/{baseline}/{scene}/{instruction}.log",
    benchmark:
        "results/benchmarks/baselines/{baseline}/{scene}/{instruction}.tsv"
    shell:
        "capframe baseline {wildcards.baseline} {input.scene} {params.text:q} -o {output} "
        "--cache results/views/{wildcards.scene} {params.gravity} > {log} 2>&1"
