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
    wildcard_constraints:
        entry=wearers_names(robust=False),
    conda:
        "../envs/cloth.yaml"
    params:
        pairs=wearers_pairs,
        folder=lambda wildcards: wearers_file("", wildcards.entry),
        cloth_version=CLOTH_VERSION,
    shell:
        "cloth wearers-report {params.pairs} --index {input.index:q} -o {params.folder:q} "
        "> {log:q} 2>&1"


# a wearers entry with targets: the robust design for every wearer (cloth design --wearers),
# one job (each of its rounds relaxes every wearer); robust.csv says whether every wearer is
# inside every band and, where not, the narrowest band reached (the pipeline does not stop)
rule robust_wearers:
    input:
        material=robust_material,
        index=wearers_index,
    output:
        start=wearers_file("start.yaml"),
        csv=report(
            wearers_file("robust.csv"),
            caption="../report/wearers.rst",
            category="Wearers",
        ),
        table=wearers_file("confirmed/wearers.csv"),
        png=report(
            wearers_file("confirmed/wearers.png"),
            caption="../report/wearers.rst",
            category="Wearers",
        ),
    log:
        "logs/robust_wearers/{entry}.log",
    wildcard_constraints:
        entry=wearers_names(robust=True),
    conda:
        "../envs/cloth.yaml"
    params:
        case=robust_case_json,
        targets=robust_targets,
        wearers=lambda wildcards: WEARERS[wildcards.entry].folder,
        folder=lambda wildcards: wearers_file("", wildcards.entry),
        cloth_version=CLOTH_VERSION,
    shell:
        "(cloth case write --json {params.case:q} -o {output.start:q} && "
        "cloth design {output.start:q} --wearers {params.wearers:q} {params.targets} "
        "--report-unmet -o {params.folder:q}) > {log:q} 2>&1"
