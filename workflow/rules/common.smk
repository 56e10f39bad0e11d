# Helpers shared by the rules: the plan's cases and blocks as the rules take them (JSON), and the
# list of final outputs. Where each file goes is the plan's layout (cloth/pipeline/layout.py:
# material_file, body_file, case_file, sweep_file, design_file), under the config's own results
# folder.
import importlib.util
import json
import os
import shlex

from snakemake.logging import logger

from cloth import __version__ as CLOTH_VERSION
from cloth.errors import InputError
from cloth.pipeline.plan import body_files as plan_body_files
from cloth.pipeline.plan import make_plan
from cloth.pipeline.resources import stage_resources, surface_resources


wildcard_constraints:
    # body names as the config schema allows them (no dots: {body}.check.txt is not a torso)
    body="[A-Za-z0-9][A-Za-z0-9_-]*",


def material_tables(wildcards):
    """The lab table(s) of a material, as a list of paths."""
    return PLAN.material_tables(wildcards.material)


def material_json(wildcards):
    """A material's config block, its tables found, for `cloth material ingest --json`."""
    return json.dumps(PLAN.material_block(wildcards.material), sort_keys=True)


def body_json(wildcards):
    """A body's block, its files found, for `cloth body torso/fit/check --json`."""
    return json.dumps(PLAN.body_block(wildcards.body), sort_keys=True)


PLAN = make_plan(config, workflow.basedir, CONFIG_FILE)
RESULTS = PLAN.layout.root
material_file = PLAN.layout.material_file
body_file = PLAN.layout.body_file
case_file = PLAN.layout.case_file
sweep_file = PLAN.layout.sweep_file
design_file = PLAN.layout.design_file
wearers_file = PLAN.layout.wearers_file
size_chart_file = PLAN.layout.size_chart_file
SWEEP_BLOCKS, SWEEP_INDEX, CASES = PLAN.sweep, PLAN.index, PLAN.cases
DESIGNS = PLAN.designs
WEARERS = PLAN.wearers
SIZE_CHARTS = PLAN.size_charts
COMPARISONS = PLAN.comparisons
#: The wearers runs' cases: they run to result.nc only (no figures or views of their own).
WEARER_CASES = {name for run in WEARERS.values() for name in run.cases.values()}


def wearers_results(wildcards):
    """Every result.nc of a wearers entry (the size's body first)."""
    return [case_file("result.nc", n) for n in WEARERS[wildcards.entry].cases.values()]


def comparison_file(wildcards):
    """The measurements file a case is compared with (config comparisons)."""
    return COMPARISONS[wildcards.case]


def size_chart_material(wildcards):
    return SIZE_CHARTS[wildcards.entry].start.material


def size_chart_inputs(wildcards):
    """A size chart's material and, where given, its population file."""
    run = SIZE_CHARTS[wildcards.entry]
    return [run.start.material, *([run.population] if run.population else [])]


def size_chart_case_json(wildcards):
    return json.dumps(SIZE_CHARTS[wildcards.entry].start.to_dict(), sort_keys=True)


def wearers_index(wildcards):
    return WEARERS[wildcards.entry].index


def wearers_names(robust):
    """A wildcard constraint matching the wearers entries with targets (``robust``) or
    without; one that matches nothing where there are none."""
    names = [n for n, run in WEARERS.items() if (run.start is not None) == robust]
    return "|".join(names) if names else "(?!)"


def robust_material(wildcards):
    return WEARERS[wildcards.entry].start.material


def robust_case_json(wildcards):
    return json.dumps(WEARERS[wildcards.entry].start.to_dict(), sort_keys=True)


def robust_targets(wildcards):
    return " ".join(
        f"--target {shlex.quote(t)}" for t in WEARERS[wildcards.entry].targets
    )


def wearers_pairs(wildcards):
    """``NAME=RESULT`` per wearer, for cloth wearers-report."""
    cases = WEARERS[wildcards.entry].cases
    return " ".join(
        shlex.quote(f"{w}={case_file('result.nc', n)}") for w, n in cases.items()
    )


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


def surface_mesh(wildcards):
    return PLAN.body_block(wildcards.body)["mesh"]


def sweep_results(wildcards):
    return PLAN.sweep_results()


def figure_ranges(wildcards):
    """A case's colour-range file: its sweep's (cloth.figures.ranges), or none for a case
    outside the sweep (its figures take its own ranges)."""
    return [sweep_file("colour_ranges.json")] if wildcards.case in SWEEP_BLOCKS else []


def ranges_option(wildcards, input):
    """``--ranges FILE`` for ``cloth plot`` where the case has a colour-range file."""
    files = [input.ranges] if isinstance(input.ranges, str) else list(input.ranges)
    return " ".join(f"--ranges {shlex.quote(str(f))}" for f in files)


def confirmation_results(wildcards):
    from cloth.pipeline.sweep import confirm_name, read_design

    rows = read_design(checkpoints.design.get().output[0])
    return [
        case_file("result.nc", confirm_name(r)) for r in rows if r["status"] == "ok"
    ]


