# Stage: bodies -> a mesh per parametric torso (for ParaView/Blender), the smooth contact
# surface of every mesh body (fitted once, read by predeform, relax and aggregate), and check
# reports (watertightness, bounds, girth profile, the surface's deviation from the mesh).


rule body_mesh:
    output:
        mesh=body_file("ply"),
        check=body_file("txt"),
    log:
        "logs/body_mesh/{body}.log",
    conda:
        "../envs/cloth.yaml"
    params:
        block=body_json,
        cloth_version=CLOTH_VERSION,
    shell:
        "(cloth body torso --json {params.block:q} -o {output.mesh:q} && "
        "cloth body check {output.mesh:q} --surface mesh > {output.check:q}.tmp && "
        "mv {output.check:q}.tmp {output.check:q}) > {log:q} 2>&1"


rule body_surface:
    input:
        surface_mesh,
    output:
        body_file("surface.nc"),
    log:
        "logs/body_surface/{body}.log",
    conda:
        "../envs/cloth.yaml"
    resources:
        mem_mb=SURFACE_RESOURCES.mem_mb,
        runtime=SURFACE_RESOURCES.runtime,
    params:
        block=body_json,
        cloth_version=CLOTH_VERSION,
    shell:
        "cloth body fit --json {params.block:q} -o {output:q} > {log:q} 2>&1"


rule body_check:
    input:
        mesh=surface_mesh,
        surface=body_file("surface.nc"),
    output:
        check=body_file("check.txt"),
        curvature=report(
            body_file("curvature.png"),
            caption="../report/curvature.rst",
            category="Bodies",
        ),
    log:
        "logs/body_check/{body}.log",
    conda:
        "../envs/cloth.yaml"
    params:
        block=body_json,
        cloth_version=CLOTH_VERSION,
    shell:
        "(cloth body check --json {params.block:q} --curvature {output.curvature:q} "
        "> {output.check:q}.tmp && mv {output.check:q}.tmp {output.check:q}) > {log:q} 2>&1"
