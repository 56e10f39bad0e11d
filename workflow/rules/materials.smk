# Stage 1: lab tables -> material.nc (piecewise-linear curves, data, fit error) + a figure.


rule ingest_material:
    input:
        tables=material_tables,
    output:
        nc=material_file("nc"),
        png=report(
            material_file("png"),
            caption="../report/material.rst",
            category="Materials",
        ),
    log:
        "logs/ingest_material/{material}.log",
    conda:
        "../envs/cloth.yaml"
    params:
        block=material_json,
        cloth_version=CLOTH_VERSION,
    shell:
        "cloth material ingest --json {params.block:q} -o {output.nc:q} "
        "--plot {output.png:q} > {log:q} 2>&1"
