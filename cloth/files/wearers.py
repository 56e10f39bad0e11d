"""A size's wearers as files (issue 52, item 2): one avatar each and an index.

`cloth body wearers CHART --size NAME [--population FILE] -o DIR` writes into ``DIR``:

- ``{wearer}.ply`` and ``{wearer}.json``: each wearer's avatar (`cloth.files.avatar`; the
  sidecar's ``size`` is ``SIZE/WEARER``, its landmarks the wearer's girth-line heights);
- ``wearers.json``: the index: the chart (name, sha256) and size, where the wearers come from
  (``population`` with the file's name, sha256 and the ages kept, or ``ranges``), how many
  people the size holds and their survey weight, the share the wearers' range covers, and per
  wearer its mesh, quantiles and targets (girths and stature, m), or why the body model could
  not reach them (``refused``).

The default charts' wearers ship in ``data/bodies/wearers/{kind}_{size}/`` (the torso's from
the shipped NHANES population, the leg's from the chart's ranges), found by the chart's and the
population's sha256 (`shipped_wearers`), so no extra is needed to use them.
"""

from __future__ import annotations

import json
from pathlib import Path

from cloth.bodies.leg import DEFAULT_LEG_CHART
from cloth.bodies.torso import DEFAULT_CHART
from cloth.bodies.wearers import Wearers
from cloth.errors import InputError
from cloth.io import atomic_output, sha256
from cloth.shipped import shipped

#: Where the default charts' wearers ship.
SHIPPED = shipped("bodies", "wearers")
#: Where the shipped populations are (data/bodies/README.md).
POPULATIONS = shipped("bodies", "population")
#: The default population of the torso chart's wearers: US NHANES 2017-2020.
DEFAULT_POPULATION = POPULATIONS / "nhanes_2017_2020_women.csv"
#: The default population of the leg chart's wearers and size charts: US Army ANSUR II women.
DEFAULT_LEG_POPULATION = POPULATIONS / "ansur2_women.csv"


def default_population(kind: str) -> Path:
    """The shipped population of a chart of ``kind`` ('torso' or 'leg')."""
    return DEFAULT_LEG_POPULATION if kind == "leg" else DEFAULT_POPULATION


INDEX = "wearers.json"
FORMAT = 1


def index_record(
    wearers: Wearers,
    chart: str | Path,
    size: str,
    population: str | Path | None,
    ages: tuple[float, float] | None,
    fitted: dict[str, str],
) -> dict:
    """The index (module docstring); ``fitted``: wearer -> its mesh's file name, or
    ``refused: ...`` with the reason."""
    first = wearers.wearers[0].targets
    return {
        "cloth_wearers": FORMAT,
        "kind": first.kind,
        "chart": Path(chart).name,
        "chart_sha256": sha256(chart),
        "size": size,
        "source": wearers.source,
        "population": None if population is None else Path(population).name,
        "population_sha256": None if population is None else sha256(population),
        "ages": None if population is None or ages is None else list(ages),
        "people": wearers.people,
        "weight": wearers.weight,
        "coverage": round(wearers.coverage, 6),
        "measures": list(wearers.measures),
        "wearers": [
            {
                "name": w.name,
                **(
                    {"refused": fitted[w.name].removeprefix("refused: ")}
                    if fitted[w.name].startswith("refused: ")
                    else {"mesh": fitted[w.name]}
                ),
                "quantiles": dict(w.quantiles),
                "girths_m": {
                    k: round(v, 9) for k, v in w.targets.girth.items() if k not in w.targets.free
                },
                "free": list(w.targets.free),
                "heights_m": {k: round(v, 9) for k, v in w.targets.height.items()},
                "stature_m": round(w.targets.stature, 9),
            }
            for w in wearers.wearers
        ],
    }


def write_index(record: dict, folder: str | Path) -> Path:
    path = Path(folder) / INDEX
    with atomic_output(path) as tmp:
        tmp.write_text(json.dumps(record, indent=1, sort_keys=True) + "\n")
    return path


def read_index(folder: str | Path) -> dict:
    """A wearers folder's index; one line for a folder without one."""
    path = Path(folder) / INDEX
    if not path.is_file():
        raise InputError(
            f"no {INDEX}: not a wearers folder; write one with cloth body wearers",
            folder,
            "wearers",
        )
    try:
        record = json.loads(path.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise InputError(f"not JSON ({exc})", path) from None
    if not isinstance(record, dict) or "cloth_wearers" not in record:
        raise InputError("not a wearers index; write it with cloth body wearers", path)
    return record


def shipped_wearers(
    chart: str | Path, size: str, population: str | Path | None = None
) -> Path | None:
    """The folder of the shipped wearers of ``size`` of ``chart`` from ``population`` (None:
    from the chart's ranges), matched by sha256; None where none ship."""
    digest = sha256(chart)
    people = None if population is None else sha256(population)
    for path in sorted(SHIPPED.glob(f"*/{INDEX}")):
        record = json.loads(path.read_text())
        if (
            record.get("chart_sha256") == digest
            and record.get("size") == size
            and record.get("population_sha256") == people
        ):
            return path.parent
    return None


def body_wearers(body: dict, resolve, field: str, how: str) -> tuple[Path, dict]:
    """The shipped wearers folder of a body block with a size (a torso, leg or avatar of a
    chart: its chart's wearers, from the torso's default population or the chart's ranges) and
    its index; ``resolve`` finds the block's chart path. One line at ``field`` where the body has
    no size or none ship, ending with ``how`` a user gives a folder instead."""
    kind = next((k for k in ("torso", "leg", "avatar") if k in body), None)
    spec = body.get(kind, {}) if kind else {}
    if "size" not in spec:
        raise InputError(
            "the body has no size, so it has no wearers; give a torso, leg or avatar body with "
            f"a size, or {how}",
            None,
            field,
        )
    chart = Path(resolve(spec["chart"])) if "chart" in spec else None
    if chart is None:
        chart = DEFAULT_LEG_CHART if kind == "leg" else DEFAULT_CHART
    for population in (DEFAULT_POPULATION, DEFAULT_LEG_POPULATION, None):
        found = shipped_wearers(chart, spec["size"], population)
        if found is not None:
            return found, read_index(found)
    raise InputError(
        f"no wearers of size {spec['size']} ship for {chart}; make them with `cloth body "
        f"wearers {chart} --size {spec['size']} -o DIR` (pip install 'cloth[bodies]') and give "
        f"{how}",
        None,
        field,
    )


__all__ = [
    "DEFAULT_LEG_POPULATION",
    "DEFAULT_POPULATION",
    "INDEX",
    "SHIPPED",
    "body_wearers",
    "default_population",
    "index_record",
    "read_index",
    "shipped_wearers",
    "write_index",
]
