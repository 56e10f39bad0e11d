"""The pipeline's plan from its config: every case by name, the sweep's index, the design's
confirmation cases, checked before any job runs, in the config's file layout
(`cloth.pipeline.layout`). ``workflow/rules/common.smk`` keeps only the input functions that
hand these to the rules.

Names: a sweep case is ``{material}__{body}__r{reduction x 1000:03d}`` plus its skin and wear
variant's tag (`cloth.pipeline.variants`: none for a rigid, frictionless, new one); a configured
case keeps its key; a confirmation case is `cloth.pipeline.sweep.confirm_name`. A case's material
becomes its ingested file (``layout.material_file("nc", material)``); a mesh body's smooth
surface the pipeline's file (``layout.body_file("surface.nc", name)``).

Paths in the config are relative to the working directory. Where a path does not exist there
but does beside the workflow (``base``: its base directory, holding the bundled ``data/``),
the bundled file is used, so that the workflow runs from any working directory.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from cloth.bodies.avatar import chart_kind
from cloth.bodies.leg import DEFAULT_LEG_CHART
from cloth.bodies.leg import POINTS as LEG_POINTS
from cloth.bodies.torso import DEFAULT_CHART
from cloth.bodies.torso import LANDMARKS as TORSO_LANDMARKS
from cloth.case import Case
from cloth.case.case import validate_case
from cloth.errors import InputError
from cloth.files.avatar import avatar_mesh
from cloth.paths import input_file
from cloth.pipeline.layout import DEFAULT, Layout, results_folder
from cloth.pipeline.sizecharts import SizeChartRun, size_chart_runs
from cloth.pipeline.variants import Variant, sweep_variants
from cloth.pipeline.wearers import WearersRun, wearer_runs
from cloth.results.targets import config_targets
from cloth.shipped import shipped


def data_path(path: str, base: str | Path | None) -> str:
    """``path`` as given where it exists (or is absolute, or ``base`` is None), else the
    bundled file ``base / path`` where that exists, else, for a path into ``data/``, the
    package's shipped file (`cloth.shipped`: an installed package runs its workflow from its
    own folder, its data beside it), else as given (its rule then reports it missing)."""
    given = Path(path)
    if base is None or given.is_absolute() or given.exists():
        return path
    bundled = Path(base) / given
    if bundled.exists():
        return str(bundled)
    if given.parts[:1] == ("data",) and shipped(*given.parts[1:]).exists():
        return str(shipped(*given.parts[1:]))
    return path


def local_body(
    body: dict,
    name: str,
    base: str | Path | None = None,
    layout: Layout = DEFAULT,
    span: tuple[float, float] | None = None,
) -> dict:
    """A body block with its files found (`data_path`); an avatar as the mesh it names
    (`cloth.files.avatar.avatar_mesh`, whose sidecar keeps its girth lines); and, for a mesh
    body contacted through its smooth surface (the default), the pipeline's surface file of
    body ``name`` (in ``layout``), fitted over ``region``, else ``span`` (`config_span`: one
    fit serves every case of the body)."""
    body = dict(body)
    if "avatar" in body:
        avatar = dict(body.pop("avatar"))
        for key in ("chart", "mesh"):
            if key in avatar:
                avatar[key] = data_path(avatar[key], base)
        body["mesh"] = str(avatar_mesh(avatar, base or "."))
    if "mesh" in body:
        body["mesh"] = data_path(body["mesh"], base)
        if body.get("surface", "smooth") == "smooth":
            body = {"surface_file": layout.body_file("surface.nc", name), **body}
            if span is not None and "region" not in body:
                body["region"] = [float(span[0]), float(span[1])]
    for kind in ("torso", "leg"):
        if kind in body and "chart" in body[kind]:
            body[kind] = {**body[kind], "chart": data_path(body[kind]["chart"], base)}
    return body


#: Body kinds whose smooth surface is fitted over a region (`config_span`).
SURFACE_KINDS = ("mesh", "avatar")


def config_span(config: dict) -> tuple[float, float] | None:
    """The lowest bottom and highest top (m) of every garment the config names that a fitted
    surface may carry (the sweep's, each case's on a mesh or avatar, each profile design's):
    the region a mesh body's one smooth surface covers. A case on a cylinder or a parametric
    torso does not widen it."""
    garments = [(config.get("sweep") or {}).get("garment") or {}]
    garments += [
        case.get("garment") or {}
        for case in (config.get("cases") or {}).values()
        if any(kind in (case.get("body") or {}) for kind in SURFACE_KINDS)
    ]
    garments += [
        {**garments[0], **(design.get("garment") or {})}
        for design in (config.get("profile_designs") or {}).values()
    ]
    bottoms = [g["bottom"] for g in garments if isinstance(g.get("bottom"), int | float)]
    tops = [g["top"] for g in garments if isinstance(g.get("top"), int | float)]
    if not bottoms or not tops:
        return None
    return float(min(bottoms)), float(max(tops))


def reduction_tag(reduction: float) -> str:
    """``r`` and the reduction in thousandths, three digits: 0.15 -> r150."""
    return f"r{round(1000 * reduction):03d}"


def sweep_name(material: str, body: str, reduction: float, variant: Variant | None = None) -> str:
    """The name of a sweep case."""
    tag = variant.tag() if variant is not None else ""
    return f"{material}__{body}__{reduction_tag(reduction)}{tag}"


@dataclass(frozen=True)
class ProfileDesign:
    """A profile design of the config: its start case per body (config body name -> case;
    several bodies: every size of a chart, designed at once), its targets as ``cloth design
    --target`` texts, its tolerance (mmHg) and its pattern's options as ``cloth design``
    arguments (``--cut``, ``--seam-allowance``, ``--paper``)."""

    cases: dict[str, Case]
    targets: list[str]
    tolerance: float
    pattern: list[str]
    chart: bool

    @property
    def first(self) -> Case:
        return next(iter(self.cases.values()))


@dataclass
class Plan:
    """The cases of a config: ``cases`` (name -> validated case block, sweep cases included),
    ``sweep`` (name -> block of the sweep's cases, before validation) and ``index`` (one entry
    per sweep case: case, material, body, reduction, and the variant keys the sweep varies)."""

    config: dict
    base: str | Path | None = None
    #: Where the run's files go (its config's results folder).
    layout: Layout = field(default_factory=Layout)
    cases: dict[str, Case] = field(default_factory=dict)
    sweep: dict[str, dict] = field(default_factory=dict)
    index: list[dict] = field(default_factory=list)
    #: Profile designs by name (`ProfileDesign`).
    designs: dict[str, ProfileDesign] = field(default_factory=dict)
    #: Wearers runs by entry (`cloth.pipeline.wearers`); their cases are in ``cases`` too.
    wearers: dict[str, WearersRun] = field(default_factory=dict)
    #: Size charts by entry (`cloth.pipeline.sizecharts`).
    size_charts: dict[str, SizeChartRun] = field(default_factory=dict)
    #: Measured readings by case name (config ``comparisons``): the measurements CSV each
    #: case is compared with (`cloth.stages.compare`).
    comparisons: dict[str, str] = field(default_factory=dict)

    def case(self, name: str, block: dict | None = None, where: str = "cases") -> Case:
        """Case ``name`` of the config (or ``block``) with its material as the ingested file,
        validated; errors name the config key ``where``.``name``."""
        config = self.config
        if block is None:
            block = dict(config.get("cases", {})[name])
            bodies = config.get("bodies", {})
            same = [key for key, body in bodies.items() if body == block["body"]]
            block["body"] = local_body(
                block["body"],
                same[0] if same else f"case-{name}",
                self.base,
                self.layout,
                self.span,
            )
        block = dict(block)
        material = block.get("material")
        if material not in config["materials"]:
            raise InputError(
                f"material {material!r} is not defined under materials "
                f"({', '.join(sorted(config['materials']))})",
                "config",
                f"{where}.{name}.material",
            )
        block["material"] = self.layout.material_file("nc", material)
        return validate_case(block, f"config: {where}.{name}")

    def sweep_block(
        self, material: str, body: str, reduction: float, variant: Variant | None = None
    ) -> dict:
        """The block of the sweep's case of ``material``, ``body``, ``reduction`` and skin and
        wear ``variant`` (default: rigid, frictionless, new)."""
        sweep = self.config["sweep"]
        block = {
            "material": material,
            "body": local_body(
                self.config["bodies"][body], body, self.base, self.layout, self.span
            ),
            "garment": {**sweep["garment"], "reduction": reduction},
            "solver": sweep.get("solver", {}),
        }
        if variant is None:
            return block
        return variant.apply(block, sweep.get("tissue_thickness"))

    def design_case(self, row: dict) -> dict:
        """The confirmation case of a design answer (a row of design.csv)."""
        return self.sweep_block(
            row["material"], row["body"], float(row["reduction"]), Variant.of(row)
        )

    def material_tables(self, material: str) -> list[str]:
        """The lab table(s) of a material, found (`data_path`)."""
        table = self.config["materials"][material]["table"]
        tables = [table] if isinstance(table, str) else list(table)
        return [data_path(t, self.base) for t in tables]

    def material_block(self, material: str) -> dict:
        """A material's config block, its tables found: what ``cloth material ingest --json``
        takes."""
        return {**self.config["materials"][material], "table": self.material_tables(material)}

    def body_block(self, name: str) -> dict:
        """The body block of a body name (a configured body, or ``case-{case}`` for a case's
        own), its files found (`local_body`): what ``cloth body torso``, ``fit`` and ``check``
        take as ``--json``."""
        cases = self.config.get("cases", {})
        if name.startswith("case-") and name[5:] in cases:
            return local_body(cases[name[5:]]["body"], name, self.base, self.layout, self.span)
        return local_body(self.config["bodies"][name], name, self.base, self.layout, self.span)

    def found(self, path: str) -> str:
        """A path of the config, found where the pipeline looks for it (`data_path`)."""
        return data_path(path, self.base)

    @property
    def span(self) -> tuple[float, float] | None:
        """The heights every garment of the config spans (`config_span`)."""
        return config_span(self.config)

    def sweep_results(self) -> list[str]:
        """The result file of every sweep case, in the index's order (``cloth sweep``'s)."""
        return [self.layout.case_file("result.nc", entry["case"]) for entry in self.index]


def _expand_sweep(plan: Plan) -> None:
    sweep = plan.config.get("sweep")
    if not sweep:
        return
    bodies = plan.config.get("bodies", {})
    for key, names, pool in (
        ("sweep.materials", sweep["materials"], plan.config["materials"]),
        ("sweep.bodies", sweep["bodies"], bodies),
    ):
        for name in names:
            if name not in pool:
                raise InputError(
                    f"{name!r} is not defined ({', '.join(sorted(pool)) or 'none defined'})",
                    "config",
                    key,
                )
    finite = [v for v in sweep.get("tissue_moduli", []) if v is not None and v != float("inf")]
    if finite and "tissue_thickness" not in sweep:
        raise InputError(
            "tissue_moduli needs tissue_thickness (m), the layer's thickness",
            "config",
            "sweep.tissue_thickness",
        )
    variants = sweep_variants(sweep)
    for material in sweep["materials"]:
        for body in sweep["bodies"]:
            for reduction in sweep["reductions"]:
                for keys, variant in variants:
                    name = sweep_name(material, body, reduction, variant)
                    plan.sweep[name] = plan.sweep_block(material, body, reduction, variant)
                    plan.index.append(
                        {
                            "case": name,
                            "material": material,
                            "body": body,
                            "reduction": reduction,
                            **keys,
                        }
                    )


def profile_design(plan: Plan, name: str) -> ProfileDesign:
    """A profile design of the config (``profile_designs``): its start case per body (the
    sweep's garment and solver, the design's garment keys over them, its start reduction), its
    targets as ``cloth design --target`` texts, its tolerance (mmHg) and pattern options."""
    config = plan.config
    design = config["profile_designs"][name]
    where = f"profile_designs.{name}"
    if ("body" in design) == ("bodies" in design):
        raise InputError(
            "give body (one body) or bodies (every size of a chart at once), not both or neither",
            "config",
            where,
        )
    names = [design["body"]] if "body" in design else list(design["bodies"])
    key = "body" if "body" in design else "bodies"
    for number, body in enumerate(names):
        if body not in config.get("bodies", {}):
            raise InputError(
                f"body {body!r} is not defined under bodies "
                f"({', '.join(sorted(config.get('bodies', {}))) or 'none defined'})",
                "config",
                f"{where}.{key}" + ("" if key == "body" else f".{number}"),
            )
    if len(set(names)) != len(names):
        raise InputError("a body is listed twice; give each size once", "config", f"{where}.bodies")
    if "reduction" in design.get("garment", {}):
        raise InputError(
            "the design sets the reduction; use start_reduction",
            "config",
            f"{where}.garment.reduction",
        )
    sweep = config.get("sweep") or {}
    cases = {}
    for body in names:
        block = {
            "material": design["material"],
            "body": local_body(config["bodies"][body], body, plan.base, plan.layout, plan.span),
            "garment": {
                **sweep.get("garment", {}),
                **design.get("garment", {}),
                "reduction": design.get("start_reduction", 0.2),
            },
            "solver": sweep.get("solver", {}),
        }
        cases[body] = plan.case(name, block, "profile_designs")
    config_targets(design["targets"], f"{where}.targets")
    targets = list(design["targets"])
    lines = [text.split("=", 1)[0].strip() for text in targets]
    if len(set(lines)) != len(lines):
        raise InputError(
            "a girth line is targeted twice; give each line once", "config", f"{where}.targets"
        )
    pattern = design.get("pattern", {})
    options = [
        f"--cut={pattern.get('cut', 'auto')}",
        f"--seam-allowance={float(pattern.get('seam_allowance_mm', 6.0))}",
        f"--paper={pattern.get('paper', 'A4')}",
    ]
    return ProfileDesign(
        cases, targets, float(design.get("tolerance_mmHg", 0.5)), options, "bodies" in design
    )


#: The girth lines of the parametric bodies, known before any job runs.
PARAMETRIC_LINES = {"torso": TORSO_LANDMARKS, "leg": LEG_POINTS}


def check_targets(config: dict, base: str | Path | None = None) -> None:
    """Targets need one pressure and a girth line the sweep's bodies have (known in advance:
    the torso's four lines, the leg's measuring points, an avatar's chart's; other bodies get
    'middle' or girth_min_N / girth_max_N)."""
    sweep = config.get("sweep") or {}
    bodies = [config.get("bodies", {}).get(name, {}) for name in sweep.get("bodies", [])]
    kinds = {
        chart_kind(data_path(body["avatar"].get("chart", str(DEFAULT_CHART)), base))
        if "avatar" in body
        else next((k for k in PARAMETRIC_LINES if k in body), "other")
        for body in bodies
    }
    known = [line for kind in sorted(kinds - {"other"}) for line in PARAMETRIC_LINES[kind]]
    for number, target in enumerate(config.get("targets", [])):
        where = f"targets.{number}"
        if ("pressure_mmHg" in target) == ("pressure_kPa" in target):
            raise InputError("give exactly one of pressure_mmHg or pressure_kPa", "config", where)
        name = target["landmark"]
        if name in known or ("other" in kinds and (name == "middle" or name.startswith("girth_"))):
            continue
        others = ", or middle, girth_min_N / girth_max_N (other bodies)" if "other" in kinds else ""
        raise InputError(
            f"unknown landmark {name!r}; the sweep's bodies have {', '.join(known)}{others}",
            "config",
            f"{where}.landmark",
        )


#: Config keys whose numbers may be +infinity, and what it means there (the config schema's
#: description says so too).
INFINITE = {("sweep", "tissue_moduli"): "a rigid body"}


def check_finite(data: object, path: tuple = ()) -> None:
    """Refuse (`InputError`) a number in the config that is NaN or infinite, except +infinity
    where `INFINITE` gives it a meaning: YAML's .nan and .inf pass the config schema."""
    if isinstance(data, dict):
        for key, value in data.items():
            check_finite(value, (*path, str(key)))
    elif isinstance(data, list):
        for index, value in enumerate(data):
            check_finite(value, (*path, str(index)))
    elif isinstance(data, float) and not math.isfinite(data):
        if data == math.inf and path[:2] in INFINITE:
            return
        raise InputError(
            f"{data} is not a finite number; give a finite value", "config", ".".join(path)
        )


