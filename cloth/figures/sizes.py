"""sizes.png of ``cloth sizes`` (issue 62): the people and the size boxes, the pressure at the
primary line against the primary measure per size with its band and the confirmations, and
the fabric's tension in each needed size's corridor.

Takes plain arrays (`cloth.stages.sizetables` builds them): lengths in m and pressures in Pa
in, cm and mmHg on the axes.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from numpy.typing import NDArray

from cloth.io import atomic_output
from cloth.results.pressure import MMHG


@dataclass(frozen=True)
class SizeBox:
    """A size as drawn: ``name``, its ranges (measure -> (low, high), m), its pressure at the
    primary line against the girth there (``pressure``: (G,) m -> (G,) Pa) and its
    confirmations at the primary line (girth m, pressure Pa, error Pa)."""

    name: str
    ranges: dict[str, tuple[float, float]]
    pressure: Callable[[NDArray[np.float64]], NDArray[np.float64]]
    confirmed: Sequence[tuple[float, float, float]]


@dataclass(frozen=True)
class Corridor:
    """A needed size's corridor: its strain window (1), floor and roof (N m-1) along it."""

    strain: NDArray[np.float64]
    floor: NDArray[np.float64]
    roof: NDArray[np.float64]


def plot_sizes(
    measures: tuple[str, ...],
    values: dict[str, NDArray[np.float64]],
    fits: NDArray[np.bool_],
    boxes: Sequence[SizeBox],
    band: tuple[float, float],
    corridors: Sequence[Corridor],
    tension: Callable[[NDArray[np.float64]], NDArray[np.float64]],
    path: Path,
) -> Path:
    """Three panels into ``path``: ``values`` (measure -> (P,) m) of the people the chart was
    designed for, ``fits`` (P,) whether each fits her size; the ``boxes``; the primary line's
    ``band`` (Pa); the needed ``corridors`` and the fabric's ``tension`` (strain -> N m-1)."""
    primary = measures[0]
    fig, axes = plt.subplots(1, 3, figsize=(16, 5.2), layout="constrained")
    ax = axes[0]
    x = 100 * values[primary]
    y = 100 * values[measures[1]] if len(measures) > 1 else np.random.default_rng(0).random(len(x))
    ax.scatter(x[~fits], y[~fits], s=4, c="0.6", label="made to measure")
    ax.scatter(x[fits], y[fits], s=4, c="tab:green", label="fits a size")
    for box in boxes:
        lo, hi = (100 * v for v in box.ranges[primary])
        if len(measures) > 1 and measures[1] in box.ranges:
            blo, bhi = (100 * v for v in box.ranges[measures[1]])
        else:
            blo, bhi = float(np.min(y)), float(np.max(y))
        ax.add_patch(plt.Rectangle((lo, blo), hi - lo, bhi - blo, fill=False, lw=1.2))
        ax.annotate(box.name, (lo, bhi), fontsize=7, va="bottom")
    ax.set_xlabel(f"{primary} girth [cm]")
    ax.set_ylabel(f"{measures[1]} girth [cm]" if len(measures) > 1 else "(people spread)")
    ax.set_title("the people and the sizes")
    ax.legend(loc="upper left", fontsize=8, markerscale=3, frameon=True)
    ax = axes[1]
    ax.axhspan(band[0] / MMHG, band[1] / MMHG, color="tab:blue", alpha=0.12, label="band")
    for box in boxes:
        lo, hi = box.ranges[primary]
        g = np.linspace(lo, hi, 40)
        ax.plot(100 * g, box.pressure(g) / MMHG, lw=1.5)
        for girth, p, err in box.confirmed:
            ax.errorbar(
                100 * girth, p / MMHG, yerr=err / MMHG if np.isfinite(err) else None, fmt="ko", ms=3
            )
    ax.set_xlabel(f"{primary} girth [cm]")
    ax.set_ylabel(f"mean pressure at {primary} [mmHg]")
    ax.set_title("fast model per size (lines), equilibria (dots)")
    ax.legend(loc="lower right", fontsize=8)
    ax = axes[2]
    top = 0.0
    for k, c in enumerate(corridors):
        ax.fill_between(c.strain, c.floor, c.roof, alpha=0.25, label=f"R{k + 1}")
        top = max(top, float(np.max(c.strain)))
    e = np.linspace(0.0, 1.2 * top if top > 0 else 1.0, 200)
    ax.plot(e, tension(e), "k-", lw=1.5, label="the fabric")
    ax.set_xlabel("weft strain [1]")
    ax.set_ylabel("weft tension [N/m]")
    ax.set_title("needed corridors and the fabric")
    ax.legend(loc="upper left", fontsize=7, ncols=2)
    with atomic_output(path) as tmp:
        fig.savefig(tmp, format="png", dpi=110)
    plt.close(fig)
    return path


__all__ = ["Corridor", "SizeBox", "plot_sizes"]
