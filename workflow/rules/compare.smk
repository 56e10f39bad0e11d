# Stage 10: a case against measured readings (config comparisons): cloth compare of its
# result.nc and its measurements file, the model's probe at each reading and the agreement.


rule compare:
    input:
        result=case_file("result.nc"),
        measured=comparison_file,
    output:
        csv=case_file("compare/compare.csv"),
        agreement=report(
            case_file("compare/agreement.csv"),
            caption="../report/compare.rst",
            category="Comparisons",
        ),
        nc=case_file("compare/compare.nc"),
        png=report(
            case_file("compare/compare.png"),
            caption="../report/compare.rst",
            category="Comparisons",
        ),
    log:
        "logs/compare/{case}.log",
    conda:
        "../envs/cloth.yaml"
    params:
        folder=lambda wildcards: case_file("compare", wildcards.case),
        cloth_version=CLOTH_VERSION,
    shell:
        "cloth compare {input.result:q} {input.measured:q} -o {params.folder:q} > {log:q} 2>&1"
