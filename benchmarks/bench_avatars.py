"""Avatars: the fit per size, full-body scans used as given, and the avatar against the
parametric body at every girth line.

Three parts (``--parts``), each one run per row on this machine:

- ``fit``: `cloth.bodies.avatar.fit_avatar` for every size of the default torso and leg charts
  (the model loaded once before; needs the extra ``bodies``): seconds, evaluations, the largest
  girth residual. docs/performance.md, section ``avatar_fit``.
- ``region``: a full-body avatar (tests/data/full_body_mm_yup.ply: torso M's avatar in the
  model's A-pose, arms hanging, uncropped, mm, y up) relaxed at 96 x 48 between 0.86 and
  1.22 m, as given (the surface fitted over the region the garment wraps, the default), against
  the same mesh cropped by hand to 0.78-1.265 m and capped (the fit over all of it, as before
  regions; the crop needs the extra's shapely): surface-fit seconds, its grid samples, the
  whole run, the waist. The uncropped mesh without a region is refused (its samples are
  reported). docs/performance.md, section ``avatar_region``.
- ``compare``: the avatars against the parametric bodies of the same chart at every girth line,
  the torso at make run's garment and grid (config/config.yaml's sweep, reduction 0.20, no
  lengthwise reduction), the leg at the stocking's (config/stocking.yaml, reduction 0.16):
  band means and the highest node between the edge rows, mmHg. docs/bodies.md, section
  ``avatar_compare``.

Run (the fit and the crop need the extra: make bodies):

    .venv/bin/python benchmarks/bench_avatars.py [--parts fit region compare] [--no-write]
"""

from __future__ import annotations

import argparse
import csv
import json
import logging
import os
import tempfile
import time
from pathlib import Path

import numpy as np
import xarray as xr
import yaml
from _table import markdown_table, publish

from cloth.bodies.surface import FitOptions, fit_surface
from cloth.files.avatar import load_mesh
from cloth.stages.case import run_case

ROOT = Path(__file__).resolve().parents[1]
BODIES = ROOT / "docs" / "bodies.md"
FULL_BODY = ROOT / "tests" / "data" / "full_body_mm_yup.ply"
MMHG = 133.322387415


def fit_part(write: bool) -> None:
    import cloth.bodies.avatar as avatar

    avatar._Model()  # the model's cache built and loaded before the clock starts
    rows = []
    for chart in ("size_chart.csv", "leg_chart.csv"):
        for size in ("S", "M", "L"):
            fitted = avatar.fit_avatar(ROOT / "data" / "bodies" / chart, size)
            worst = max(abs(v) for k, v in fitted.residuals().items() if k != "stature")
            rows.append(
                [
                    f"{fitted.targets.kind} {size}",
                    f"{fitted.seconds:.1f}",
                    str(fitted.evaluations),
                    f"{worst * 1e3:.4f}",
                    f"{abs(fitted.residuals()['stature']) * 1e3:.4f}",
                ]
            )
    header = ["avatar", "fit s", "evaluations", "largest girth residual mm", "stature mm"]
    publish(markdown_table(header, rows), "avatar_fit", write)


def run(folder: Path, case: dict) -> tuple[float, Path]:
    path = folder / "case.yaml"
    folder.mkdir(parents=True, exist_ok=True)
    path.write_text(yaml.safe_dump(case))
    start = time.perf_counter()
    run_case(path, folder / "run", {}, base_dir=ROOT, stop_after="aggregate")
    return time.perf_counter() - start, folder / "run"


def band(folder: Path, line: str) -> float:
    rows = csv.DictReader((folder / "summary.csv").open())
    return next(float(r["pressure_mean_mmHg"]) for r in rows if r["landmark"] == line)


