"""The README's real-robot figure: a model trained on a robot-style bag, imported, against the model trained on
the native recording it was made from, both scored on the last 5 s against the native camera frames.

    softarm robot-log recordings/seed0.mcap --out recordings/seed0_robot.mcap
    softarm import recordings/seed0_robot.mcap --camera /camera/image_raw/compressed --sensors /arm/stretch:data \
        --drive /arm/command:position --roi 190,30,260,420 --out recordings/seed0_imported.mcap
    softarm train recordings/seed0.mcap --out recordings/native.pt
    softarm train recordings/seed0_imported.mcap --out recordings/imported.pt
    python docs/scripts/real_robot_score.py recordings/seed0.mcap recordings/native.pt recordings/seed0_imported.mcap \
        recordings/imported.pt
"""

import sys

import numpy as np

from softarm.imagine.replay_data import compute_replay
from softarm.model.metrics import frame_scores, iou_per_frame
from softarm.record.reader import read_recording

START = 1_700_000_000.0  # s: the ROS time of the native recording's t = 0 in `softarm robot-log`'s bags


def main(native_path: str, native_model: str, imported_path: str, imported_model: str) -> None:
    native = read_recording(native_path, nodes=False)
    own = compute_replay(native_model, native_path, nodes=False)
    last = own.predicted & (native.times >= native.times[-1] - 5.0 + 1e-9)
    replay = compute_replay(imported_model, imported_path, nodes=False)
    rec = replay.recording
    times = rec.model["source"]["found"]["t0"] - START + rec.times   # each imported frame's native time
    k = np.round(times / native.frame_dt).astype(int)
    scored = replay.predicted & rec.seen & (times >= native.times[-1] - 5.0 + 1e-9) & (k < len(native.times))
    imported_iou = iou_per_frame(replay.imagined[scored], native.frames[k[scored]]).mean()
    mask_iou = iou_per_frame(rec.frames[rec.seen].astype(np.float32), native.frames[k[rec.seen]]).mean()
    print(f"last 5 s, against the native camera frames: native model {own.iou[last].mean():.3f} "
          f"({int(last.sum())} frames), imported model {imported_iou:.3f} ({int(scored.sum())} frames), "
          f"difference {own.iou[last].mean() - imported_iou:+.3f}")
    if np.isfinite(rec.pixels_per_metre):  # imported with --scale or --arm-length: tip errors in mm, both models
        mine = frame_scores(own.imagined[last], native.frames[last], native.pixels_per_metre)["tip_mm"].mean()
        theirs = frame_scores(replay.imagined[scored], native.frames[k[scored]], rec.pixels_per_metre)["tip_mm"].mean()
        print(f"tip error, last 5 s, against the native camera frames: native model {mine:.2f} mm, imported model "
              f"{theirs:.2f} mm (its scale {rec.pixels_per_metre:.1f} px/m, the native {native.pixels_per_metre:.1f})")
    print(f"imported model against its own masks, last 5 s: {replay.metrics['imagination_last_5s']['iou']:.3f}; "
          f"the imported masks against the native frames: {mask_iou:.3f}; lag found "
          f"{rec.model['source']['found']['lag'] * 1e3:.1f} ms")


if __name__ == "__main__":
    main(*sys.argv[1:5])
