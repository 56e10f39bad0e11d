"""The design figures: a sweep's girth-line pressure against the reduction with the design's
targets (``design.png``, `plot_design`), and a graded design's profile against its targets
(``design_profile.png``, `plot_profile_design`)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from cloth.figures.plots import class_bands, judge_of, plt, save_figure
from cloth.pipeline.sweep import combinations, mean_error, target_pa, variant_dims
from cloth.pipeline.variants import Variant
from cloth.results.pressure import MMHG


def plot_design(ds: xr.Dataset, targets: list[dict], path: str | Path) -> Path:
    """Landmark pressure against reduction per fabric and body, with the class bands in the
    panel of the class point where the sweep's lines include it (`class_bands`); a
    sweep with variants draws each line at every key's first value and shades the spread that
    each varied key causes (`cloth.pipeline.variants`)."""
    landmarks = ds["landmark"].values.tolist()
    fig, axes = plt.subplots(
        1,
        len(landmarks),
        figsize=(3.6 * len(landmarks), 3.8),
        sharey=True,
        layout="constrained",
        squeeze=False,
    )
    bands = class_bands(ds)
    point = judge_of(ds).class_point
    for ax, landmark in zip(axes[0], landmarks, strict=True):
        for name, lo, hi in bands if landmark == point else []:
            ax.axhspan(lo, hi, color="tab:red", alpha=0.08, gid="class-band")
            ax.text(
                ds["reduction"].values.min(),
                (lo + hi) / 2,
                f" class {name}",
                fontsize=7,
                va="center",
            )
        percent = 100 * ds["reduction"].values
        variants = variant_dims(ds)
        first = {dim: ds[dim].values[0] for dim in variants}  # the line: each key's first value
        for where in combinations(ds, ("material", "body")):
            line = ds["pressure_mean"].sel(where | first | {"landmark": landmark}) / MMHG
            label = ", ".join(
                [str(v) for v in where.values()]
                + [Variant.of({d: v for d, v in first.items()}).label()]
            ).strip(", ")
            bars = mean_error(ds).sel(where | first | {"landmark": landmark}).values / MMHG
            drawn = ax.errorbar(
                percent, line.values, yerr=np.nan_to_num(bars), fmt="o-", capsize=2, label=label
            ).lines[0]
            for hatch, dim in zip(("", "//", ".."), variants, strict=False):
                if ds.sizes[dim] < 2:
                    continue  # the spread each varied key causes, the others at their first
                others = {d: v for d, v in first.items() if d != dim}
                spread = ds["pressure_mean"].sel(where | others | {"landmark": landmark}) / MMHG
                ax.fill_between(
                    percent,
                    spread.min(dim).values,
                    spread.max(dim).values,
                    color=drawn.get_color(),
                    alpha=0.15,
                    hatch=hatch,
                    label=f"{label}: spread over {dim.replace('_', ' ')}",
                )
        for target in targets:
            if target["landmark"] == landmark:
                ax.axhline(target_pa(target) / MMHG, color="k", ls="--", lw=0.8, label="target")
        ax.set_title(landmark)
        ax.set_xlabel("pattern reduction [%]")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("mean pressure on the girth line [mmHg]")
    axes[0][-1].legend(fontsize=7)
    return save_figure(fig, path)


def plot_profile_design(rows: list[dict[str, object]], path: Path) -> Path:
    """Per girth line (by height): the target, the uniform answer and the confirmed graded one
    with its estimated error, mmHg."""
    height = np.array([row["height_m"] for row in rows], dtype=float)
    fig, ax = plt.subplots(figsize=(5.5, 4.2), layout="constrained")
    ax.plot([row["target_mmHg"] for row in rows], height, "k*", ms=11, label="target")
    if "uniform_mmHg" in rows[0]:
        ax.plot(
            [row["uniform_mmHg"] for row in rows],
            height,
            "s--",
            color="tab:gray",
            label=f"uniform reduction {float(rows[0]['uniform_reduction']):.3f}",
        )
    error = np.array([row["confirmed_error_mmHg"] for row in rows], dtype=float)
    ax.errorbar(
        [row["confirmed_mmHg"] for row in rows],
        height,
        xerr=np.where(np.isfinite(error), error, 0.0),
        fmt="o-",
        color="tab:red",
        capsize=3,
        label="graded pattern (confirmed)",
    )
    for row, z in zip(rows, height, strict=True):
        ax.annotate(
            str(row["landmark"]),
            (float(row["target_mmHg"]), z),
            xytext=(6, 4),
            textcoords="offset points",
            fontsize=8,
        )
    ax.set_xlabel("mean pressure on the girth line [mmHg]")
    ax.set_ylabel("height [m]")
    ax.set_title("graded pattern to a pressure profile", fontsize=10)
    ax.legend(fontsize=8)
    return save_figure(fig, path)