#: ``priority:`` of the rules on the way to the design's answers (a case's write, predeform,
#: relax and aggregate, the sweep, the design and its confirmation, the profile designs):
#: figures and views wait for them. Without it Snakemake's greedy scheduler prefers the ready
#: jobs with the largest inputs, the figures (each reads its whole sweep's results), and make
#: run's sweep waited for all 16 cases' figures before the design could start.
CRITICAL = 1

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
    bodies = config.get("bodies", {})
    sweep = [body_file("ply", n) for n, b in bodies.items() if "torso" in b]
    sweep += [
        body_file("check.txt", n)
        for n, b in bodies.items()
        if "mesh" in b or "avatar" in b
    ]
    if SWEEP_INDEX:
        names = ["sweep.nc", "sweep.csv", "design.png", "sweep_on_body.png"]
        names += ["design_confirmed.csv"] if config.get("targets") else []
        sweep += [sweep_file(name) for name in names]
    materials = sorted(config["materials"])
    files = ["initial.nc", "relaxed.nc", "result.nc", "summary.csv"]
    files += ["figures/stress_weft.png", *(["garment.html"] if VIEW else [])]
    designs = [
        design_file(name, design)
        for design in sorted(DESIGNS)
        for name in (
            ("design_confirmed.csv", "design_reductions.png")
            if DESIGNS[design].chart
            else ("design_confirmed.csv", "design_profile.png", "pattern.svg")
        )
    ]
    wearers = [
        wearers_file(name, entry)
        for entry in sorted(WEARERS)
        for name in (
            ("robust.csv", "confirmed/wearers.csv", "confirmed/wearers.png")
            if WEARERS[entry].start is not None
            else ("wearers.csv", "wearers.nc", "wearers.png")
        )
    ]
    size_charts = [
        size_chart_file(name, entry)
        for entry in sorted(SIZE_CHARTS)
        for name in ("sizes.csv", "chart.csv", "fabric_requirement.csv", "sizes.png")
    ]
    comparisons = [
        case_file(f"compare/{name}", case)
        for case in sorted(COMPARISONS)
        for name in ("compare.csv", "agreement.csv", "compare.nc", "compare.png")
    ]
    return (
        sweep
        + designs
        + wearers
        + size_charts
        + comparisons
        + [material_file(suffix, m) for m in materials for suffix in ("nc", "png")]
        + [
            case_file(name, case)
            for case in sorted(set(CASES) - WEARER_CASES)
            for name in files
        ]
    )


def case_resource(stage, name):
    """A rule's ``resources:`` entry: ``name`` (mem_mb, MB, or runtime, minutes) that
    ``stage`` of the job's case asks a cluster for (cloth/pipeline/resources.py). A confirmation case
    of the design asks what the largest sweep case asks (its block is read from the design
    checkpoint, which a cluster job of this rule cannot see)."""

    def value(wildcards):
        cases = resource_cases(wildcards)
        return max(getattr(stage_resources(stage, case), name) for case in cases)

    return value


def resource_cases(wildcards):
    """The cases whose needs a job of ``wildcards.case`` asks for: the case itself, or for a
    confirmation case of the design, every sweep case (`case_resource`)."""
    if wildcards.case in CASES:
        return [CASES[wildcards.case]]
    return [CASES[n] for n in SWEEP_BLOCKS] or [case_block(wildcards.case)]


def relax_threads(wildcards):
    """Rule relax's ``threads:``: the case's ``solver.blas_threads`` (relax holds every BLAS
    library to that many, docs/solvers.md; 1 by default, so that two cases relax side by side
    on two cores), or every core where it is null (the libraries' choice); Snakemake lowers
    it to ``--cores``."""
    asked = [case.solver.blas_threads for case in resource_cases(wildcards)]
    return (os.cpu_count() or 1) if None in asked else max(asked)


def design_answer(wildcards):
    """The design checkpoint's answer, for a confirmation case whose block is read from it (a
    cluster job needs it as an input to see it); nothing for the other cases."""
    if wildcards.case in CASES:
        return []
    return checkpoints.design.get().output[0]


SURFACE_RESOURCES = surface_resources()


def design_case_json(wildcards):
    """A profile design's start case, for `cloth case write --json`."""
    return json.dumps(DESIGNS[wildcards.design].first.to_dict(), sort_keys=True)


def design_arguments(wildcards):
    """A profile design's ``--target`` texts and pattern options, for `cloth design`."""
    design = DESIGNS[wildcards.design]
    return " ".join([f"--target={text}" for text in design.targets] + design.pattern)


def design_material(wildcards):
    return DESIGNS[wildcards.design].first.material


def design_body_files(wildcards):
    cases = DESIGNS[wildcards.design].cases.values()
    return sorted({path for case in cases for path in plan_body_files(case)})


def chart_writes(wildcards, output):
    """A chart design's shell: one `cloth case write` per size into ``output.starts``."""
    return " && ".join(
        f"cloth case write --json {shlex.quote(json.dumps(case.to_dict(), sort_keys=True))} "
        f"-o {shlex.quote(f'{output.starts}/{size}.yaml')}"
        for size, case in DESIGNS[wildcards.design].cases.items()
    )


def chart_inputs(wildcards, output):
    """A chart design's start cases, in the config's order of its bodies (the warm start's)."""
    return " ".join(
        shlex.quote(f"{output.starts}/{size}.yaml")
        for size in DESIGNS[wildcards.design].cases
    )


def design_names(chart):
    """A wildcard constraint matching the names of the chart designs (``chart``) or of the
    single ones; one that matches nothing where there are none."""
    names = [name for name, design in DESIGNS.items() if design.chart == chart]
    return "|".join(names) if names else "(?!)"
