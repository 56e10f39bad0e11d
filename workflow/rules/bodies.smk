# Stage: bodies of the sweep -> a mesh per parametric torso (for ParaView/Blender) and a check
# report (watertightness, bounds, girth profile).


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
        "cloth body check {output.mesh:q} > {output.check:q}.tmp && "
        "mv {output.check:q}.tmp {output.check:q}) > {log:q} 2>&1"
