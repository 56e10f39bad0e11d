"""The figure of docs/model.md: the default torso's pressure on a rigid body, on soft tissue
(E = 20 kPa, h = 15 mm) and with skin friction (mu = 0.4).

The pipeline's garment (torso M, the example power net cut 20 % small, 48 x 24 nodes from the
hip to the bust line, sliding edges) relaxed by Newton three times; front views of the pressure
on one colour range, and the pressure along the four girth lines. Run:

    .venv/bin/python benchmarks/figure_skin.py [-o docs/skin_models.png]

It prints the mean pressure on each girth line of each case (mmHg) for the docs' table.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import yaml
from matplotlib import colors

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from cloth.figures.drawing import body_band
from cloth.figures.onbody import VIEWS, draw_view, field_range
from cloth.figures.plots import save_figure
from cloth.io import read_netcdf
from cloth.stages.case import run_case

BASE = {
    "material": "powernet",
    "body": {"torso": {"size": "M"}},
    "garment": {
        "bottom": 0.86,
        "top": 1.22,
        "reduction": 0.2,
        "grid": [48, 24],
        "edges": "sliding",
    },
    "solver": {"method": "newton", "tolerance": 1e-8, "max_iterations": 150},
}
TISSUE = {"thickness": 0.015, "modulus": 20e3}
CASES = {
    "rigid, frictionless": BASE,
    "soft tissue (E 20 kPa, h 15 mm)": {**BASE, "body": {**BASE["body"], "tissue": TISSUE}},
    "skin friction (mu 0.4)": {**BASE, "contact": {"friction": 0.4}},
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    default = Path(__file__).resolve().parents[1] / "docs" / "skin_models.png"
    parser.add_argument("-o", "--output", type=Path, default=default)
    args = parser.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="cloth-skin-"))
    results = {}
    for k, (label, case) in enumerate(CASES.items()):
        path = folder / f"case{k}.yaml"
        path.write_text(yaml.safe_dump(case))
        run_case(path, folder / f"case{k}", {}, stop_after="aggregate")
        results[label] = read_netcdf(folder / f"case{k}" / "result.nc", "result")
    low, high = field_range(list(results.values()), "pressure_mmHg")
    norm = colors.Normalize(low, high)
    fig = plt.figure(figsize=(13.0, 4.6), layout="constrained")
    grid = fig.add_gridspec(1, 5, width_ratios=[1, 1, 1, 0.08, 1.5])
    for k, (label, ds) in enumerate(results.items()):
        ax = fig.add_subplot(grid[0, k], projection="3d")
        draw_view(ax, ds, body_band(ds), "pressure_mmHg", 1.0, norm, VIEWS["front"], girths=False)
        ax.set_title(label, fontsize=9)
    bar = fig.add_subplot(grid[0, 3])
    fig.colorbar(plt.cm.ScalarMappable(norm, "viridis"), cax=bar, label="pressure [mmHg]")
    ax = fig.add_subplot(grid[0, 4])
    names = results["rigid, frictionless"]["landmark"].values.tolist()
    print("girth line | " + " | ".join(results))
    for style, (label, ds) in zip(("o-", "s--", "^:"), results.items(), strict=True):
        means = ds["pressure_mean"].values / 133.322
        ax.plot(range(len(names)), means, style, label=label)
    for i, name in enumerate(names):
        print(
            f"{name} | "
            + " | ".join(
                f"{float(ds['pressure_mean'].values[i]) / 133.322:.2f}" for ds in results.values()
            )
        )
    ax.set_xticks(range(len(names)), names)
    ax.set_ylabel("mean pressure on the girth line [mmHg]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.suptitle("torso M, power net cut 20 % small: rigid body, soft tissue, skin friction")
    save_figure(fig, args.output)
    print(f"wrote {args.output}; cases in {folder}")


if __name__ == "__main__":
    main()
