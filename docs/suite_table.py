"""Print an evaluation JSON (`softarm evaluate ... --json FILE`) as the README's Markdown table.

    python docs/suite_table.py recordings/paper_suite.json
"""

import json
import sys


def main(path: str) -> None:
    evaluation = json.load(open(path))
    print("| family | frames | IoU | BCE | tip (mm) | skill | mean-frame IoU | ridge IoU (skill) | AE ceiling IoU |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name, row in evaluation["families"].items():
        b = row["baselines"]
        print(f"| {name} | {row['frames']} | **{row['iou']:.3f}** | {row['bce']:.4f} | {row['tip_error_mm']:.1f} | "
              f"{row['skill']:.2f} | {b['mean_frame']['iou']:.3f} | {b['ridge']['iou']:.3f} ({b['ridge']['skill']:.2f}) | "
              f"{b['ae_ceiling']['iou']:.3f} |")
    m = evaluation["mean"]
    print(f"| **mean of families** | | **{m['iou']:.3f}** | {m['bce']:.4f} | {m['tip_error_mm']:.1f} | {m['skill']:.2f} | | | |")


if __name__ == "__main__":
    main(sys.argv[1])
