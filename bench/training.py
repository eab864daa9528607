"""Training throughput: optimisation steps per second of the autoencoder and of the latent model at the default
settings, for each way of running them on this CPU, as ratios to the fp32 path with softarm's fused Adam measured
in the same run ("unfused Adam" is the optimiser of the releases before it).

    python -m bench.training [--steps N] [--repeats R] [--variants fp32 channels_last bf16 ...]

Each variant trains a fresh network of the default size on frames and inputs of the real shapes (the step's cost
does not depend on what the frames show) for `--steps` steps after a warm-up, the variants taking turns; the
table gives the median step time over `--repeats` turns, steps/s and samples/s, and the ratio to fp32.
"""

import argparse
import contextlib
import statistics
import time
from typing import Callable, Iterable

import numpy as np
import torch
import torch.nn.functional as F

from softarm.config import load_config
from softarm.learn.precision import cpu_has_bf16
from softarm.learn.train_state import adam
from softarm.model.autoencoder import Autoencoder
from softarm.registry import latent_model_class

CONFIG = load_config()
T = CONFIG.train


def frames(batch: int) -> torch.Tensor:
    rng = np.random.default_rng(0)
    return torch.from_numpy((rng.random((batch, CONFIG.camera.height, CONFIG.camera.width)) > 0.85).astype(np.uint8))


def optimiser_of(parameters: Iterable[torch.nn.Parameter], lr: float, fused: bool) -> torch.optim.Optimizer:
    return adam(parameters, lr) if fused else torch.optim.Adam(parameters, lr=lr)


def autoencoder_step(memory_format: torch.memory_format, autocast: bool, compiled: bool,
                     fused: bool = True) -> Callable[[], None]:
    """One step of the autoencoder's training loop (Adam, BCE on logits), as `softarm.learn.loop` takes it."""
    torch.manual_seed(0)
    net = Autoencoder(CONFIG.camera.height, CONFIG.camera.width, T.latent).to(memory_format=memory_format).train()
    optimiser = optimiser_of(net.parameters(), T.lr_ae, fused)
    forward = torch.compile(net) if compiled else net
    batch = frames(T.batch_ae).float()

    def step() -> None:
        with torch.autocast("cpu", dtype=torch.bfloat16) if autocast else contextlib.nullcontext():
            logits = forward(batch)
        loss = F.binary_cross_entropy_with_logits(logits.float(), batch)
        optimiser.zero_grad(set_to_none=True)
        loss.backward()
        optimiser.step()
    return step


def latent_step(autocast: bool, compiled: bool, fused: bool = True) -> Callable[[], None]:
    """One chunk step of the default latent model: `streams` stretches of `sequence` samples."""
    torch.manual_seed(0)
    model = latent_model_class(T.model)(5, T.latent, T).train()
    optimiser = optimiser_of(model.parameters(), T.lr_lstm, fused)
    forward = torch.compile(model) if compiled else model
    x, y = torch.randn(T.streams, T.sequence, 5), torch.randn(T.streams, T.sequence, T.latent)

    def step() -> None:
        with torch.autocast("cpu", dtype=torch.bfloat16) if autocast else contextlib.nullcontext():
            mean, log_error, _ = forward(x)
        loss = F.mse_loss(mean.float(), y) + log_error.float().mean()
        optimiser.zero_grad(set_to_none=True)
        loss.backward()
        torch.nn.utils.clip_grad_norm_(model.parameters(), 1.0)
        optimiser.step()
    return step


VARIANTS: dict[str, tuple[Callable[[], Callable[[], None]], Callable[[], Callable[[], None]]]] = {
    "fp32": (lambda: autoencoder_step(torch.contiguous_format, False, False), lambda: latent_step(False, False)),
    "fp32, unfused Adam": (lambda: autoencoder_step(torch.contiguous_format, False, False, fused=False),
                           lambda: latent_step(False, False, fused=False)),
    "channels_last": (lambda: autoencoder_step(torch.channels_last, False, False), lambda: latent_step(False, False)),
    "bf16": (lambda: autoencoder_step(torch.contiguous_format, True, False), lambda: latent_step(True, False)),
    "bf16 + channels_last": (lambda: autoencoder_step(torch.channels_last, True, False),
                             lambda: latent_step(True, False)),
    "compiled": (lambda: autoencoder_step(torch.contiguous_format, False, True), lambda: latent_step(False, True)),
}


def seconds_per_step(steps: dict[str, Callable[[], None]], count: int, repeats: int) -> dict[str, float]:
    """Median seconds per step of each variant; the variants take turns within every repeat, so a shared
    machine's drift falls on all of them alike."""
    for step in steps.values():
        for _ in range(3):  # warm up (and compile)
            step()
    times: dict[str, list[float]] = {name: [] for name in steps}
    for _ in range(repeats):
        for name, step in steps.items():
            start = time.perf_counter()
            for _ in range(count):
                step()
            times[name].append((time.perf_counter() - start) / count)
    return {name: statistics.median(values) for name, values in times.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--steps", type=int, default=10, help="steps per timing")
    ap.add_argument("--repeats", type=int, default=5, help="timings per variant, taken in turns")
    ap.add_argument("--variants", nargs="+", default=list(VARIANTS), choices=list(VARIANTS))
    args = ap.parse_args()
    names = ["fp32", *[v for v in args.variants if v != "fp32"]]
    print(f"torch {torch.__version__}, {torch.get_num_threads()} threads, native bf16 on this CPU: {cpu_has_bf16()} "
          f"(train.precision = {T.precision!r}: 'auto' times both at the start of a training and takes bf16 only "
          f"where it runs each network's step at least 5 % faster)")
    ae = seconds_per_step({name: VARIANTS[name][0]() for name in names}, args.steps, args.repeats)
    latent = seconds_per_step({name: VARIANTS[name][1]() for name in names}, args.steps, args.repeats)
    print("| variant | AE steps/s | AE frames/s | AE ratio | latent steps/s | latent samples/s | latent ratio |\n"
          "|---|---:|---:|---:|---:|---:|---:|")
    for name in names:
        print(f"| {name} | {1 / ae[name]:.2f} | {T.batch_ae / ae[name]:,.0f} | {ae['fp32'] / ae[name]:.2f}x "
              f"| {1 / latent[name]:.2f} | {T.streams * T.sequence / latent[name]:,.0f} "
              f"| {latent['fp32'] / latent[name]:.2f}x |")


if __name__ == "__main__":
    main()
