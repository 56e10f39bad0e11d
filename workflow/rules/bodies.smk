# Stage: bodies -> a mesh per parametric torso (for ParaView/Blender), the smooth contact
# surface of every mesh body (fitted once, read by predeform, relax and aggregate), and check
# reports (watertightness, bounds, girth profile, the surface's deviation from the mesh).


rule body_mesh:
    output:
        mesh="results/bodies/{body}.ply",
        check="results/bodies/{body}.txt",
    log:
        "logs/body_mesh/{body}.log",
    conda:
        "../envs/cloth.yaml"
    params:
        flags=torso_flags,
        cloth_version=CLOTH_VERSION,
    shell:
        "(cloth body torso {params.flags} -o {output.mesh:q} && "
        "cloth body check {output.mesh:q} --surface mesh > {output.check:q}.tmp && "
        "mv {output.check:q}.tmp {output.check:q}) > {log:q} 2>&1"


rule body_surface:
    input:
        surface_mesh,
    output:
        "results/bodies/{body}.surface.nc",
    log:
        "logs/body_surface/{body}.log",
    conda:
        "../envs/cloth.yaml"
    resources:
        mem_mb=SURFACE_RESOURCES.mem_mb,
        runtime=SURFACE_RESOURCES.runtime,
    params:
        flags=surface_flags,
        cloth_version=CLOTH_VERSION,
    shell:
        "cloth body fit {input:q} {params.flags} -o {output:q} > {log:q} 2>&1"


rule body_check:
    input:
        mesh=surface_mesh,
        surface="results/bodies/{body}.surface.nc",
    output:
        check="results/bodies/{body}.check.txt",
        curvature=report(
            "results/bodies/{body}.curvature.png",
            caption="../report/curvature.rst",
            category="Bodies",
        ),
    log:
        "logs/body_check/{body}.log",
    conda:
        "../envs/cloth.yaml"
    params:
        flags=surface_flags,
        cloth_version=CLOTH_VERSION,
    shell:
        "(cloth body check {input.mesh:q} {params.flags} --surface-file {input.surface:q} "
        "--curvature {output.curvature:q} "
        "> {output.check:q}.tmp && mv {output.check:q}.tmp {output.check:q}) > {log:q} 2>&1"
