# Stage 7: graded patterns designed to a pressure profile (config profile_designs): the design
# loop with adjoint sensitivities, confirmed from scratch, and the cut pattern (cloth design).


rule profile_design:
    input:
        material=design_material,
        body=design_body_files,
    output:
        start=design_file("start.yaml"),
        confirmed=report(
            design_file("design_confirmed.csv"),
            caption="../report/profile_design.rst",
            category="Designs",
        ),
        png=report(
            design_file("design_profile.png"),
            caption="../report/profile_design.rst",
            category="Designs",
        ),
        pattern=design_file("pattern.csv"),
        svg=design_file("pattern.svg"),
    log:
        "logs/profile_design/{design}.log",
    conda:
        "../envs/cloth.yaml"
    params:
        case=design_case_json,
        targets=design_targets,
        tolerance=lambda wildcards: DESIGNS[wildcards.design][2],
        folder=lambda wildcards: design_file("", wildcards.design),
        cloth_version=CLOTH_VERSION,
    shell:
        "(cloth case write --json {params.case:q} -o {output.start:q} && "
        "cloth design {output.start:q} {params.targets} "
        "--tolerance {params.tolerance} -o {params.folder:q}) > {log:q} 2>&1"
