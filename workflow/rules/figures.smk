# Stage 5: result.nc -> figures (stress maps, garment in 3D and on the body, pressure,
# landmarks, convergence; names in cloth.figures.plots.FIGURES), in colour ranges shared by a sweep
# (read once for it by colour_ranges).
from cloth.figures.plots import FIGURES


rule colour_ranges:
    input:
        sweep_results,
    output:
        sweep_file("colour_ranges.json"),
    log:
        "logs/colour_ranges.log",
    conda:
        "../envs/cloth.yaml"
    params:
        cloth_version=CLOTH_VERSION,
    shell:
        "cloth ranges {input:q} -o {output:q} > {log:q} 2>&1"


rule figures:
    input:
        result=case_file("result.nc"),
        ranges=figure_ranges,
    output:
        report(
            [case_file(f"figures/{figure}.png") for figure in FIGURES],
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
        folder=lambda wildcards: case_file("figures", wildcards.case),
        ranges=ranges_option,
        cloth_version=CLOTH_VERSION,
    shell:
        "cloth plot {input.result:q} {params.ranges} -o {params.folder:q} > {log:q} 2>&1"


rule view:
    input:
        case_file("result.nc"),
    output:
        report(
            case_file("garment.html"),
            caption="../report/view.rst",
            category="Cases",
            subcategory="{case}",
        ),
    log:
        "logs/view/{case}.log",
    conda:
        "../envs/cloth.yaml"
    resources:
        mem_mb=case_resource("figures", "mem_mb"),
        runtime=case_resource("figures", "runtime"),
    params:
        cloth_version=CLOTH_VERSION,
    shell:
        "cloth view {input:q} -o {output:q} > {log:q} 2>&1"
