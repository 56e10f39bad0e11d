"""What ``cloth sizes`` is asked (issue 62), checked before any work: the bands, the sizing
measures, the population file and the case body every wearer is built from
(`cloth.stages.sizes` runs it). Each refusal is one line naming the file or option and the
column or field."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from cloth.bodies.leg import DEFAULT_LEG_CHART
from cloth.bodies.torso import DEFAULT_CHART
from cloth.case import Case
from cloth.case.case import load_case
from cloth.errors import InputError
from cloth.files.population import AGES, ALIASES, Population
from cloth.files.wearers import default_population
from cloth.results.sizechart import Band
from cloth.results.targets import Target


@dataclass(frozen=True)
class Request:
    """What ``cloth sizes`` is asked: the ``population`` file, the target ``bands``, the sizing
    measures ``by`` (chart names, primary first), the ``coverage`` (0-1), the most sizes and
    variants per size, the ``ages`` kept, the search ``margin`` (Pa; None: from the fast
    model's error, module docstring) and the most ``rounds`` of confirmation (the searched
    chart's, then the recut sizes')."""

    population: Path
    bands: tuple[Band, ...]
    by: tuple[str, ...]
    coverage: float = 0.95
    max_sizes: int = 8
    variants: int = 3
    ages: tuple[float, float] | None = AGES
    margin: float | None = None
    rounds: int = 2


def bands_of(targets: list[Target]) -> tuple[Band, ...]:
    """Bands from ``--target LINE=LOW:HIGH``; one line for a target that is not a band or a
    line asked twice."""
    bands = []
    for target in targets:
        if target.band is None:
            raise InputError(
                f"{target.line}: cloth sizes needs a band; write {target.line}=LOW:HIGH (mmHg)",
                field="--target",
            )
        if any(b.line == target.line for b in bands):
            raise InputError(f"the line {target.line} is asked twice", field="--target")
        bands.append(Band(target.line, *target.band))
    return tuple(bands)


def population_of(case_path: Path, text: str) -> Path:
    """``--population``: a file, or ``default``: the shipped population of the case body's
    kind (`cloth.files.wearers.default_population`)."""
    if text != "default":
        return Path(text)
    kind = load_case(case_path).body.kind
    return default_population("leg" if kind == "leg" else "torso")


def template_of(case: Case, base_dir: Path) -> tuple[str, Path, str, dict]:
    """The case body's kind ('leg' or 'torso'), chart, size and block: the template of every
    wearer's body; one line for another body."""
    block = case.body.block
    kind = case.body.kind
    spec = block.get(kind, {}) if isinstance(block.get(kind), dict) else {}
    if kind not in ("leg", "torso") or "size" not in spec:
        raise InputError(
            "cloth sizes builds every wearer as a parametric leg or torso of her measures from "
            "the case's body; give the case a body {leg: {size: M}} or {torso: {size: M}} (a "
            "chart's size: her template)",
            None,
            "body",
        )
    default = DEFAULT_LEG_CHART if kind == "leg" else DEFAULT_CHART
    chart = base_dir / Path(spec["chart"]).expanduser() if "chart" in spec else default
    return kind, chart.resolve(), str(spec["size"]), spec


def measure_names(request: Request, people: Population, points: tuple[str, ...]) -> None:
    """Refuse in one line a sizing measure or target line the chart or the population lacks,
    or a sizing measure with no band."""
    lines = [b.line for b in request.bands]
    for line in lines:
        if line not in points:
            raise InputError(
                f"{line} is not a girth line of the case's chart ({', '.join(points)})",
                None,
                "--target",
            )
    for name in dict.fromkeys([*request.by, *lines]):
        if name not in people.measures:
            survey = [k for k, v in ALIASES.items() if v == name]
            also = f" (or {survey[0]}_cm)" if survey else ""
            raise InputError(
                f"the population has no {name} girth; add a column {name}_cm{also}, in cm",
                people.path,
                f"{name}_cm",
            )
    for name in request.by:
        if name not in lines:
            raise InputError(
                f"--by {name}: a sizing measure needs a band at its line; add --target "
                f"{name}=LOW:HIGH",
                None,
                "--by",
            )


def sizing_names(text: str) -> tuple[str, ...]:
    """``--by ankle[,calf]`` as the chart's names (`ALIASES`): one or two, distinct."""
    names = tuple(ALIASES.get(n.strip(), n.strip()) for n in text.split(","))
    if not 1 <= len(names) <= 2 or not all(names) or len(set(names)) != len(names):
        raise InputError(
            f"give one or two distinct measures, e.g. ankle or ankle,calf; got {text!r}",
            field="--by",
        )
    return names


__all__ = [
    "Request",
    "bands_of",
    "measure_names",
    "population_of",
    "sizing_names",
    "template_of",
]
