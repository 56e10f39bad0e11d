"""The pipeline's size charts (config ``size_charts``; issue 62): a size chart designed for a
measured population, one ``cloth sizes`` job per entry.

An entry names a material and a body of the config with a size (a leg or torso of a chart:
every wearer's template), the target bands and the ``cloth sizes`` options; the sweep's garment
and solver with the entry's ``garment`` keys over them. The rule ``size_chart`` writes the
entry's start case and runs ``cloth sizes`` on it into ``{results}/size_charts/{entry}/``
(`cloth.stages.sizes`): sizes.csv, chart.csv, fabric_requirement.csv, fast_model.csv,
sizes.png, and each size's pattern, knitting table and confirmations.
"""

from __future__ import annotations

import shlex
from dataclasses import dataclass

from cloth.case import Case
from cloth.errors import InputError
from cloth.pipeline.wearers import configured_body
from cloth.results.targets import config_targets

#: ``cloth sizes`` options an entry may give, config key -> option.
OPTIONS = {
    "by": "--by",
    "coverage": "--coverage",
    "max_sizes": "--max-sizes",
    "max_variants": "--max-variants",
    "margin_mmHg": "--margin",
    "rounds": "--rounds",
}


@dataclass(frozen=True)
class SizeChartRun:
    """A size chart entry: its start case (the template body, the fabric, the garment and
    the solver) and the ``cloth sizes`` arguments after the case (``arguments``), its
    population file where one is given (``population``)."""

    start: Case
    arguments: str
    population: str | None = None


def size_chart_runs(plan) -> dict[str, SizeChartRun]:
    """Every size chart entry of the plan's config, validated (errors name the config key
    ``size_charts.{entry}``)."""
    config = plan.config
    runs = {}
    for entry, spec in (config.get("size_charts") or {}).items():
        where = f"size_charts.{entry}"
        configured_body(config, spec["body"], f"{where}.body")
        own = plan.body_block(spec["body"])
        if not any(k in own and "size" in own[k] for k in ("leg", "torso")):
            raise InputError(
                "a size chart's body is a leg or torso of a chart with a size (every wearer's "
                "template), e.g. {leg: {size: M}}",
                "config",
                f"{where}.body",
            )
        sweep = config.get("sweep") or {}
        garment = {**sweep.get("garment", {}), **spec.get("garment", {})}
        garment.setdefault("reduction", 0.2)  # the command cuts each size's own
        block = {
            "material": spec["material"],
            "garment": garment,
            "solver": sweep.get("solver", {}),
            "body": own,
        }
        try:
            start = plan.case(f"size_charts__{entry}", block, "size_charts")
        except InputError as exc:
            field = (exc.field or "").replace(f"size_charts.size_charts__{entry}", where)
            raise InputError(exc.detail, "config", field or where) from None
        config_targets(spec["targets"], f"{where}.targets")
        words = [word for text in spec["targets"] for word in ("--target", text)]
        for key, option in OPTIONS.items():
            if key in spec:
                words += [option, str(spec[key])]
        population = spec.get("population")
        if population is not None:
            population = plan.found(population)
            words += ["--population", population]
        if "ages" in spec:
            words += ["--ages", *(str(a) for a in spec["ages"])]
        runs[entry] = SizeChartRun(start, " ".join(shlex.quote(w) for w in words), population)
    return runs


__all__ = ["OPTIONS", "SizeChartRun", "size_chart_runs"]
