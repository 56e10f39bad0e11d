# Helpers shared by the rules: config lookups, case expansion and the list of final outputs.
import importlib.util
import json
import shlex

from snakemake.logging import logger

from cloth import __version__ as CLOTH_VERSION
from cloth.errors import InputError
from cloth.pipeline.plan import body_files as plan_body_files
from cloth.pipeline.plan import local_body, make_plan
from cloth.pipeline.resources import stage_resources, surface_resources


wildcard_constraints:
    # body names as the config schema allows them (no dots: {body}.check.txt is not a torso)
    body="[A-Za-z0-9][A-Za-z0-9_-]*",


def material_config(name):
    """The config block of material ``name``."""
    return config["materials"][name]


def material_tables(wildcards):
    """The lab table(s) of a material, as a list of paths."""
    return PLAN.material_tables(wildcards.material)


INGEST_FLAGS = {
    "knots": "--knots",
    "branch": "--branch",
    "cycle": "--cycle",
    "thickness_mm": "--thickness-mm",
    "specimen_width_mm": "--specimen-width-mm",
    "gauge_length_mm": "--gauge-length-mm",
    "compression_ratio": "--compression-ratio",
    "name": "--name",
}


def ingest_flags(wildcards):
    """CLI flags of `cloth material ingest` from a material's config block."""
    block = material_config(wildcards.material)
    flags = []
    for key, flag in INGEST_FLAGS.items():
        if key in block:
            flags += [flag, str(block[key])]
    for direction in block.get("directions", []):
        flags += ["--direction", direction]
    return " ".join(shlex.quote(flag) for flag in flags)


def body_block(name):
    """The body block of a body name (a configured body, or case-{case} for a case's own),
    its files found."""
    if name.startswith("case-") and name[5:] in config.get("cases", {}):
        return local_body(config["cases"][name[5:]]["body"], name, workflow.basedir)
    return local_body(config["bodies"][name], name, workflow.basedir)


PLAN = make_plan(config, workflow.basedir)
SWEEP_BLOCKS, SWEEP_INDEX, CASES = PLAN.sweep, PLAN.index, PLAN.cases


def case_block(name):
    """A case by name: a configured or sweep case, or the confirmation case of a design
    answer (known once the design checkpoint has run)."""
    if name in CASES:
        return CASES[name]
    from cloth.pipeline.sweep import confirm_name, read_design

    for row in read_design(checkpoints.design.get().output[0]):
        if row["status"] == "ok" and confirm_name(row) == name:
            return PLAN.case(name, PLAN.design_case(row))
    raise InputError(
        "no such case in the config, the sweep or the design", "config", name
    )


def case_json(wildcards):
    return json.dumps(case_block(wildcards.case).to_dict(), sort_keys=True)


def body_files(wildcards):
    """Files the body of a case reads (mesh or size chart), so edits rerun the case."""
    return plan_body_files(case_block(wildcards.case))


def case_material(wildcards):
    return case_block(wildcards.case).material


def torso_flags(wildcards):
    """`cloth body torso` flags of a torso body block."""
    spec = body_block(wildcards.body)["torso"]
    flags = ["--size", spec["size"]]
    for key in ("chart", "around", "rings"):
        if key in spec:
            flags += [f"--{key}", str(spec[key])]
    return " ".join(shlex.quote(flag) for flag in flags)


def surface_flags(wildcards):
    """`cloth body fit` flags of a mesh body block."""
    block = body_block(wildcards.body)
    flags = []
    for key in ("units", "up", "smoothing", "spacing"):
        if key in block:
            flags += [f"--{key}", str(block[key])]
    if block.get("repair"):
        flags.append("--repair")
    return " ".join(shlex.quote(flag) for flag in flags)


def surface_mesh(wildcards):
    return body_block(wildcards.body)["mesh"]


def sweep_results(wildcards):
    return [f"results/cases/{entry['case']}/result.nc" for entry in SWEEP_INDEX]


def figure_peers(wildcards):
    """The results whose values set a case's figure colour ranges: its sweep's (all of them,
    so that the sweep's figures compare), or none for a case outside the sweep."""
    if wildcards.case not in SWEEP_BLOCKS:
        return []
    return [f"results/cases/{case}/result.nc" for case in sorted(SWEEP_BLOCKS)]


def confirmation_results(wildcards):
    from cloth.pipeline.sweep import confirm_name, read_design

    rows = read_design(checkpoints.design.get().output[0])
    return [
        f"results/cases/{confirm_name(r)}/result.nc"
        for r in rows
        if r["status"] == "ok"
    ]


#: The interactive view per case needs plotly (the extra ``view``); without it the pipeline
#: leaves garment.html out and says so once.
VIEW = importlib.util.find_spec("plotly") is not None
if not VIEW:
    logger.warning(
        "cloth: plotly is not installed, so no garment.html views are written; "
        "pip install 'cloth[view]' to have them"
    )


def all_outputs():
    """Every final output of the configured pipeline."""
    torsos = [n for n, b in config.get("bodies", {}).items() if "torso" in b]
    sweep = expand("results/bodies/{body}.ply", body=torsos)
    sweep += expand(
        "results/bodies/{body}.check.txt",
        body=[n for n, b in config.get("bodies", {}).items() if "mesh" in b],
    )
    if SWEEP_INDEX:
        sweep += ["results/sweep.nc", "results/sweep.csv", "results/design.png"]
        sweep.append("results/sweep_on_body.png")
        if config.get("targets"):
            sweep.append("results/design_confirmed.csv")
    return (
        sweep
        + expand(
            ["results/materials/{material}.nc", "results/materials/{material}.png"],
            material=sorted(config["materials"]),
        )
        + expand(
            [
                "results/cases/{case}/initial.nc",
                "results/cases/{case}/initial.png",
                "results/cases/{case}/relaxed.nc",
                "results/cases/{case}/result.nc",
                "results/cases/{case}/summary.csv",
                "results/cases/{case}/figures/stress_weft.png",
                *(["results/cases/{case}/garment.html"] if VIEW else []),
            ],
            case=sorted(CASES),
        )
    )


def case_resource(stage, name):
    """A rule's ``resources:`` entry: ``name`` (mem_mb, MB, or runtime, minutes) that
    ``stage`` of the job's case asks a cluster for (cloth/pipeline/resources.py). A confirmation case
    of the design asks what the largest sweep case asks (its block is read from the design
    checkpoint, which a cluster job of this rule cannot see)."""

    def value(wildcards):
        if wildcards.case in CASES:
            cases = [CASES[wildcards.case]]
        else:
            cases = [CASES[n] for n in SWEEP_BLOCKS] or [case_block(wildcards.case)]
        return max(getattr(stage_resources(stage, case), name) for case in cases)

    return value


def design_answer(wildcards):
    """The design checkpoint's answer, for a confirmation case whose block is read from it (a
    cluster job needs it as an input to see it); nothing for the other cases."""
    if wildcards.case in CASES:
        return []
    return checkpoints.design.get().output[0]


SURFACE_RESOURCES = surface_resources()
