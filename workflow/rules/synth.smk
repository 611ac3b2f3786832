"""Synthetic scenes and their instructions."""


rule synth_scene:
    output:
        directory("results/scenes/{scene}"),
    log:
        "results/logs/synth/{scene}.log",
    benchmark:
        "results/benchmarks/synth/{scene}.tsv"
    threads: 1  # renders on one thread (bit-identical images on any machine): two scenes generate at once
    params:
        args=synth_args,
    shell:
        "capframe synth {output:q} {params.args:q} > {log:q} 2>&1"


checkpoint instructions:
    input:
        "results/scenes/{scene}",
    output:
        constraints="results/instructions/{scene}/constraints.json",
        sheet="results/instructions/{scene}/instructions.tsv",
    log:
        "results/logs/instructions/{scene}.log",
    benchmark:
        "results/benchmarks/instructions/{scene}.tsv"
    params:
        number=lambda wc: SCENES[wc.scene].instructions,
        seed=lambda wc: SCENES[wc.scene].seed,
    shell:
        "capframe instructions {input:q} -o results/instructions/{wildcards.scene:q} "
        "--count {params.number:q} --seed {params.seed:q} > {log:q} 2>&1"
