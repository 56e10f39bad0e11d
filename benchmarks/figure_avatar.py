"""docs/avatar_pressure.png: one garment's pressure on the parametric torso M and on its avatar.

The power net cut 20 % small between the hip and bust lines (0.86-1.22 m), sliding edges,
96 x 48, on ``torso: {size: M}`` and on ``avatar: {size: M}`` (the same chart's girths at the
same heights); front, side and back views on one colour range, the girth lines' band means
labelled. Run:

    .venv/bin/python benchmarks/figure_avatar.py [-o docs/avatar_pressure.png]
"""

from __future__ import annotations

import argparse
import os
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import xarray as xr
import yaml
from matplotlib import colors

from cloth.figures.drawing import body_band
from cloth.figures.onbody import CMAP, FIELDS, VIEWS, draw_view, field_range
from cloth.figures.plots import save_figure
from cloth.stages.case import run_case

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", type=Path, default=ROOT / "docs" / "avatar_pressure.png")
    args = parser.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="cloth-avatar-figure-"))
    os.environ["CLOTH_CACHE_DIR"] = str(folder / "cache")
    garment = {"bottom": 0.86, "top": 1.22, "reduction": 0.2, "grid": [96, 48]}
    garment["edges"] = "sliding"
    results = []
    for label, body in (
        ("parametric torso M", {"torso": {"size": "M"}}),
        ("avatar M", {"avatar": {"size": "M"}}),
    ):
        case = folder / f"{label.split()[0]}.yaml"
        case.write_text(yaml.safe_dump({"material": "powernet", "body": body, "garment": garment}))
        run_case(case, folder / label.split()[0], {}, base_dir=ROOT, stop_after="aggregate")
        with xr.open_dataset(folder / label.split()[0] / "result.nc") as ds:
            results.append((label, ds.load()))
    variable, scale, text = FIELDS["body_pressure"]
    low, high = field_range([ds for _, ds in results], variable, scale)
    norm = colors.Normalize(low, high)
    fig = plt.figure(figsize=(10.5, 7.6), layout="constrained")
    axes = []
    for row, (label, ds) in enumerate(results):
        for column, (view, azimuth) in enumerate(VIEWS.items()):
            ax = fig.add_subplot(2, 3, 3 * row + column + 1, projection="3d")
            draw_view(ax, ds, body_band(ds), variable, scale, norm, azimuth, "mmHg")
            ax.set_title(f"{label}, {view}", fontsize=9)
            axes.append(ax)
    fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap=CMAP), ax=axes, shrink=0.6, label=text)
    save_figure(fig, args.output)
    print(args.output)


if __name__ == "__main__":
    main()
