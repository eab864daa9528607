"""The suite's picture: per family, the model's IoU as a bar beside the mean-frame and ridge baselines,
with the AE ceiling as a tick above each group and the privileged node ridge as a dot on the model's bar, so
one glance shows where imagination holds."""

from pathlib import Path
from typing import Any, Union

import numpy as np

from softarm.files import atomic_path

COLOURS = {"model": "#1f6fb4", "ridge": "#f0a030", "mean_frame": "#9a9a9a"}
LABELS = {"model": "model", "ridge": "ridge baseline", "mean_frame": "mean-frame baseline"}


def save_suite_png(evaluation: dict[str, Any], path: Union[str, Path], title: str = "") -> Path:
    """Grouped IoU bars per family (model, ridge, mean frame) and the AE ceiling, written atomically."""
    import matplotlib

    matplotlib.use("Agg")  # files only, never a window
    import matplotlib.pyplot as plt

    families = list(evaluation["families"])
    rows = evaluation["families"]
    x = np.arange(len(families))
    width = 0.27
    fig, ax = plt.subplots(figsize=(1.3 * len(families) + 2.5, 4.2), dpi=120)
    for k, answer in enumerate(("model", "ridge", "mean_frame")):
        values = [rows[f]["iou"] if answer == "model" else rows[f]["baselines"][answer]["iou"] for f in families]
        ax.bar(x + (k - 1) * width, values, width, color=COLOURS[answer], label=LABELS[answer])
    ceiling = [rows[f]["baselines"]["ae_ceiling"]["iou"] for f in families]
    ax.scatter(x, ceiling, marker="_", s=900, color="black", linewidths=2, label="AE ceiling", zorder=3)
    if all("ridge_nodes" in rows[f]["baselines"] for f in families):  # suites scored by softarm-suite/2's evaluate
        nodes = [rows[f]["baselines"]["ridge_nodes"]["iou"] for f in families]
        ax.scatter(x - width, nodes, marker="o", s=18, color="#c0392b", label="node ridge (privileged)", zorder=4)
    ax.set_xticks(x, [f.replace("_", "\n") for f in families], fontsize=8)
    ax.set_ylabel("IoU of imagined frames")
    ax.set_ylim(0, 1.2)
    ax.set_title(title or f"{evaluation['suite']}: {Path(evaluation['checkpoint']).name}", fontsize=10)
    ax.legend(fontsize=8, loc="upper center", ncol=5, frameon=False)
    ax.set_yticks(np.linspace(0, 1, 6))
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    with atomic_path(path) as part:
        fig.savefig(part, format="png")
    plt.close(fig)
    return Path(path)
