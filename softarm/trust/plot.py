"""The sparsification picture: for each confidence, the mean IoU of the frames kept as the least-trusted are
dropped, beside the oracle that drops the truly worst first and the flat line of dropping at random; the area
between a method and its oracle (AUSE) in the legend."""

from pathlib import Path
from typing import Any, Union

import numpy as np

from softarm.files import atomic_path

COLOURS = ("#1f6fb4", "#d0452f", "#2a9d5c", "#8a5ac2")


def save_sparsification_png(report: dict[str, Any], path: Union[str, Path], fractions: np.ndarray,
                            title: str = "") -> Path:
    """`fractions`: the share of frames dropped at each point of the report's curves (the suite's)."""
    import matplotlib

    matplotlib.use("Agg")  # files only, never a window
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=120)
    for colour, (name, m) in zip(COLOURS, report["methods"].items()):
        ax.plot(fractions * 100, m["sparsification"], color=colour, lw=2,
                label=f"{name}: AUSE {m['ause']:.4f} (calibrated reference {m['reference']['ause']:.4f})")
        ax.plot(fractions * 100, m["oracle"], color="black", lw=1, ls="--",
                label="oracle (drop the truly worst first)" if colour == COLOURS[0] else None)
        ax.axhline(m["sparsification"][0], color="#9a9a9a", lw=1, ls=":",
                   label="random order" if colour == COLOURS[0] else None)
    ax.set_xlabel("least-trusted frames dropped (%)")
    ax.set_ylabel("mean IoU of the frames kept")
    ax.set_title(title or "sparsification of the confidence over the suite", fontsize=9)
    ax.legend(fontsize=7, loc="lower right")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
    plt.close(fig)
    return Path(path)
