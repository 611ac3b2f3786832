"""The method per instruction, one rule per stage (Retrieve: coarse, qe; Translate: segment,
associate, orient, translate; Refine), its variants, and the per-scene stages it reads.

Stages a scene or an instruction does not need are left out of its DAG (DESIGN §7): COLMAP only
for a scene without poses, gravity only for a scene that is not aligned (posed_scene(),
gravity_input()); segmentation only for an associator or an orientation estimator that reads
masks (masks_input()); orientation only for an instruction whose parse asks for a front
(fronts_input(), read from the parse checkpoint).
"""


rule colmap:
    input:
        "results/scenes/{scene}",
    output:
        directory("results/sfm/{scene}"),
    log:
        "results/logs/colmap/{scene}.log",
    benchmark:
        "results/benchmarks/colmap/{scene}.tsv"
    shell:
        "capframe colmap {input:q} -o {output:q} > {log:q} 2>&1"


# Evaluation of synthetic scenes: the recovered cameras are mapped into the generator's world,
# where the Gaussians live (a real 3DGS would be trained on the COLMAP poses instead).
rule align_truth:
    input:
        recovered="results/sfm/{scene}",
        truth="results/scenes/{scene}",
    output:
        directory("results/colmap/{scene}"),
    log:
        "results/logs/align_truth/{scene}.log",
    benchmark:
        "results/benchmarks/align_truth/{scene}.tsv"
    shell:
        "capframe align-truth {input.recovered:q} --truth {input.truth:q} -o {output:q} > {log:q} 2>&1"


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
        "capframe gravity {input:q} -o {output:q} > {log:q} 2>&1"


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
        "capframe views {input:q} -o {output:q} > {log:q} 2>&1"


rule occupancy:
    input:
        scene=posed_scene,
        gravity=gravity_input,
    output:
        "results/views/{scene}/occupancy.npz",
    log:
        "results/logs/occupancy/{scene}.log",
    benchmark:
        "results/benchmarks/occupancy/{scene}.tsv"
    params:
        gravity=gravity_option,
    shell:
        "capframe occupancy {input.scene:q} -o {output:q} {params.gravity:q} > {log:q} 2>&1"


wildcard_constraints:
    variant="|".join(map(re.escape, VARIANTS)),  # names may hold a "."
    baseline="|".join(BASELINES),


checkpoint parse:
    # A checkpoint: the parsed instruction decides which Translate stages run (fronts_input).
    input:
        scene=posed_scene,
        gravity=gravity_input,
        # The text param reads the instructions checkpoint's output, so it must be an input.
        constraints="results/instructions/{scene}/constraints.json",
    output:
        "results/parse/{variant}/{scene}/{instruction}.json",
    log:
        "results/logs/parse/{variant}/{scene}/{instruction}.log",
    benchmark:
        "results/benchmarks/parse/{variant}/{scene}/{instruction}.tsv"
    priority: METHOD_PRIORITY
    params:
        text=instruction_text,
        gravity=gravity_option,
        backends=lambda wc: backend_options(wc.variant, STAGE_ROLES["parse"]),
    shell:
        "capframe parse {input.scene:q} {params.text:q} -o {output:q} --cache results/views/{wildcards.scene:q} "
        "{params.backends:q} {params.gravity:q} > {log:q} 2>&1"


rule coarse:
    input:
        scene=posed_scene,
        views="results/views/{scene}/label_views.npz",
        gravity=gravity_input,
        parsed=stage_file("parse", "results/parse/{key}/{scene}/{instruction}.json"),
    output:
        "results/coarse/{variant}/{scene}/{instruction}.json",
    log:
        "results/logs/coarse/{variant}/{scene}/{instruction}.log",
    benchmark:
        "results/benchmarks/coarse/{variant}/{scene}/{instruction}.tsv"
    priority: METHOD_PRIORITY
    params:
        gravity=gravity_option,
        backends=lambda wc: backend_options(wc.variant, STAGE_ROLES["coarse"]),
    shell:
        "capframe coarse {input.scene:q} --parsed {input.parsed:q} -o {output:q} --cache results/views/{wildcards.scene:q} "
        "{params.backends:q} {params.gravity:q} > {log:q} 2>&1"


