"""The Python API end to end: simulate an arm, read its recording, train a model on it, replay it with the camera
off for the last two seconds, then imagine it again online, one sample at a time, as a robot's loop would.

    python examples/python_api.py                      # 30 s of arm, the default training (a few minutes)
    python examples/python_api.py --seconds 6 --quick  # a smoke test: a tiny training, seconds
"""

import argparse
from pathlib import Path

import numpy as np

import softarm

QUICK = {"train.epochs_ae": 2, "train.epochs_lstm": 2, "train.max_steps_ae": 20, "train.max_steps_lstm": 20,
         "train.latent": 8, "train.lstm_hidden": 32, "train.precision": "fp32"}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--folder", type=Path, default=Path("recordings/example_api"), help="where the files go")
    parser.add_argument("--seconds", type=float, default=30.0, help="seconds of arm to simulate")
    parser.add_argument("--quick", action="store_true", help="a tiny training schedule (a smoke test)")
    args = parser.parse_args()

    config = softarm.load_config(overrides={"run.duration": args.seconds, **(QUICK if args.quick else {})})
    recording_path, checkpoint = args.folder / "arm.mcap", args.folder / "arm.pt"

    simulated = softarm.simulate(config, recording_path, force=True)
    print(f"simulated {simulated.frames} frames in {simulated.wall_seconds:.1f} s")
    recording = softarm.read_recording(recording_path)
    print(f"read {recording.frames.shape[0]} camera frames {recording.frames.shape[1:]} and the stretch of "
          f"{recording.stretch.shape[1]} sensors")

    trained = softarm.train([recording_path], config, out=checkpoint, force=True)
    last = trained.metrics["imagination"]  # its held-out last 5 %, the model beside its baselines
    print(f"trained in {trained.wall_seconds:.0f} s: imagination IoU {last['model']['iou']:.3f} (ridge "
          f"{last['ridge']['iou']:.3f}, mean frame {last['mean_frame']['iou']:.3f}, AE ceiling "
          f"{last['ae_ceiling']['iou']:.3f})")

    blind = f"{args.seconds - 2:g}:{args.seconds:g}"  # the camera off for the last two seconds
    replayed = softarm.replay(checkpoint, recording_path, blind=[blind], png=args.folder / "replay.png", force=True)
    print(f"replayed with the camera off over {blind} s: IoU {replayed.metrics['imagination_blind']['iou']:.3f}")

    stream = softarm.StreamingImaginer.from_checkpoint(checkpoint)
    confidences = []
    for stretch in recording.stretch:  # one sample every 10 ms, as a robot would read it
        frame = stream.step(stretch=stretch)
        if frame is not None:
            confidences.append(frame.confidence)
    print(f"streamed {len(confidences)} imagined frames online, median confidence {np.median(confidences):.2f}")


if __name__ == "__main__":
    main()
