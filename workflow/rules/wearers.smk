# Stage 8: one garment on every wearer of a size (config wearers): each wearer's case runs
# through the rules above as its own job (write_case, predeform, relax, aggregate), so that a
# cluster runs them side by side; this rule gathers their results (cloth wearers-report).


rule wearers:
    input:
        results=wearers_results,
        index=wearers_index,
    output:
        csv=report(
            wearers_file("wearers.csv"),
            caption="../report/wearers.rst",
            category="Wearers",
        ),
        nc=wearers_file("wearers.nc"),
        png=report(
            wearers_file("wearers.png"),
            caption="../report/wearers.rst",
            category="Wearers",
        ),
    log:
        "logs/wearers/{entry}.log",
    conda:
        "../envs/cloth.yaml"
    params:
        pairs=wearers_pairs,
        folder=lambda wildcards: wearers_file("", wildcards.entry),
        cloth_version=CLOTH_VERSION,
    shell:
        "cloth wearers-report {params.pairs} --index {input.index:q} -o {params.folder:q} "
        "> {log:q} 2>&1"