def check_inputs(plan: Plan) -> None:
    """The user's files the config names exist as files (lab tables, meshes, size charts),
    checked before any job runs (`cloth.paths.input_file`), where they are looked for
    (`data_path`)."""
    config = plan.config
    for name, block in config["materials"].items():
        several = not isinstance(block["table"], str)
        for index, table in enumerate(plan.material_tables(name)):
            field = f"materials.{name}.table" + (f".{index}" if several else "")
            input_file(table, ".", "config", field, "lab table")
    bodies = {
        **config.get("bodies", {}),
        **{f"cases.{n}": c["body"] for n, c in config.get("cases", {}).items()},
    }
    for name, body in bodies.items():
        where = name if name.startswith("cases.") else f"bodies.{name}"
        if "mesh" in body:
            input_file(
                data_path(body["mesh"], plan.base), ".", "config", f"{where}.mesh", "mesh file"
            )
        for kind in ("torso", "leg", "avatar"):
            if "chart" in body.get(kind, {}):
                input_file(
                    data_path(body[kind]["chart"], plan.base),
                    ".",
                    "config",
                    f"{where}.{kind}.chart",
                    "size chart",
                )
        if "avatar" in body:
            avatar = {
                k: data_path(v, plan.base) if k in ("chart", "mesh") else v
                for k, v in body["avatar"].items()
            }
            try:
                avatar_mesh(avatar)
            except InputError as exc:
                raise InputError(exc.detail, "config", f"{where}.avatar") from None


