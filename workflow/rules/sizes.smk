# Stage 9: a size chart designed for a measured population (config size_charts): one job per
# entry (cloth sizes), which calibrates its fast model on full equilibria, searches the chart
# and confirms every size on its extreme wearers from scratch.


rule size_chart:
    input:
        size_chart_inputs,
    output:
        start=size_chart_file("start.yaml"),
        csv=report(
            size_chart_file("sizes.csv"),
            caption="../report/sizes.rst",
            category="Size charts",
        ),
        chart=size_chart_file("chart.csv"),
        need=size_chart_file("fabric_requirement.csv"),
        png=report(
            size_chart_file("sizes.png"),
            caption="../report/sizes.rst",
            category="Size charts",
        ),
    log:
        "logs/size_chart/{entry}.log",
    conda:
        "../envs/cloth.yaml"
    params:
        case=size_chart_case_json,
        arguments=lambda wildcards: SIZE_CHARTS[wildcards.entry].arguments,
        folder=lambda wildcards: size_chart_file("", wildcards.entry),
        cloth_version=CLOTH_VERSION,
    shell:
        "(cloth case write --json {params.case:q} -o {output.start:q} && "
        "cloth sizes {output.start:q} {params.arguments} --report-unmet "
        "-o {params.folder:q}) > {log:q} 2>&1"
