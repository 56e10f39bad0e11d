# Stage 4: relaxed.nc -> result.nc (stresses, pressure, landmarks) + summary.csv.


rule aggregate:
    input:
        case_file("relaxed.nc"),
    output:
        nc=case_file("result.nc"),
        csv=report(
            case_file("summary.csv"),
            caption="../report/summary.rst",
            category="Cases",
            subcategory="{case}",
        ),
    log:
        "logs/aggregate/{case}.log",
    priority: CRITICAL
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