def make_plan(
    config: dict, base: str | Path | None = None, config_file: str | Path | None = None
) -> Plan:
    """The plan of a (schema-validated) config read from ``config_file``, every case
    validated, every number finite and every input file present, its files in the config's
    results folder (`cloth.pipeline.layout.results_folder`); `InputError` naming the config key
    on the first problem."""
    check_finite(config)
    plan = Plan(config, base, Layout(results_folder(config, config_file)))
    check_inputs(plan)
    _expand_sweep(plan)
    check_targets(config, base)
    for name in plan.sweep:
        if name in config.get("cases", {}):
            raise InputError("a case of this name is also in the sweep", "config", f"cases.{name}")
    plan.cases = {name: plan.case(name) for name in config.get("cases", {})}
    plan.cases.update({name: plan.case(name, block) for name, block in plan.sweep.items()})
    plan.designs = {name: profile_design(plan, name) for name in config.get("profile_designs", {})}
    plan.wearers, worn = wearer_runs(plan)
    for name in worn:
        if name in plan.cases:
            raise InputError(
                "a case of this name is also a wearers case", "config", f"cases.{name}"
            )
    plan.cases.update(worn)
    plan.size_charts = size_chart_runs(plan)
    plan.comparisons = comparison_files(plan)
    return plan


def comparison_files(plan: Plan) -> dict[str, str]:
    """The config's ``comparisons``: case name -> its measurements file (where it is looked
    for, `data_path`); `InputError` naming the key where the case is not one of the plan's or
    the file is missing."""
    out = {}
    for name, path in (plan.config.get("comparisons") or {}).items():
        field_name = f"comparisons.{name}"
        if name not in plan.cases:
            raise InputError(
                f"no case {name!r} to compare; name one of cases or the sweep", "config", field_name
            )
        found = data_path(path, plan.base)
        input_file(found, ".", "config", field_name, "measurements file")
        out[name] = found
    return out


def body_files(case: Case) -> list[str]:
    """Files a case's body reads (mesh and its surface file, or size chart), so that editing
    them reruns the case."""
    body = case.body
    if body.kind == "mesh":
        surface = body.option("surface_file")
        return [body.option("mesh"), *([surface] if surface is not None else [])]
    if body.kind == "torso":
        return [body.params.get("chart", str(DEFAULT_CHART))]
    if body.kind == "leg":
        return [body.params.get("chart", str(DEFAULT_LEG_CHART))]
    return []
