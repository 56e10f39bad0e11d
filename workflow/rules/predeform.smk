# Stage 2: case -> initial.nc (the pattern cut and wrapped around the body); the figures rule
# draws it (garment_stress_initial.png), so predeform draws nothing (issue 54: 2-3 s a case).


rule write_case:
    input:
        design_answer,
    output:
        case_file("case.yaml"),
    log:
        "logs/write_case/{case}.log",
    priority: CRITICAL
    conda:
        "../envs/cloth.yaml"
    params:
        case=case_json,
        cloth_version=CLOTH_VERSION,
    shell:
        "cloth case write --json {params.case:q} -o {output:q} > {log:q} 2>&1"


rule predeform:
    input:
        case=case_file("case.yaml"),
        material=case_material,
        body=body_files,
    output:
        nc=case_file("initial.nc"),
    log:
        "logs/predeform/{case}.log",
    benchmark:
        "benchmarks/results/predeform/{case}.tsv"
    priority: CRITICAL
    conda:
        "../envs/cloth.yaml"
    resources:
        mem_mb=case_resource("predeform", "mem_mb"),
        runtime=case_resource("predeform", "runtime"),
    params:
        cloth_version=CLOTH_VERSION,
    shell:
        "cloth predeform {input.case:q} -o {output.nc:q} > {log:q} 2>&1"
