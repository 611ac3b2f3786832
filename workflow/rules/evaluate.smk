"""Ground-truth checks and tables."""


rule check_oracle:
    input:
        scene="results/scenes/{scene}",
        result="results/refine/oracle/{scene}/{instruction}",
        constraints="results/instructions/{scene}/constraints.json",
    output:
        "results/check/oracle/{scene}/{instruction}.json",
    log:
        "results/logs/check/oracle/{scene}/{instruction}.log",
    benchmark:
        "results/benchmarks/check/oracle/{scene}/{instruction}.tsv"
    shell:
        "capframe check {input.scene} {input.result}/result.json --constraints {input.constraints} "
        "--id {wildcards.instruction} -o {output} > {log} 2>&1"


rule aggregate_oracle:
    input:
        checks=per_instruction("results/check/oracle/{scene}/{instruction}.json"),
        results=per_instruction("results/refine/oracle/{scene}/{instruction}"),
    output:
        "results/tables/refine_oracle.csv",
    log:
        "results/logs/aggregate/refine_oracle.log",
    params:
        results=lambda wc, input: [f"{r}/result.json" for r in input.results],
    shell:
        "capframe aggregate --method refine-oracle --checks {input.checks} --results {params.results} -o {output} > {log} 2>&1"
