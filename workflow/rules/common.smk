# Helpers shared by the rules: config lookups, case expansion and the list of final outputs.
import json
import shlex

from cloth import __version__ as CLOTH_VERSION
from cloth.config import validate_case
from cloth.errors import InputError


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


def resolved_case(name):
    """Case ``name`` of the config with its material as the ingested file, validated."""
    block = dict(config.get("cases", {})[name])
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


CASES = {name: resolved_case(name) for name in config.get("cases", {})}


def case_json(wildcards):
    return json.dumps(CASES[wildcards.case], sort_keys=True)


def body_files(wildcards):
    """Files the body of a case reads (mesh or size chart), so edits rerun the case."""
    body = CASES[wildcards.case]["body"]
    if "mesh" in body:
        return [body["mesh"]]
    if "torso" in body:
        return [body["torso"].get("chart", "data/bodies/size_chart.csv")]
    return []


def case_material(wildcards):
    return CASES[wildcards.case]["material"]


def all_outputs():
    """Every final output of the configured pipeline."""
    return expand(
        ["results/materials/{material}.nc", "results/materials/{material}.png"],
        material=sorted(config["materials"]),
    ) + expand(
        [
            "results/cases/{case}/initial.nc",
            "results/cases/{case}/initial.png",
            "results/cases/{case}/relaxed.nc",
            "results/cases/{case}/result.nc",
            "results/cases/{case}/summary.csv",
            "results/cases/{case}/figures/stress_weft.png",
        ],
        case=sorted(CASES),
    )