def region_part(write: bool, folder: Path) -> None:
    import trimesh

    from cloth.bodies.mesh import to_z_up

    garment = {"bottom": 0.86, "top": 1.22, "reduction": 0.2, "grid": [96, 48]}
    garment["edges"] = "sliding"
    full, _ = load_mesh(FULL_BODY, "mm", "y")
    mesh = trimesh.Trimesh(to_z_up(trimesh.load(FULL_BODY).vertices, "mm", "y"), full.faces)
    cut = mesh.slice_plane([0, 0, 0.78], [0, 0, 1], cap=True)
    cut = cut.slice_plane([0, 0, 1.265], [0, 0, -1], cap=True)
    cropped = folder / "cropped.ply"
    cut.export(cropped)
    rows = []
    for name, body, region in (
        ("full body, as given (region: the garment's)", FULL_BODY, (0.86, 1.22)),
        ("cropped by hand to 0.78-1.265 m (whole mesh)", cropped, None),
    ):
        units, up = ("mm", "y") if body == FULL_BODY else ("m", "z")
        loaded, _ = load_mesh(body, units, up, allow_holes=True)
        start = time.perf_counter()
        fit = fit_surface(loaded, FitOptions(region=region), progress=False)
        fit_seconds = time.perf_counter() - start
        samples = int(np.prod(fit.field.coefficients.shape))
        block = {"mesh": str(body), "units": units, "up": up}
        case = {"material": "powernet", "body": block, "garment": garment}
        seconds, out = run(folder / name[:9].replace(" ", "_"), case)
        rows.append(
            [
                name,
                f"{fit_seconds:.1f}",
                f"{samples / 1e6:.1f} M",
                f"{seconds:.1f}",
                f"{band(out, 'girth_min_1'):.2f}",
            ]
        )
    header = ["body", "surface fit s", "grid samples", "run s (fit, predeform, relax, aggregate)"]
    header.append("waist (girth_min_1) mmHg")
    publish(markdown_table(header, rows), "avatar_region", write)


def compare_part(write: bool, folder: Path) -> None:
    rows = []
    for config, pairs, reduction in (
        ("config.yaml", [("torso", "M"), ("torso", "S")], 0.20),
        ("stocking.yaml", [("leg", "S"), ("leg", "M"), ("leg", "L")], 0.16),
    ):
        sweep = yaml.safe_load((ROOT / "config" / config).read_text())["sweep"]
        garment = {**sweep["garment"], "reduction": reduction}
        for kind, size in pairs:
            chart = "size_chart.csv" if kind == "torso" else "leg_chart.csv"
            chart = f"data/bodies/{chart}"
            values = {}
            for label, body in (
                ("parametric", {kind: {"size": size}}),
                ("avatar", {"avatar": {"size": size, "chart": chart}}),
            ):
                case = {"material": "powernet", "body": body, "garment": garment}
                case["solver"] = sweep.get("solver", {})
                _, out = run(folder / f"{kind}_{size}_{label}", case)
                lines = list(csv.DictReader((out / "summary.csv").open()))
                with xr.open_dataset(out / "result.nc") as ds:
                    pressure = ds["pressure"].values[1:-1] / MMHG
                values[label] = (
                    {r["landmark"]: float(r["pressure_mean_mmHg"]) for r in lines},
                    float(np.nanmax(pressure)),
                )
            grid = "x".join(map(str, garment["grid"]))
            for line, value in values["parametric"][0].items():
                other = values["avatar"][0].get(line, float("nan"))
                rows.append(
                    [
                        f"{kind} {size}",
                        line,
                        f"{value:.2f}",
                        f"{other:.2f}",
                        f"{100 * (other / value - 1):+.0f} %",
                    ]
                )
            peak, other = values["parametric"][1], values["avatar"][1]
            rows.append(
                [
                    f"{kind} {size} ({grid}, r {reduction})",
                    "highest node between the edge rows",
                    f"{peak:.1f}",
                    f"{other:.1f}",
                    f"x {other / peak:.2f}",
                ]
            )
    header = ["body", "girth line", "parametric mmHg", "avatar mmHg", "difference"]
    publish(markdown_table(header, rows), "avatar_compare", write, BODIES)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--parts",
        nargs="+",
        default=["fit", "region", "compare"],
        choices=["fit", "region", "compare"],
    )
    parser.add_argument("--no-write", action="store_true")
    args = parser.parse_args()
    logging.basicConfig(level=logging.WARNING)
    folder = Path(tempfile.mkdtemp(prefix="cloth-avatars-"))
    os.environ["CLOTH_CACHE_DIR"] = str(folder / "cache")  # every fit is timed
    write = not args.no_write
    if "fit" in args.parts:
        fit_part(write)
    if "region" in args.parts:
        region_part(write, folder)
    if "compare" in args.parts:
        compare_part(write, folder)
    print(json.dumps({"folder": str(folder)}))


if __name__ == "__main__":
    main()
