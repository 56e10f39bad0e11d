"""The figure of ``cloth wearers`` (`cloth.stages.wearers`): each girth line's mean pressure
over the wearers of a size, against the case's pressure bands and, at its class point, the
compression classes."""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from cloth.bodies.wearers import SIZE
from cloth.case.judge import Judge
from cloth.io import atomic_output
from cloth.results.pressure import MMHG


def plot_wearers(ds: xr.Dataset, judge: Judge, path: Path) -> Path:
    """wearers.png: per girth line (rows, bottom to top as in ``ds``) a bar from the lowest to
    the highest wearer (mmHg), the centre wearer (dot), the size's body (cross) and each
    wearer's stated error as a whisker on its value; the class bands shaded at the class
    point, the case's bands as dashed lines."""
    names = [str(n) for n in ds["wearer"].values]
    lines = [str(n) for n in ds["landmark"].values]
    p = ds["pressure_mean"].values / MMHG
    e = ds["pressure_mean_error"].values / MMHG
    wearers = [k for k, n in enumerate(names) if n != SIZE]
    fig, ax = plt.subplots(figsize=(7.5, 1.2 + 0.45 * len(lines)))
    for j, line in enumerate(lines):
        values = p[wearers, j]
        if np.isfinite(values).any():
            ax.plot(
                [np.nanmin(values), np.nanmax(values)],
                [j, j],
                color="tab:blue",
                lw=6,
                alpha=0.35,
                solid_capstyle="butt",
            )
            for k in wearers:
                if np.isfinite(p[k, j]) and np.isfinite(e[k, j]):
                    ax.plot([p[k, j] - e[k, j], p[k, j] + e[k, j]], [j, j], color="k", lw=0.8)
        if "centre" in names and np.isfinite(p[names.index("centre"), j]):
            ax.plot(p[names.index("centre"), j], j, "o", color="tab:blue")
        if SIZE in names and np.isfinite(p[names.index(SIZE), j]):
            ax.plot(p[names.index(SIZE), j], j, "x", color="tab:red", ms=8)
        if line == judge.class_point:
            for name, (low, high) in judge.classes.items():
                top = high if math.isfinite(high) else low + 10
                ax.fill_betweenx([j - 0.4, j + 0.4], low, top, alpha=0.12, color="tab:green")
                ax.text(0.5 * (low + top), j + 0.42, name, ha="center", fontsize=7)
    for name, low, high in judge.bands:
        for x in (low, high):
            ax.axvline(x, ls="--", lw=0.8, color="tab:gray")
        ax.text(low, len(lines) - 0.4, name, fontsize=7, color="tab:gray")
    ax.set_yticks(range(len(lines)), lines)
    ax.set_ylim(-0.7, len(lines) - 0.3)
    ax.set_xlabel("mean pressure on the girth line [mmHg]")
    people = int(ds.attrs.get("people", 0))
    who = (
        f"{people} people, {100 * float(ds.attrs.get('coverage', 1)):.0f} % covered"
        if people
        else "the chart's ranges"
    )
    ax.set_title(
        f"size {ds.attrs.get('size')}: {len(wearers)} wearers ({who})\n"
        "bar: lowest to highest wearer, o centre wearer, x the size's body, whiskers: stated error",
        fontsize=9,
    )
    ax.grid(axis="x", alpha=0.3)
    fig.tight_layout()
    with atomic_output(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)
    return path


__all__ = ["plot_wearers"]
