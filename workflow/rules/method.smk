"""The method per instruction (Retrieve -> Translate -> Refine) and the per-scene stages it reads.

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


rule ground:
    input:
        scene=posed_scene,
        views="results/views/{scene}/label_views.npz",
        gravity=gravity_input,
    output:
        directory("results/ground/{scene}/{instruction}"),
    params:
        text=instruction_text,
        gravity=lambda wc, input: f"--gravity {input.gravity}" if input.gravity else "",
        iterations=config["refine"]["iterations"],
        long_side=config["refine"]["long_side"],
    log:
        "results/logs/ground/{scene}/{instruction}.log",
    benchmark:
        "results/benchmarks/ground/{scene}/{instruction}.tsv"
    shell:
        "capframe ground {input.scene} {params.text:q} -o {output} --cache results/views/{wildcards.scene} {params.gravity} "
        "--iterations {params.iterations} --long-side {params.long_side} > {log} 2>&1"