rule qe:
    input:
        scene=posed_scene,
        views="results/views/{scene}/label_views.npz",
        gravity=gravity_input,
        coarse=stage_file("coarse", "results/coarse/{key}/{scene}/{instruction}.json"),
    output:
        "results/retrieve/{variant}/{scene}/{instruction}.json",
    log:
        "results/logs/qe/{variant}/{scene}/{instruction}.log",
    benchmark:
        "results/benchmarks/qe/{variant}/{scene}/{instruction}.tsv"
    priority: METHOD_PRIORITY
    params:
        gravity=gravity_option,
        topk=lambda wc: stage_setting(wc.variant, "retrieve", "topk", 2),
        backends=lambda wc: backend_options(wc.variant, STAGE_ROLES["qe"]),
    shell:
        "capframe qe {input.scene:q} --coarse {input.coarse:q} -o {output:q} --topk {params.topk:q} "
        "--cache results/views/{wildcards.scene:q} {params.backends:q} {params.gravity:q} > {log:q} 2>&1"


rule retrieved_view:
    input:
        scene=posed_scene,
        retrieval="results/retrieve/capframe/{scene}/{instruction}.json",
    output:
        directory("results/retrieved/{scene}/{instruction}"),
    log:
        "results/logs/retrieved/{scene}/{instruction}.log",
    benchmark:
        "results/benchmarks/retrieved/retrieve/{scene}/{instruction}.tsv"
    # Retrieve's answer unrefined, checked as method "retrieve" (Retrieve-vs-Refine per group).
    priority: METHOD_PRIORITY
    shell:
        "capframe retrieved-view {input.scene:q} --retrieval {input.retrieval:q} -o {output:q} > {log:q} 2>&1"


rule segment:
    input:
        scene=posed_scene,
        views="results/views/{scene}/label_views.npz",
        gravity=gravity_input,
        retrieval=stage_file("qe", "results/retrieve/{key}/{scene}/{instruction}.json"),
    output:
        "results/segment/{variant}/{scene}/{instruction}.npz",
    log:
        "results/logs/segment/{variant}/{scene}/{instruction}.log",
    benchmark:
        "results/benchmarks/segment/{variant}/{scene}/{instruction}.tsv"
    priority: METHOD_PRIORITY
    params:
        gravity=gravity_option,
        backends=lambda wc: backend_options(wc.variant, STAGE_ROLES["segment"]),
    shell:
        "capframe segment {input.scene:q} --retrieval {input.retrieval:q} -o {output:q} {params.backends:q} "
        "--cache results/views/{wildcards.scene:q} {params.gravity:q} > {log:q} 2>&1"


rule associate:
    input:
        scene=posed_scene,
        views="results/views/{scene}/label_views.npz",
        gravity=gravity_input,
        retrieval=stage_file("qe", "results/retrieve/{key}/{scene}/{instruction}.json"),
        masks=masks_input("associator"),
    output:
        "results/associate/{variant}/{scene}/{instruction}.json",
    log:
        "results/logs/associate/{variant}/{scene}/{instruction}.log",
    benchmark:
        "results/benchmarks/associate/{variant}/{scene}/{instruction}.tsv"
    priority: METHOD_PRIORITY
    params:
        gravity=gravity_option,
        backends=lambda wc: backend_options(wc.variant, STAGE_ROLES["associate"]),
        masks=lambda wc, input: ["--masks", input.masks] if input.masks else [],
    shell:
        "capframe associate {input.scene:q} --retrieval {input.retrieval:q} {params.masks:q} -o {output:q} "
        "{params.backends:q} --cache results/views/{wildcards.scene:q} {params.gravity:q} > {log:q} 2>&1"


