"""Success against each varied parameter, as a figure (``cosmos sweep --plot FILE``)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from cosmos.errors import CosmosError
from cosmos.sweep.parameters import PARAMETERS, SEED
from cosmos.sweep.report import success_by_value, wilson_interval


def plot_success(results: Sequence[dict[str, Any]], varied: Sequence[str], path: Path) -> None:
    """Success against each varied parameter, one panel each, written as a PNG.

    Each run is a dot (succeeded at 1, failed at 0); a line joins the success rates of bins
    of equal counts, with their 95 % Wilson intervals.

    Raises:
        CosmosError: Nothing was varied, or the file cannot be written.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = [name for name in varied if name != SEED]
    if not names:
        raise CosmosError("--plot: no parameter was varied (--vary NAME=DIST) to plot success against")
    figure, axes = plt.subplots(len(names), 1, figsize=(7, 2.6 * len(names)), squeeze=False)
    jitter = np.random.default_rng(0).uniform(-0.03, 0.03, len(results))
    for ax, name in zip(axes[:, 0], names, strict=True):
        parameter = PARAMETERS[name]
        scale = parameter.shown_scale
        x = np.array([r["values"][name] * scale for r in results])
        ok = np.array([1.0 if r["ok"] else 0.0 for r in results])
        ax.scatter(x, ok + jitter, s=10, c=np.where(ok > 0, "tab:green", "tab:red"), alpha=0.6, label="runs")
        bins = success_by_value(results, name)
        centres = [(b["low"] + b["high"]) / 2 * scale for b in bins]
        rates = [b["succeeded"] / b["runs"] for b in bins]
        lows, highs = zip(*(wilson_interval(b["succeeded"], b["runs"]) for b in bins), strict=True)
        ax.errorbar(
            centres,
            rates,
            yerr=[np.subtract(rates, lows), np.subtract(highs, rates)],
            fmt="o-",
            color="tab:blue",
            capsize=3,
            label="success rate (95 % interval)",
        )
        unit = f" [{parameter.shown_unit}]" if parameter.shown_unit else ""
        ax.set_xlabel(f"{name}{unit}")
        ax.set_ylabel("success")
        ax.set_ylim(-0.1, 1.1)
        ax.grid(alpha=0.3)
    axes[0, 0].legend(loc="lower left", fontsize=8)
    figure.tight_layout()
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        figure.savefig(path, dpi=100)
    except OSError as error:
        raise CosmosError(f"{path}: cannot write the plot: {error.strerror or error}") from None
    finally:
        plt.close(figure)
