"""Masks of robot-style logs of scenes unlike the default one, against the recording they were made from: the mean
IoU of the imported frames with the native camera frames, for each mask rule asked, all in one run; beside them
the best any mask can score where the camera smears the arm over its exposure (the exposure's mean coverage, at
least half, against the native frame at the image's stamp, the exposure's end).

    python -m bench.segmentation [--seconds 4] [--masks 's>otsu,auto'] [--out FOLDER]

A recording of `--seconds` (seed 0, the defaults) is written as a robot log (`softarm robot-log`) under each scene,
imported with `--roi` alone and each `--mask`, and every imported frame with a camera image is scored against the
native frame at its time. The goal of the import (issue "real robots' logs"): within 0.05 IoU of the native frames.
"""

import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from softarm.model.metrics import iou_per_frame
from softarm.record.reader import read_recording

SCENES = {
    "default (orange arm, blue-green wall)": [],
    "dark arm, light wall": ["--arm-colour", "40,35,45", "--scene-colour", "200,200,190"],
    "pale arm, dark wall": ["--arm-colour", "230,225,200", "--scene-colour", "60,70,80"],
    "lighting drift 0.3": ["--lighting-drift", "0.3"],
    "a swinging second object": ["--distractor"],
    "texture x2": ["--texture", "2"],
    "motion blur 10 ms": ["--motion-blur", "0.01"],
    "motion blur 30 ms, texture x2": ["--motion-blur", "0.03", "--texture", "2"],
    "dark arm, drift, second object": ["--arm-colour", "40,35,45", "--scene-colour", "200,200,190",
                                       "--lighting-drift", "0.3", "--distractor"],
}
IMPORT = ["--camera", "/camera/image_raw/compressed", "--sensors", "/arm/stretch:data", "--roi", "190,30,260,420"]
START = 1_700_000_000.0  # s: the robot log's clock at the recording's t = 0 (RobotLogSettings.start)


def softarm(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", "from softarm_cli.main import main; main()", *args],
                          capture_output=True, text=True)


def native_frames(native_path: Path, imported_path: Path) -> tuple[np.ndarray, np.ndarray, float]:
    """(the imported frames with an image, the native frame indices at their stamps, the native frame period)."""
    native, rec = read_recording(native_path), read_recording(imported_path)
    k = np.rint((rec.model["source"]["found"]["t0"] - START + rec.times) / native.frame_dt).astype(int)
    seen = rec.seen & (k < len(native.times))
    return rec.frames[seen].astype(float), k[seen], native.frame_dt


def mask_iou(native_path: Path, imported_path: Path) -> float:
    frames, k, _ = native_frames(native_path, imported_path)
    return float(iou_per_frame(frames, read_recording(native_path).frames[k]).mean())


def best_possible(native_path: Path, imported_path: Path, options: list[str]) -> str:
    """The smeared exposure's mean coverage (at least half) against the native frame at its end, where the scene
    has motion blur ("" where it has none: a sharp image can match the native frame)."""
    if "--motion-blur" not in options:
        return ""
    native = read_recording(native_path).frames.astype(float)
    _, k, frame_dt = native_frames(native_path, imported_path)
    smear = int(round(float(options[options.index("--motion-blur") + 1]) / frame_dt))
    smeared = np.stack([native[max(0, j - smear):j + 1].mean(axis=0) >= 0.5 for j in k]).astype(float)
    return f"{iou_per_frame(smeared, native[k]).mean():.3f}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=4.0)
    ap.add_argument("--masks", default="s>otsu,auto")
    ap.add_argument("--out", type=Path, default=None, help="keep the logs here [default: a temporary folder]")
    args = ap.parse_args()
    masks = args.masks.split(",")
    with tempfile.TemporaryDirectory() as scratch:
        folder = args.out or Path(scratch)
        folder.mkdir(parents=True, exist_ok=True)
        native = folder / "native.mcap"
        softarm("sim", "--duration", str(args.seconds), "--out", str(native), "--force").check_returncode()
        print(f"| scene | {' | '.join(f'`{m}`' for m in masks)} | best possible |")
        print(f"|---|{'---:|' * (len(masks) + 1)}")
        for k, (scene, options) in enumerate(SCENES.items()):
            log = folder / f"scene{k}.mcap"
            softarm("robot-log", str(native), "--out", str(log), "--force", *options).check_returncode()
            cells = []
            for mask in masks:
                done = softarm("import", str(log), *IMPORT, "--mask", mask, "--out", str(folder / "imported.mcap"),
                               "--force")
                chose = next((line.split("auto chose ")[1].split(" (")[0] for line in done.stdout.splitlines()
                              if "auto chose" in line), None)
                cells.append(f"{mask_iou(native, folder / 'imported.mcap'):.3f}" + (f" ({chose})" if chose else "")
                             if done.returncode == 0 else "refused: " + done.stderr.strip().splitlines()[-1][:60])
            print(f"| {scene} | {' | '.join(cells)} | {best_possible(native, folder / 'imported.mcap', options)} |",
                  flush=True)


if __name__ == "__main__":
    main()
