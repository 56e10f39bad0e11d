# Helpers shared by the rules: config lookups and the list of final outputs.
from cloth import __version__ as CLOTH_VERSION


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
    return " ".join(shlex_quote(flag) for flag in flags)


def shlex_quote(text):
    import shlex

    return shlex.quote(text)


def all_outputs():
    """Every final output of the configured pipeline."""
    return expand(
        ["results/materials/{material}.nc", "results/materials/{material}.png"],
        material=sorted(config["materials"]),
    )
