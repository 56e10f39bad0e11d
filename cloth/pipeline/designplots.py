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

#: Panels per row of design.png (a stocking's seven points wrap onto two rows).
PANELS_PER_ROW = 4
#: Line styles of a sweep's variants (lengthwise reduction, tissue, ...), in the order of their
#: combinations; a body's colour is the same in every panel.
VARIANT_STYLES = ("-", "--", ":", "-.")
VARIANT_MARKERS = ("o", "s", "^", "D")


def plot_design(ds: xr.Dataset, targets: list[dict], path: str | Path) -> Path:
    """Landmark pressure against reduction, one panel per girth line (`PANELS_PER_ROW` to a
    row): one line per fabric, body and variant (a colour per fabric and body, a line style
    per variant, e.g. the lengthwise reduction), each with its stated errors as bars; the
    class bands in the panel of the class point where the sweep's lines include it
    (`class_bands`); the targets dashed black. The legend sits below the panels, over no data."""
    landmarks = ds["landmark"].values.tolist()
    columns = min(PANELS_PER_ROW, len(landmarks))
    rows = -(-len(landmarks) // columns)
    fig, axes = plt.subplots(
        rows,
        columns,
        figsize=(3.4 * columns, 3.2 * rows + 0.9),
        sharey=True,
        layout="constrained",
        squeeze=False,
    )
    bands = class_bands(ds)
    point = judge_of(ds).class_point
    percent = 100 * ds["reduction"].values
    variants = combinations(ds, variant_dims(ds))
    bodies = combinations(ds, ("material", "body"))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for ax, landmark in zip(axes.flat, landmarks, strict=False):
        for name, lo, hi in bands if landmark == point else []:
            ax.axhspan(lo, hi, color="tab:red", alpha=0.08, gid="class-band")
            ax.text(percent.min(), (lo + hi) / 2, f" class {name}", fontsize=7, va="center")
        for k, where in enumerate(bodies):
            for j, variant in enumerate(variants):
                at = where | variant | {"landmark": landmark}
                line = ds["pressure_mean"].sel(at).values / MMHG
                bars = mean_error(ds).sel(at).values / MMHG
                names = [where["material"]] if ds.sizes["material"] > 1 else []
                label = ", ".join(
                    [*map(str, names), str(where["body"]), Variant.of(variant).label()]
                ).strip(", ")
                ax.errorbar(
                    percent,
                    line,
                    yerr=np.nan_to_num(bars),
                    fmt=VARIANT_MARKERS[j % len(VARIANT_MARKERS)],
                    ls=VARIANT_STYLES[j % len(VARIANT_STYLES)],
                    color=colours[k % len(colours)],
                    ms=4,
                    capsize=2,
                    label=label,
                )
        for target in targets:
            if target["landmark"] == landmark:
                ax.axhline(target_pa(target) / MMHG, color="k", ls="--", lw=0.8, label="target")
        ax.set_title(landmark)
        ax.set_xlabel("pattern reduction [%]")
        ax.grid(alpha=0.3)
    for ax in axes.flat[len(landmarks) :]:
        ax.set_visible(False)
    for ax in axes[:, 0]:
        ax.set_ylabel("mean pressure [mmHg]")
    handles: dict[str, object] = {}
    for ax in axes.flat[: len(landmarks)]:
        for handle, label in zip(*ax.get_legend_handles_labels(), strict=True):
            handles.setdefault(label, handle)
    if "target" in handles:
        handles["target"] = handles.pop("target")  # after the lines
    fig.legend(
        list(handles.values()),
        list(handles.keys()),
        loc="outside lower center",
        ncol=min(len(handles), 3),
        fontsize=8,
        frameon=False,
    )
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
