"""compare.png of ``cloth compare``: the model against the measured readings.

Left, model against measured with the identity line (error bars: the model's stated error and
the repeats' standard deviation); right, the Bland-Altman plot, the difference model - measured
against their mean, with the bias and the limits of agreement (`cloth.results.agreement`). One
colour per subject. Pressures in Pa in, mmHg on the axes.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from cloth.figures.plots import save_figure
from cloth.results.agreement import Agreement, Compared
from cloth.results.pressure import MMHG


def agreement_figure(table: Compared, path: Path) -> Path:
    """Draw ``table``'s places (module docstring) into ``path``."""
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.8), layout="constrained")
    model, measured = table.model / MMHG, table.measured / MMHG
    names = list(dict.fromkeys(table.subject))
    colours = plt.get_cmap("tab10")
    for k, name in enumerate(names):
        keep = np.array([s == name for s in table.subject])
        style = {"color": colours(k % 10), "fmt": "o", "ms": 5, "capsize": 2, "lw": 0.8}
        label = name or "readings"
        left.errorbar(
            measured[keep],
            model[keep],
            xerr=np.nan_to_num(table.repeat_sd[keep] / MMHG),
            yerr=np.nan_to_num(table.model_error[keep] / MMHG),
            label=label,
            **style,
        )
        mean = 0.5 * (model[keep] + measured[keep])
        right.plot(mean, model[keep] - measured[keep], "o", color=colours(k % 10), ms=5)
    finite = np.concatenate([model[np.isfinite(model)], measured[np.isfinite(measured)]])
    low, high = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    pad = 0.05 * max(high - low, 1.0)
    span = [low - pad, high + pad]
    left.plot(span, span, color="0.3", lw=1, label="model = measured")
    left.set(xlim=span, ylim=span, aspect="equal")
    left.set_xlabel("measured pressure [mmHg]")
    left.set_ylabel("model's probe reading [mmHg]")
    left.legend(loc="upper left", fontsize=8, frameon=False)
    stats = Agreement.of(table.model, table.measured)
    for value, text, style in (
        (stats.bias, "bias", "-"),
        (stats.loa_low, "-1.96 SD", "--"),
        (stats.loa_high, "+1.96 SD", "--"),
    ):
        if np.isfinite(value):
            right.axhline(value / MMHG, color="0.3", ls=style, lw=1)
            right.annotate(
                f"{text} {value / MMHG:.2f}",
                (1.0, value / MMHG),
                xycoords=("axes fraction", "data"),
                xytext=(-4, 3),
                textcoords="offset points",
                ha="right",
                fontsize=8,
            )
    right.axhline(0.0, color="0.7", lw=0.8)
    right.set_xlabel("mean of model and measured [mmHg]")
    right.set_ylabel("model - measured [mmHg]")
    right.set_title(
        f"{stats.n} places: RMSE {stats.rmse / MMHG:.2f} mmHg, r {stats.r:.3f}", fontsize=10
    )
    left.set_title("model against measured", fontsize=10)
    return save_figure(fig, path)
