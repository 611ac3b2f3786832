"""Refine from oracle pseudo labels (ground truth): the optimiser alone, until Retrieve and
Translate provide the method's own labels."""


rule oracle_labels:
    input:
        scene="results/scenes/{scene}",
        constraints="results/instructions/{scene}/constraints.json",
    output:
        labels="results/oracle/{scene}/{instruction}/labels.json",
        init="results/oracle/{scene}/{instruction}/init.json",
    log:
        "results/logs/oracle/{scene}/{instruction}.log",
    benchmark:
        "results/benchmarks/labels/oracle/{scene}/{instruction}.tsv"
    shell:
        "capframe oracle {input.scene:q} --constraints {input.constraints:q} --id {wildcards.instruction:q} "
        "-o results/oracle/{wildcards.scene:q}/{wildcards.instruction:q} > {log:q} 2>&1"


rule refine_oracle:
    input:
        scene="results/scenes/{scene}",
        labels="results/oracle/{scene}/{instruction}/labels.json",
        init="results/oracle/{scene}/{instruction}/init.json",
        occupancy="results/views/{scene}/occupancy.npz",
    output:
        directory("results/refine/oracle/{scene}/{instruction}"),
    log:
        "results/logs/refine/oracle/{scene}/{instruction}.log",
    benchmark:
        "results/benchmarks/refine/oracle/{scene}/{instruction}.tsv"
    params:
        iterations=config["refine"]["iterations"],
        long_side=config["refine"]["long_side"],
    shell:
        "capframe refine {input.scene:q} --labels {input.labels:q} --init {input.init:q} -o {output:q} "
        "--occupancy {input.occupancy:q} --iterations {params.iterations:q} --long-side {params.long_side:q} > {log:q} 2>&1"
