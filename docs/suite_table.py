"""Print an evaluation JSON (`softarm evaluate ... --json FILE`) as the README's Markdown table.

    python docs/suite_table.py recordings/paper_suite.json
"""

import json
import sys


def number(value: float | None, digits: int) -> str:
    """A score as the table shows it; null (NaN in the evaluation) as a dash."""
    return "–" if value is None else f"{value:.{digits}f}"


def main(path: str) -> None:
    evaluation = json.load(open(path))
    print("| family | frames | IoU | BCE | tip (mm) | skill | mean-frame IoU | ridge IoU (skill) | AE ceiling IoU |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name, row in evaluation["families"].items():
        b = row["baselines"]
        print(f"| {name} | {row['frames']} | **{number(row['iou'], 3)}** | {number(row['bce'], 4)} | "
              f"{number(row['tip_error_mm'], 1)} | {number(row['skill'], 2)} | {number(b['mean_frame']['iou'], 3)} | "
              f"{number(b['ridge']['iou'], 3)} ({number(b['ridge']['skill'], 2)}) | {number(b['ae_ceiling']['iou'], 3)} |")
    m = evaluation["mean"]
    print(f"| **mean of families** | | **{number(m['iou'], 3)}** | {number(m['bce'], 4)} | "
          f"{number(m['tip_error_mm'], 1)} | {number(m['skill'], 2)} | | | |")


if __name__ == "__main__":
    main(sys.argv[1])
