"""The pipeline's wearers runs (config ``wearers``; issue 52, item 4): one garment on every
wearer of a size, one case per wearer, so that a cluster runs them side by side.

An entry names a body of the config with a size (a torso, leg or avatar of a chart whose
wearers ship, or ``folder``: a folder ``cloth body wearers`` wrote), a material and the
garment's reduction; the sweep's garment and solver with the entry's ``garment`` keys over
them. The garment is cut for that body and worn unchanged by each wearer (`cloth.garment.cut`).
Cases: ``wearers__{entry}__size`` (the body it is cut for) and ``wearers__{entry}__{wearer}``,
and with the entry's ``variation`` each of its values on the centre wearer
(``wearers__{entry}__centre~mu0.4``, `cloth.pipeline.variants.variation_cases`);
each runs through the pipeline's rules as any case (write_case, predeform, relax, aggregate;
no figures), and the rule ``wearers`` gathers their result.nc into
``{results}/wearers/{entry}/``: wearers.csv, wearers.nc and wearers.png
(`cloth.stages.wearers`).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from pathlib import Path

from cloth.bodies.wearers import SIZE
from cloth.case import Case
from cloth.errors import InputError
from cloth.files.wearers import INDEX, body_wearers, read_index
from cloth.pipeline.variants import variation_cases
from cloth.results.targets import config_targets

log = logging.getLogger(__name__)

#: Mesh options a wearer's body takes from the size's avatar body.
MESH_OPTIONS = ("surface", "smoothing", "spacing")


@dataclass(frozen=True)
class WearersRun:
    """A wearers entry: its cases (wearer -> case name, `SIZE` first) and its wearers index;
    for a robust design (``targets``) no cases, its start case, targets and wearers folder."""

    cases: dict[str, str]
    index: str
    start: Case | None = None
    targets: tuple[str, ...] = ()

    @property
    def folder(self) -> str:
        return str(Path(self.index).parent)


def case_name(entry: str, wearer: str) -> str:
    return f"wearers__{entry}__{wearer}"


def wearers_folder(body: dict, folder: str | None, where: str, data_path) -> tuple[Path, dict]:
    """The wearers folder of an entry's ``body`` block (its chart's shipped wearers, from the
    torso chart's default population or the chart's ranges) or ``folder``, and its index."""
    if folder is not None:
        path = Path(data_path(folder))
        try:
            return path, read_index(path)
        except InputError as exc:
            raise InputError(exc.detail, "config", f"{where}.folder") from None
    try:
        return body_wearers(body, data_path, f"{where}.body", "folder: DIR")
    except InputError as exc:
        raise InputError(exc.detail, "config", exc.field) from None


def configured_body(config: dict, name: str, field: str) -> dict:
    """The body block ``name`` under the config's ``bodies``; one line at ``field`` where it
    is not there."""
    bodies = config.get("bodies", {})
    if name not in bodies:
        raise InputError(
            f"body {name!r} is not defined under bodies "
            f"({', '.join(sorted(bodies)) or 'none defined'})",
            "config",
            field,
        )
    return bodies[name]


def wearers_blocks(plan, entry: str) -> tuple[dict[str, dict], str]:
    """Wearer -> case block of the config's wearers ``entry`` (module docstring), the size's
    body first, and its index file."""
    config = plan.config
    spec = config["wearers"][entry]
    where = f"wearers.{entry}"
    body = configured_body(config, spec["body"], f"{where}.body")
    folder, index = wearers_folder(body, spec.get("folder"), where, plan.found)
    own = plan.body_block(spec["body"])
    sweep = config.get("sweep") or {}
    garment = {
        **sweep.get("garment", {}),
        **spec.get("garment", {}),
        "reduction": spec.get("reduction", spec.get("start_reduction", 0.2)),
        "pattern": {"body": own},
    }
    base = {"material": spec["material"], "garment": garment, "solver": sweep.get("solver", {})}
    if "judge" in spec:
        base["judge"] = spec["judge"]
    if "variation" in spec:
        base["variation"] = spec["variation"]
    try:
        blocks = wearer_blocks({**base, "body": own}, folder, index)
    except InputError as exc:
        raise InputError(exc.detail, "config", f"{where}.{exc.field}") from None
    return blocks, str(folder / INDEX)


def wearer_blocks(data: dict, folder: Path, index: dict) -> dict[str, dict]:
    """Name -> case mapping of the size's body (`SIZE`: ``data``, a case mapping whose garment
    is the pattern every wearer wears) and of every fitted wearer of the wearers ``folder``
    with ``index``: ``data`` on her mesh, with the size's body's tissue and mesh options; and
    with ``data``'s ``variation`` each of its values on the centre wearer
    (`cloth.pipeline.variants.variation_cases`)."""
    out = {SIZE: data}
    options = {k: data["body"][k] for k in MESH_OPTIONS if k in data["body"]}
    tissue = data["body"].get("tissue")
    for wearer in index["wearers"]:
        if "mesh" not in wearer:
            log.warning("wearer %s: not fitted (%s); left out", wearer["name"], wearer["refused"])
            continue
        body = {"mesh": str((folder / wearer["mesh"]).resolve()), **options}
        if tissue is not None:
            body["tissue"] = tissue
        out[wearer["name"]] = {**data, "body": body}
    centre = "centre" if "centre" in out else next((n for n in out if n != SIZE), None)
    if centre is not None:
        out.update(variation_cases(data, out[centre], centre))
    return out


def _case(plan, entry: str, wearer: str, block: dict) -> Case:
    """The validated case of ``wearer`` of ``entry``; errors name ``wearers.{entry}``."""
    name = case_name(entry, wearer)
    try:
        return plan.case(name, block, "wearers")
    except InputError as exc:
        field = (exc.field or "").replace(f"wearers.{name}", f"wearers.{entry}")
        raise InputError(f"wearer {wearer}: {exc.detail}", "config", field or None) from None


def wearer_runs(plan) -> tuple[dict[str, WearersRun], dict[str, Case]]:
    """Every wearers entry of the plan's config and their cases, validated (their errors name
    the config key ``wearers.{entry}``)."""
    runs, cases = {}, {}
    for entry, spec in (plan.config.get("wearers") or {}).items():
        blocks, index = wearers_blocks(plan, entry)
        if "targets" in spec:  # a robust design: one job (cloth design --wearers)
            config_targets(spec["targets"], f"wearers.{entry}.targets")
            start = dict(blocks[SIZE])
            start["garment"] = {k: v for k, v in start["garment"].items() if k != "pattern"}
            case = _case(plan, entry, SIZE, start)
            runs[entry] = WearersRun({}, index, case, tuple(spec["targets"]))
            continue
        names = {}
        for wearer, block in blocks.items():
            name = case_name(entry, wearer)
            cases[name] = _case(plan, entry, wearer, block)
            names[wearer] = name
        runs[entry] = WearersRun(names, index)
    return runs, cases


__all__ = [
    "MESH_OPTIONS",
    "WearersRun",
    "case_name",
    "configured_body",
    "wearer_blocks",
    "wearer_runs",
    "wearers_blocks",
]
