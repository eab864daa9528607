"""A study's picture: IoU (top) and tip error (bottom) against the studied variable, one panel per group of
trials (a sensor placement, a kind of imperfection), one thin line per suite family, the mean of the
families in black, and the mean-frame and ridge baselines (means of the families) dashed."""

from pathlib import Path
from typing import Union

import numpy as np

from softarm.files import atomic_path
from softarm.study.ledger import TrialRecord
from softarm.study.plan import Study, format_value

METRICS = (("iou", "IoU of imagined frames"), ("tip_error_mm", "tip error (mm)"))
LEGEND_INCHES = 1.9
BASELINES = {"mean_frame": ("mean-frame baseline", "#9a9a9a", (0, (5, 3))),
             "ridge": ("ridge baseline", "#f0a030", (0, (2, 2)))}


def save_study_png(study: Study, scale: str, records: list[TrialRecord], path: Union[str, Path]) -> Path:
    """The figure, written atomically; trials not (or not well) finished leave gaps in their lines."""
    import matplotlib

    matplotlib.use("Agg")  # files only, never a window
    import matplotlib.pyplot as plt

    groups = list(dict.fromkeys(r.group for r in records))
    members = [[r for r in records if r.group == g] for g in groups]
    families = next((list(r.scores["families"]) for r in records if r.status == "ok"), [])
    colours = plt.get_cmap("tab10")
    slots = [max(len(m), 2) for m in members]
    width = max(8.0, 1.2 + 1.1 * sum(slots) + LEGEND_INCHES)
    fig, axes = plt.subplots(2, len(groups), figsize=(width, 6.4), dpi=120, sharey="row", squeeze=False,
                             gridspec_kw={"width_ratios": slots})
    for column, (group, rows) in enumerate(zip(groups, members)):
        x = np.arange(len(rows))
        for row, (metric, label) in enumerate(METRICS):
            ax = axes[row, column]
            for k, family in enumerate(families):
                ax.plot(x, [_score(r, metric, family) for r in rows], "o-", ms=3, lw=1, color=colours(k % 10),
                        alpha=0.8, label=family)
            ax.plot(x, [_score(r, metric) for r in rows], "o-", ms=5, lw=2.5, color="black", label="mean of families")
            for answer, (name, colour, dashes) in BASELINES.items():
                ax.plot(x, [_baseline(r, metric, answer) for r in rows], marker="_", ms=14, lw=1.5, color=colour,
                        linestyle=dashes, label=name)  # the tick shows a trial alone in its group
            ax.set_xticks(x, [format_value(r.value) for r in rows], fontsize=8)
            ax.set_xlim(-0.4, len(rows) - 0.6)
            ax.grid(alpha=0.3)
            if column == 0:
                ax.set_ylabel(label)
            if row == 0:
                ax.set_title(group or study.name, fontsize=10)
            else:
                ax.set_xlabel(study.variable, fontsize=9)
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="center right", fontsize=8, frameon=False)
    fig.suptitle(f"study {study.name} ({scale}): {study.description}", fontsize=11)
    fig.tight_layout(rect=(0, 0, 1 - LEGEND_INCHES / width, 1))
    with atomic_path(path) as part:
        fig.savefig(part, format="png")
    plt.close(fig)
    return Path(path)


def _score(record: TrialRecord, metric: str, family: str = "") -> float:
    """The model's score in a family (or the mean of the families); NaN for a trial without scores."""
    if record.status != "ok":
        return float("nan")
    return record.scores["families"][family][metric] if family else record.scores["mean"][metric]


def _baseline(record: TrialRecord, metric: str, answer: str) -> float:
    if record.status != "ok":
        return float("nan")
    return float(np.mean([row["baselines"][answer][metric] for row in record.scores["families"].values()]))
