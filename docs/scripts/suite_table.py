"""Print an evaluation JSON (`softarm evaluate ... --json FILE`) as the results pages' Markdown table.

    python docs/scripts/suite_table.py recordings/paper_suite.json
"""

import json
import sys


def number(value: float | None, digits: int) -> str:
    """A score as the table shows it; null (NaN in the evaluation) as a dash."""
    return "–" if value is None else f"{value:.{digits}f}"


def tip(row: dict) -> str:
    """Mean tip error, and the median where the evaluation has it (older ones do not)."""
    median = row.get("tip_error_median_mm")
    return number(row["tip_error_mm"], 1) + ("" if median is None else f" / {number(median, 1)}")


def main(path: str) -> None:
    evaluation = json.load(open(path))
    print("| family | frames | IoU | BCE | tip mean / median (mm) | skill | mean-frame IoU | ridge IoU (skill) | "
          "node ridge IoU | AE ceiling IoU |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name, row in evaluation["families"].items():
        b = row["baselines"]
        nodes = number(b["ridge_nodes"]["iou"], 3) if "ridge_nodes" in b else "–"
        print(f"| {name} | {row['frames']} | **{number(row['iou'], 3)}** | {number(row['bce'], 4)} | "
              f"{tip(row)} | {number(row['skill'], 2)} | {number(b['mean_frame']['iou'], 3)} | "
              f"{number(b['ridge']['iou'], 3)} ({number(b['ridge']['skill'], 2)}) | {nodes} | "
              f"{number(b['ae_ceiling']['iou'], 3)} |")
    means = [(f"mean of {group} families", m) for group, m in evaluation.get("group_means", {}).items()]
    for label, m in [*means, ("mean of all families", evaluation["mean"])]:
        print(f"| **{label}** | | **{number(m['iou'], 3)}** | {number(m['bce'], 4)} | "
              f"{tip(m)} | {number(m['skill'], 2)} | | | | |")
    if "confidence" in evaluation:
        c = evaluation["confidence"]
        chosen = c["methods"][c["default"]] if "methods" in c else c  # older evaluations held one confidence
        print(f"\nConfidence over {chosen['frames']} frames: Spearman correlation with IoU "
              f"{number(chosen['spearman'], 2)}; IoU of the {c['least_trusted_share']:.0%} least-trusted frames "
              f"{number(chosen['least_trusted_iou'], 3)}, of the rest {number(chosen['rest_iou'], 3)}.")


if __name__ == "__main__":
    main(sys.argv[1])
