# Helpers shared by the rules: config lookups, case expansion and the list of final outputs.
import importlib.util
import json
import shlex

from snakemake.logging import logger

from cloth import __version__ as CLOTH_VERSION
from cloth.config import validate_case
from cloth.errors import InputError
from cloth.resources import stage_resources, surface_resources


wildcard_constraints:
    # body names as the config schema allows them (no dots: {body}.check.txt is not a torso)
    body="[A-Za-z0-9][A-Za-z0-9_-]*",


def material_config(name):
    """The config block of material ``name``."""
    return config["materials"][name]


def material_tables(wildcards):
    """The lab table(s) of a material, as a list of paths."""
    table = material_config(wildcards.material)["table"]
    return [table] if isinstance(table, str) else list(table)


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


def with_surface(body, name):
    """A body block whose smooth surface (a mesh body's default) is the pipeline's file
    results/bodies/{name}.surface.nc, made once by rule body_surface for every case on it.
    """
    if "mesh" not in body or body.get("surface", "smooth") != "smooth":
        return body
    return {"surface_file": f"results/bodies/{name}.surface.nc", **body}


def body_block(name):
    """The body block of a body name: a configured body, or case-{case} for a case's own."""
    if name.startswith("case-") and name[5:] in config.get("cases", {}):
        return config["cases"][name[5:]]["body"]
    return config["bodies"][name]


def resolved_case(name, block=None):
    """Case ``name`` (of the config, or the given block) with its material as the ingested
    file, validated."""
    if block is None:
        block = dict(config.get("cases", {})[name])
        bodies = config.get("bodies", {})
        same = [key for key, body in bodies.items() if body == block["body"]]
        block["body"] = with_surface(block["body"], same[0] if same else f"case-{name}")
    block = dict(block)
    material = block.get("material")
    if material not in config["materials"]:
        raise InputError(
            f"material {material!r} is not defined under materials "
            f"({', '.join(sorted(config['materials']))})",
            "config",
            f"cases.{name}.material",
        )
    block["material"] = f"results/materials/{material}.nc"
    return validate_case(block, f"config: cases.{name}")


def reduction_tag(reduction):
    return f"r{round(1000 * reduction):03d}"


def sweep_cases():
    """Case blocks of the sweep, by readable name, with what the sweep stage needs to know."""
    sweep = config.get("sweep")
    if not sweep:
        return {}, []
    bodies = config.get("bodies", {})
    blocks, index = {}, []
    for key, names, pool in (
        ("sweep.materials", sweep["materials"], config["materials"]),
        ("sweep.bodies", sweep["bodies"], bodies),
    ):
        for name in names:
            if name not in pool:
                raise InputError(
                    f"{name!r} is not defined ({', '.join(sorted(pool)) or 'none defined'})",
                    "config",
                    key,
                )
    for material in sweep["materials"]:
        for body in sweep["bodies"]:
            for reduction in sweep["reductions"]:
                name = f"{material}__{body}__{reduction_tag(reduction)}"
                blocks[name] = {
                    "material": material,
                    "body": with_surface(bodies[body], body),
                    "garment": {**sweep["garment"], "reduction": reduction},
                    "solver": sweep.get("solver", {}),
                }
                index.append(
                    {
                        "case": name,
                        "material": material,
                        "body": body,
                        "reduction": reduction,
                    }
                )
    return blocks, index


TORSO_LANDMARKS = ("hip", "waist", "underbust", "bust")


def check_targets():
    """Targets need one pressure and a girth line the sweep's bodies have (known in advance:
    the torso's four lines; other bodies get 'middle' or girth_min_N / girth_max_N)."""
    sweep = config.get("sweep") or {}
    bodies = [
        config.get("bodies", {}).get(name, {}) for name in sweep.get("bodies", [])
    ]
    for number, target in enumerate(config.get("targets", [])):
        if ("pressure_mmHg" in target) == ("pressure_kPa" in target):
            raise InputError(
                "give exactly one of pressure_mmHg or pressure_kPa",
                "config",
                f"targets.{number}",
            )
        name = target["landmark"]
        torso_only = bool(bodies) and all("torso" in body for body in bodies)
        if torso_only and name not in TORSO_LANDMARKS:
            raise InputError(
                f"unknown landmark {name!r}; the torso has {', '.join(TORSO_LANDMARKS)}",
                "config",
                f"targets.{number}.landmark",
            )
        if not (
            name in TORSO_LANDMARKS or name == "middle" or name.startswith("girth_")
        ):
            raise InputError(
                f"unknown landmark {name!r}; use hip, waist, underbust, bust (torso), middle, "
                "or girth_min_N / girth_max_N (other bodies)",
                "config",
                f"targets.{number}.landmark",
            )


SWEEP_BLOCKS, SWEEP_INDEX = sweep_cases()
check_targets()
for _name in SWEEP_BLOCKS:
    if _name in config.get("cases", {}):
        raise InputError(
            "a case of this name is also in the sweep", "config", f"cases.{_name}"
        )
CASES = {name: resolved_case(name) for name in config.get("cases", {})}
CASES.update({name: resolved_case(name, block) for name, block in SWEEP_BLOCKS.items()})


def case_block(name):
    """A case by name: a configured or sweep case, or the confirmation case of a design
    answer (known once the design checkpoint has run)."""
    if name in CASES:
        return CASES[name]
    from cloth.sweep import confirm_name, read_design

    for row in read_design(checkpoints.design.get().output[0]):
        if row["status"] == "ok" and confirm_name(row) == name:
            sweep = config["sweep"]
            block = {
                "material": row["material"],
                "body": with_surface(config["bodies"][row["body"]], row["body"]),
                "garment": {**sweep["garment"], "reduction": float(row["reduction"])},
                "solver": sweep.get("solver", {}),
            }
            return resolved_case(name, block)
    raise InputError(
        "no such case in the config, the sweep or the design", "config", name
    )


def case_json(wildcards):
    return json.dumps(case_block(wildcards.case), sort_keys=True)


def body_files(wildcards):
    """Files the body of a case reads (mesh or size chart), so edits rerun the case."""
    body = case_block(wildcards.case)["body"]
    if "mesh" in body:
        return [
            body["mesh"],
            *([body["surface_file"]] if "surface_file" in body else []),
        ]
    if "torso" in body:
        return [body["torso"].get("chart", "data/bodies/size_chart.csv")]
    return []


def case_material(wildcards):
    return case_block(wildcards.case)["material"]


def torso_flags(wildcards):
    """`cloth body torso` flags of a torso body block."""
    spec = config["bodies"][wildcards.body]["torso"]
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
    from cloth.sweep import confirm_name, read_design

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
    ``stage`` of the job's case asks a cluster for (cloth/resources.py). A confirmation case
    of the design asks what the largest sweep case asks (its block is read from the design
    checkpoint, which a cluster job of this rule cannot see)."""

    def value(wildcards):
        if wildcards.case in CASES:
            blocks = [CASES[wildcards.case]]
        else:
            blocks = list(SWEEP_BLOCKS.values()) or [case_block(wildcards.case)]
        return max(getattr(stage_resources(stage, block), name) for block in blocks)

    return value


def design_answer(wildcards):
    """The design checkpoint's answer, for a confirmation case whose block is read from it (a
    cluster job needs it as an input to see it); nothing for the other cases."""
    if wildcards.case in CASES:
        return []
    return checkpoints.design.get().output[0]


SURFACE_RESOURCES = surface_resources()
