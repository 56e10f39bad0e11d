"""A stocking on the leg with soft tissue by region: the pressure profile from ankle to thigh
on a rigid leg and on a leg whose tissue is thin over the lower shin and soft over the calf.

    .venv/bin/python docs/examples/stocking_tissue.py   # writes docs/leg_tissue.png

Tissue bands are by height (`body.tissue.bands`, docs/model.md): the band from B to B1 (the
lower leg, where the tibia and the malleoli lie under a thin layer) is 4 mm thick and stiff,
the band over the calf (from B1 to D) 25 mm thick and soft; elsewhere a 10 mm layer of 20 kPa.
The run leaves ``heights`` (m), ``rigid`` and ``tissue`` (row-mean pressures, Pa) and
``bands`` for tests/test_examples.py.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np
import xarray as xr
import yaml

from cloth.bodies.leg import leg_size
from cloth.stages.case import run_case

ROOT = Path(__file__).resolve().parents[2]
CHART = leg_size("M")
B, B1, D = (CHART.height[p] for p in ("B", "B1", "D"))
BANDS = [
    {"bottom": 0.09, "top": B1, "thickness": 0.004, "modulus": 60000.0},
    {"bottom": B1, "top": D, "thickness": 0.025, "modulus": 8000.0},
]
GARMENT = {
    "bottom": 0.09,
    "top": 0.77,
    "grid": [32, 48],
    "reduction": 0.16,
    "lengthwise_reduction": 0.15,
    "error_estimate": False,
}


def row_pressure(body: dict, folder: Path) -> tuple[np.ndarray, np.ndarray]:
    """Row heights (m) and row-mean pressures (Pa) of the stocking on ``body``."""
    case = {
        "material": "powernet",
        "body": body,
        "garment": GARMENT,
        "solver": {"method": "newton"},
    }
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "case.yaml").write_text(yaml.safe_dump(case))
    run_case(folder / "case.yaml", folder / "out", {}, ROOT, stop_after="aggregate")
    ds = xr.load_dataset(folder / "out" / "result.nc")
    return ds["z"].values.mean(axis=1), ds["pressure"].values.mean(axis=1)


with tempfile.TemporaryDirectory() as tmp:
    heights, rigid = row_pressure({"leg": {"size": "M"}}, Path(tmp) / "rigid")
    tissue_body = {
        "leg": {"size": "M"},
        "tissue": {"thickness": 0.010, "modulus": 20000.0, "bands": BANDS},
    }
    _, tissue = row_pressure(tissue_body, Path(tmp) / "tissue")
bands = BANDS

if __name__ == "__main__":
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from cloth.results.pressure import MMHG

    fig, ax = plt.subplots(figsize=(5.0, 5.2), layout="constrained")
    ax.plot(rigid / MMHG, heights, "k-", label="rigid leg")
    ax.plot(tissue / MMHG, heights, "r-", label="tissue: 10 mm, 20 kPa")
    colours = ("tab:blue", "tab:green")
    for band, colour in zip(BANDS, colours, strict=True):
        label = f"{band['thickness'] * 1e3:.0f} mm, {band['modulus'] / 1e3:.0f} kPa"
        ax.axhspan(band["bottom"], band["top"], color=colour, alpha=0.12, label=label)
    for point in ("B", "C", "F"):
        ax.axhline(CHART.height[point], color="0.6", lw=0.6)
        ax.text(1.0, CHART.height[point], f" {point}", va="bottom", fontsize=8)
    ax.set_xlabel("row-mean pressure [mmHg]")
    ax.set_ylabel("height [m]")
    ax.set_title("stocking on leg M, reduction 0.16", fontsize=10)
    ax.legend(fontsize=8, loc="upper right")
    fig.savefig(ROOT / "docs" / "leg_tissue.png", dpi=120)
