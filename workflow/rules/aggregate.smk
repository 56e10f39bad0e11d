# Stage 4: relaxed.nc -> result.nc (stresses, pressure, landmarks) + summary.csv.


rule aggregate:
    input:
        "results/cases/{case}/relaxed.nc",
    output:
        nc="results/cases/{case}/result.nc",
        csv=report(
            "results/cases/{case}/summary.csv",
            caption="../report/summary.rst",
            category="Cases",
            subcategory="{case}",
        ),
    log:
        "logs/aggregate/{case}.log",
    conda:
        "../envs/cloth.yaml"
    resources:
        mem_mb=case_resource("aggregate", "mem_mb"),
        runtime=case_resource("aggregate", "runtime"),
    params:
        cloth_version=CLOTH_VERSION,
    shell:
        "cloth aggregate {input:q} -o {output.nc:q} --summary {output.csv:q} "
        "> {log:q} 2>&1"
