# Stage 1: lab tables -> material.nc (piecewise-linear curves, data, fit error) + a figure.


rule ingest_material:
    input:
        tables=material_tables,
    output:
        nc="results/materials/{material}.nc",
        png=report(
            "results/materials/{material}.png",
            caption="../report/material.rst",
            category="Materials",
        ),
    log:
        "logs/ingest_material/{material}.log",
    conda:
        "../envs/cloth.yaml"
    params:
        flags=ingest_flags,
        cloth_version=CLOTH_VERSION,
    shell:
        "cloth material ingest {input.tables:q} -o {output.nc:q} --plot {output.png:q} "
        "{params.flags} > {log:q} 2>&1"
