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

#: A person's place, as drawn: label and colour.
KINDS = (
    ("fits her size", "tab:green"),
    ("below a band in her size", "tab:blue"),
    ("above a band in her size", "tab:red"),
    ("in no size (made to measure)", "0.6"),
)


@dataclass(frozen=True)
class SizeBox:
    """A size as drawn: ``name``, its ranges (measure -> (low, high), m), the fast model's
    lowest and highest pressure at the primary line against the girth there over the people's
    central shape terms (``pressure``: (G,) m -> (2, G) Pa) and its confirmations at the
    primary line (girth m, pressure Pa, error Pa)."""

    name: str
    ranges: dict[str, tuple[float, float]]
    pressure: Callable[[NDArray[np.float64]], NDArray[np.float64]]
    confirmed: Sequence[tuple[float, float, float]]


@dataclass(frozen=True)
class Corridor:
    """A needed size's corridor where the fabric is cut: its strain window (1), floor and roof
    (N m-1) along it, and whether the fabric holds it."""

    strain: NDArray[np.float64]
    floor: NDArray[np.float64]
    roof: NDArray[np.float64]
    holds: bool = True


def plot_sizes(
    measures: tuple[str, ...],
    values: dict[str, NDArray[np.float64]],
    kind: NDArray[np.intp],
    boxes: Sequence[SizeBox],
    band: tuple[float, float],
    corridors: Sequence[Corridor],
    tension: Callable[[NDArray[np.float64]], NDArray[np.float64]],
    path: Path,
) -> Path:
    """Three panels into ``path``: ``values`` (measure -> (P,) m) of the people the chart was
    designed for, ``kind`` (P,) each one's place (an index of `KINDS`: in every band of her
    size, below a band, above one, in no size); the ``boxes``; the primary line's ``band``
    (Pa); the needed ``corridors``, each where the fabric is cut for its size, and the
    fabric's ``tension`` (strain -> N m-1)."""
    primary = measures[0]
    fig, axes = plt.subplots(1, 3, figsize=(16, 5.2), layout="constrained")
    ax = axes[0]
    x = 100 * values[primary]
    groups = [(kind == k) for k in range(len(KINDS))]
    if len(measures) > 1:
        y = 100 * values[measures[1]]
        for (label, colour), chosen in zip(KINDS, groups, strict=True):
            ax.scatter(x[chosen], y[chosen], s=4, c=colour, label=label)
        for box in boxes:
            lo, hi = (100 * v for v in box.ranges[primary])
            blo, bhi = (100 * v for v in box.ranges.get(measures[1], (np.nan, np.nan)))
            ax.add_patch(plt.Rectangle((lo, blo), hi - lo, bhi - blo, fill=False, lw=1.0))
        ax.set_ylabel(f"{measures[1]} girth [cm]")
    else:
        bins = np.linspace(np.min(x), np.max(x), 60)
        ax.hist(
            [x[chosen] for chosen in groups],
            bins=bins,
            stacked=True,
            color=[colour for _, colour in KINDS],
            label=[label for label, _ in KINDS],
        )
        for box in boxes:
            for edge in box.ranges[primary]:
                ax.axvline(100 * edge, color="k", lw=0.6)
        ax.set_ylabel("people")
    ax.set_xlabel(f"{primary} girth [cm]")
    ax.set_title(f"the people and the sizes ({100 * np.mean(kind == 0):.0f} % fit)")
    ax.legend(loc="upper right", fontsize=8, markerscale=3)
    ax = axes[1]
    ax.axhspan(band[0] / MMHG, band[1] / MMHG, color="tab:blue", alpha=0.10, label="band")
    for k, box in enumerate(boxes):
        lo, hi = box.ranges[primary]
        g = np.linspace(lo, hi, 40)
        low, high = box.pressure(g) / MMHG
        colour = f"C{k % 10}"
        ax.fill_between(100 * g, low, high, color=colour, alpha=0.35, lw=0)
        for n, (girth, p, err) in enumerate(box.confirmed):
            ax.errorbar(
                100 * girth,
                p / MMHG,
                yerr=err / MMHG if np.isfinite(err) else None,
                fmt="o",
                color=colour,
                mec="k",
                ms=4,
                label="equilibria" if k == 0 and n == 0 else None,
            )
    ax.set_xlabel(f"{primary} girth [cm]")
    ax.set_ylabel(f"mean pressure at {primary} [mmHg]")
    ax.set_title("fast model over the people's shapes (shaded), equilibria (dots)")
    ax.legend(loc="lower right", fontsize=8)
    ax = axes[2]
    top = 0.0
    for k, c in enumerate(corridors):
        verdict = "holds" if c.holds else "does not hold"
        ax.fill_between(c.strain, c.floor, c.roof, alpha=0.5, label=f"R{k + 1} ({verdict})")
        top = max(top, float(np.max(c.strain)))
    e = np.linspace(1e-3, 1.2 * top if top > 0 else 1.0, 300)
    ax.plot(e, tension(e), "k-", lw=1.5, label="the fabric")
    ax.set_yscale("log")
    if corridors:  # the corridors' own range: the fabric's curve where it meets them
        floor = min(float(np.min(c.floor)) for c in corridors)
        roof = max(float(np.max(c.roof)) for c in corridors)
        if 0 < floor < roof:
            ax.set_ylim(0.5 * floor, 2.0 * roof)
    ax.set_xlabel("weft strain [1]")
    ax.set_ylabel("weft tension [N/m]")
    ax.set_title("each size's corridor where the fabric is cut for it")
    ax.legend(loc="lower right", fontsize=7, ncols=2)
    with atomic_output(path) as tmp:
        fig.savefig(tmp, format="png", dpi=110)
    plt.close(fig)
    return path


__all__ = ["KINDS", "Corridor", "SizeBox", "plot_sizes"]
