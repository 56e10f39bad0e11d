# Stage 3: initial.nc -> relaxed.nc (static equilibrium on the body) with solver history.


rule relax:
    input:
        case_file("initial.nc"),
    output:
        case_file("relaxed.nc"),
    log:
        "logs/relax/{case}.log",
    benchmark:
        "benchmarks/results/relax/{case}.tsv"
    priority: CRITICAL
    conda:
        "../envs/cloth.yaml"
    threads: relax_threads
    resources:
        mem_mb=case_resource("relax", "mem_mb"),
        runtime=case_resource("relax", "runtime"),
    params:
        cloth_version=CLOTH_VERSION,
    shell:
        "cloth relax {input:q} -o {output:q} > {log:q} 2>&1"
