# Stage 7: graded patterns designed to a pressure profile (config profile_designs): the design
# loop with adjoint sensitivities, confirmed from scratch, and the cut pattern (cloth design).
# A design of one body is profile_design; a design of several (every size of a chart at once,
# each warm-started from the one before) is chart_design.


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
    wildcard_constraints:
        design=design_names(chart=False),
    priority: CRITICAL
    conda:
        "../envs/cloth.yaml"
    params:
        case=design_case_json,
        arguments=design_arguments,
        tolerance=lambda wildcards: DESIGNS[wildcards.design].tolerance,
        folder=lambda wildcards: design_file("", wildcards.design),
        cloth_version=CLOTH_VERSION,
    shell:
        "(cloth case write --json {params.case:q} -o {output.start:q} && "
        "cloth design {output.start:q} {params.arguments} "
        "--tolerance {params.tolerance} -o {params.folder:q}) > {log:q} 2>&1"


rule chart_design:
    input:
        material=design_material,
        body=design_body_files,
    output:
        starts=directory(design_file("starts")),
        confirmed=report(
            design_file("design_confirmed.csv"),
            caption="../report/chart_design.rst",
            category="Designs",
        ),
        png=report(
            design_file("design_reductions.png"),
            caption="../report/chart_design.rst",
            category="Designs",
        ),
    log:
        "logs/chart_design/{design}.log",
    wildcard_constraints:
        design=design_names(chart=True),
    priority: CRITICAL
    conda:
        "../envs/cloth.yaml"
    params:
        writes=chart_writes,
        inputs=chart_inputs,
        arguments=design_arguments,
        tolerance=lambda wildcards: DESIGNS[wildcards.design].tolerance,
        folder=lambda wildcards: design_file("", wildcards.design),
        cloth_version=CLOTH_VERSION,
    shell:
        "(mkdir -p {output.starts:q} && {params.writes} && "
        "cloth design {params.inputs} {params.arguments} "
        "--tolerance {params.tolerance} -o {params.folder:q}) > {log:q} 2>&1"
