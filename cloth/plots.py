"""Figures (matplotlib, Agg backend: no display needed, safe in workers)."""

from __future__ import annotations

import logging
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from cloth.io import atomic_output
from cloth.materials import DIRECTIONS

log = logging.getLogger(__name__)

COLOURS = {"weft": "tab:blue", "warp": "tab:orange", "bias": "tab:green"}


def _save(fig: plt.Figure, path: str | Path) -> Path:
    path = Path(path)
    with atomic_output(path) as tmp:
        fig.savefig(tmp, format=path.suffix.lstrip(".") or "png", dpi=150)
    plt.close(fig)
    log.info("wrote %s", path)
    return path


def plot_material(ds: xr.Dataset, path: str | Path) -> Path:
    """Measured points and fitted piecewise-linear curves of every direction (stress in kPa)."""
    fig, ax = plt.subplots(figsize=(6.4, 4.4), layout="constrained")
    for direction in DIRECTIONS:
        if f"{direction}_knot_strain" not in ds:
            continue
        colour = COLOURS[direction]
        if f"{direction}_point_strain" in ds:
            ax.plot(
                100 * ds[f"{direction}_point_strain"].values,
                ds[f"{direction}_point_stress"].values / 1e3,
                ".",
                ms=2,
                alpha=0.35,
                color=colour,
                label=f"{direction} measured",
            )
        knots_x = ds[f"{direction}_knot_strain"].values
        knots_y = ds[f"{direction}_knot_stress"].values
        label = f"{direction} curve ({knots_x.size} knots)"
        if f"{direction}_fit_max_error_percent" in ds:
            label += f", max error {float(ds[f'{direction}_fit_max_error_percent']):.2g} %"
        ax.plot(100 * knots_x, knots_y / 1e3, "-o", ms=4, color=colour, label=label)
    ax.set_xlabel("strain [%]")
    ax.set_ylabel("stress [kPa]")
    ax.set_title(f"{ds.attrs.get('fabric_name', 'fabric')}: lab data and fitted curves")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=min(0.0, float(np.nanmin(ax.get_ylim()))))
    return _save(fig, path)