rule orient:
    input:
        scene=posed_scene,
        views="results/views/{scene}/label_views.npz",
        gravity=gravity_input,
        retrieval=stage_file("qe", "results/retrieve/{key}/{scene}/{instruction}.json"),
        masks=masks_input("orient"),
    output:
        "results/orient/{variant}/{scene}/{instruction}.json",
    log:
        "results/logs/orient/{variant}/{scene}/{instruction}.log",
    benchmark:
        "results/benchmarks/orient/{variant}/{scene}/{instruction}.tsv"
    priority: METHOD_PRIORITY
    params:
        gravity=gravity_option,
        backends=lambda wc: backend_options(wc.variant, STAGE_ROLES["orient"]),
        masks=lambda wc, input: ["--masks", input.masks] if input.masks else [],
    shell:
        "capframe orient {input.scene:q} --retrieval {input.retrieval:q} {params.masks:q} -o {output:q} {params.backends:q} "
        "--cache results/views/{wildcards.scene:q} {params.gravity:q} > {log:q} 2>&1"


rule translate:
    input:
        scene=posed_scene,
        retrieval=stage_file("qe", "results/retrieve/{key}/{scene}/{instruction}.json"),
        subjects=stage_file("associate", "results/associate/{key}/{scene}/{instruction}.json"),
        fronts=fronts_input,
    output:
        "results/translate/{variant}/{scene}/{instruction}.json",
    log:
        "results/logs/translate/{variant}/{scene}/{instruction}.log",
    benchmark:
        "results/benchmarks/translate/{variant}/{scene}/{instruction}.tsv"
    priority: METHOD_PRIORITY
    params:
        options=lambda wc: [
            arg
            for flag, value in VARIANTS[wc.variant].get("translate", {}).items()
            for arg in (f"--{flag.replace('_', '-')}", str(value))
        ],
        fronts=lambda wc, input: ["--fronts", input.fronts] if input.fronts else [],
    shell:
        "capframe translate {input.scene:q} --retrieval {input.retrieval:q} --subjects {input.subjects:q} {params.fronts:q} "
        "-o {output:q} {params.options:q} > {log:q} 2>&1"


rule refine_method:
    input:
        scene=posed_scene,
        labels=stage_file("translate", "results/translate/{key}/{scene}/{instruction}.json"),
        retrieval=stage_file("qe", "results/retrieve/{key}/{scene}/{instruction}.json"),
        occupancy="results/views/{scene}/occupancy.npz",
    output:
        directory("results/refine/{variant}/{scene}/{instruction}"),
    log:
        "results/logs/refine/{variant}/{scene}/{instruction}.log",
    benchmark:
        "results/benchmarks/refine/{variant}/{scene}/{instruction}.tsv"
    priority: METHOD_PRIORITY
    params:
        iterations=lambda wc: stage_setting(wc.variant, "refine", "iterations", config["refine"]["iterations"]),
        long_side=lambda wc: stage_setting(wc.variant, "refine", "long_side", config["refine"]["long_side"]),
        weights=lambda wc: (["--weights", w] if (w := stage_setting(wc.variant, "refine", "weights", "")) else []),
    shell:
        "capframe refine {input.scene:q} --labels {input.labels:q} --init {input.retrieval:q} -o {output:q} "
        "--occupancy {input.occupancy:q} --iterations {params.iterations:q} --long-side {params.long_side:q} "
        "{params.weights:q} > {log:q} 2>&1"


rule baseline:
    input:
        scene=posed_scene,
        views="results/views/{scene}/label_views.npz",
        gravity=gravity_input,
        constraints="results/instructions/{scene}/constraints.json",
    output:
        directory("results/baselines/{baseline}/{scene}/{instruction}"),
    log:
        "results/logs/baselines/{baseline}/{scene}/{instruction}.log",
    benchmark:
        "results/benchmarks/baselines/{baseline}/{scene}/{instruction}.tsv"
    params:
        text=instruction_text,
        gravity=gravity_option,
        backends=lambda wc: backend_options("capframe", BASELINE_ROLES),
        # ChatCam-style: Refine's step budget and resolution.
        budget=lambda wc: (
            ["--iterations", config["refine"]["iterations"], "--long-side", config["refine"]["long_side"]]
            if wc.baseline == "chatcam"
            else []
        ),
    shell:
        "capframe baseline {wildcards.baseline:q} {input.scene:q} {params.text:q} -o {output:q} "
        "--cache results/views/{wildcards.scene:q} {params.backends:q} {params.budget:q} {params.gravity:q} > {log:q} 2>&1"
