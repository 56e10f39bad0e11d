# Stage 5: result.nc -> figures (stress maps, garment in 3D, pressure, landmarks, convergence).

FIGURES = [
    "stress_weft",
    "stress_warp",
    "pressure",
    "garment_stress",
    "garment_stress_initial",
    "landmarks",
    "convergence",
    "material",
]


rule figures:
    input:
        "results/cases/{case}/result.nc",
    output:
        report(
            expand("results/cases/{{case}}/figures/{figure}.png", figure=FIGURES),
            caption="../report/figures.rst",
            category="Cases",
            subcategory="{case}",
        ),
    log:
        "logs/figures/{case}.log",
    conda:
        "../envs/cloth.yaml"
    resources:
        mem_mb=case_resource("figures", "mem_mb"),
        runtime=case_resource("figures", "runtime"),
    params:
        folder=lambda wildcards: f"results/cases/{wildcards.case}/figures",
        cloth_version=CLOTH_VERSION,
    shell:
        "cloth plot {input:q} -o {params.folder:q} > {log:q} 2>&1"
