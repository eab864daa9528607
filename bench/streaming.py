"""Online imagination latency: one `StreamingImaginer.step` per stretch sample on one CPU core, decoded
frame included, against the robot's 10 ms sample period and the 1 ms goal; beside it, the per-frame
cost of a batch replay measured in the same run.

    python -m bench.streaming [--checkpoint CKPT] [--samples N]

Without a checkpoint it times every latent model of the registry at its default size (latent 16, 128
hidden units; the window model over 6 samples, the stream models one sample at a time) with fresh
weights: latency does not depend on what the weights learned.
"""

import argparse
import time

import numpy as np
import torch

from softarm.config import load_config, override
from softarm.imagine.imaginer import Imaginer
from softarm.imagine.stream import StreamingImaginer
from softarm.imagine.trained import TrainedModel
from softarm.model.autoencoder import Autoencoder
from softarm.model.inputs import Inputs, channels
from softarm.model.scaler import Scaler
from softarm.registry import LATENT_MODELS, latent_model_class

PERIOD_MS = 10.0  # the default frame step: 100 samples a second
GOAL_MS = 1.0


def default_imaginer(model: str) -> Imaginer:
    """Fresh networks of the default sizes, identity scalers: what a checkpoint of `model` costs to run."""
    config = override(load_config(), {"train.model": model})
    t, sensors = config.train, len(config.sensors.pairs)
    torch.manual_seed(0)
    ae = Autoencoder(config.camera.height, config.camera.width, t.latent).eval()
    latent = latent_model_class(model)(sensors, t.latent, t).eval()
    ae.to(memory_format=torch.channels_last)
    identity = lambda n: Scaler(keep=np.ones(n, bool), mean=np.zeros(n), std=np.ones(n))  # noqa: E731
    return Imaginer(ae, latent, identity(t.latent), Inputs(channels(), (identity(sensors),)))


def measure(imaginer: Imaginer, samples: int) -> tuple[np.ndarray, float]:
    """Per-sample streaming latencies (ms, after the first window) and the per-frame cost of a batch replay (ms)."""
    signals = np.random.default_rng(0).normal(0, 1e-3, (samples, imaginer.inputs.features))
    stream = StreamingImaginer(imaginer)
    for sample in signals[:50]:  # warm up
        stream.step(sample)
    stream.reset()
    latencies = []
    for sample in signals:
        start = time.perf_counter()
        stream.step(sample)
        latencies.append(time.perf_counter() - start)
    start = time.perf_counter()
    imaginer.imagine(signals)
    history = imaginer.latent.history
    batch_ms = (time.perf_counter() - start) * 1e3 / (len(signals) - history)
    return np.array(latencies[history:]) * 1e3, batch_ms


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--checkpoint", default=None)
    ap.add_argument("--samples", type=int, default=2000)
    args = ap.parse_args()
    torch.set_num_threads(1)  # one core, as a robot's control loop gets
    imaginers = ({"checkpoint": TrainedModel(args.checkpoint).imaginer} if args.checkpoint
                 else {model: default_imaginer(model) for model in LATENT_MODELS})
    print(f"torch {torch.__version__}, 1 thread, {args.samples} samples")
    print("| online imagination, one sample | median ms | 99th percentile ms | median against the 1 ms goal "
          "| share of the 10 ms period | batch replay, ms per frame |\n|---|---:|---:|---:|---:|---:|")
    for name, imaginer in imaginers.items():
        steady, batch_ms = measure(imaginer, args.samples)
        median, p99 = np.median(steady), np.percentile(steady, 99)
        print(f"| {name} model ({imaginer.latent.settings.model}) | {median:.3f} | {p99:.3f} | {median / GOAL_MS:.2f}x "
              f"| {median / PERIOD_MS:.1%} | {batch_ms:.3f} |")


if __name__ == "__main__":
    main()
