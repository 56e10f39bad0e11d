# Stage 6: the sweep's results -> sweep.nc, sweep.csv and the design plot; the design answer
# (reduction per target) as a checkpoint, then confirmed by an extra relaxed case each.


rule sweep:
    input:
        sweep_results,
    output:
        nc=sweep_file("sweep.nc"),
        csv=report(
            sweep_file("sweep.csv"), caption="../report/sweep.rst", category="Sweep"
        ),
        png=report(
            sweep_file("design.png"), caption="../report/design.rst", category="Sweep"
        ),
        body=report(
            sweep_file("sweep_on_body.png"),
            caption="../report/sweep_on_body.rst",
            category="Sweep",
        ),
    log:
        "logs/sweep.log",
    priority: CRITICAL
    conda:
        "../envs/cloth.yaml"
    params:
        index=json.dumps(SWEEP_INDEX),
        targets=json.dumps(config.get("targets", [])),
        cloth_version=CLOTH_VERSION,
    shell:
        "cloth sweep {input:q} --index {params.index:q} --targets {params.targets:q} "
        "-o {output.nc:q} "
        "--csv {output.csv:q} --plot {output.png:q} --body-plot {output.body:q} > {log:q} 2>&1"


checkpoint design:
    input:
        sweep_file("sweep.nc"),
    output:
        sweep_file("design.csv"),
    log:
        "logs/design.log",
    priority: CRITICAL
    conda:
        "../envs/cloth.yaml"
    params:
        targets=json.dumps(config.get("targets", [])),
        cloth_version=CLOTH_VERSION,
    shell:
        "cloth design {input:q} --targets {params.targets:q} -o {output:q} > {log:q} 2>&1"


rule confirm:
    input:
        design=sweep_file("design.csv"),
        results=confirmation_results,
    output:
        csv=report(
            sweep_file("design_confirmed.csv"),
            caption="../report/design_confirmed.rst",
            category="Sweep",
        ),
        secant=directory(sweep_file("design_secant")),
    log:
        "logs/confirm.log",
    priority: CRITICAL
    conda:
        "../envs/cloth.yaml"
    params:
        cloth_version=CLOTH_VERSION,
    shell:
        "cloth confirm {input.design:q} {input.results:q} -o {output.csv:q} "
        "--iterate {output.secant:q} > {log:q} 2>&1"
