"""bench.gpu's learning rows: optimisation steps per second of softarm's own networks (the autoencoder, the default
stream LSTM) with its own optimiser, on the GPU and on the CPU's cores; and the whole default pipeline on the GPU.

A step is the training loop's: forward, loss, backward (the stream model's gradient clipped), Adam, on batches of
the real shapes already on the device (the training keeps its data there). Times are taken with the device's queue
drained before and after.
"""

import json
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Callable

import torch
import torch.nn.functional as F

SHAPES = {"autoencoder": (128, 1024), "stream LSTM": (32, 512)}  # frames per batch; streams of 100 samples


def step_of(network: str, size: int, device: torch.device) -> Callable[[], None]:
    """One training step of `network` at batch `size` on `device`, on fixed data of the real shape."""
    from softarm.config import load_config
    from softarm.learn.train_state import adam
    from softarm.model.autoencoder import Autoencoder
    from softarm.registry import latent_model_class

    config = load_config()
    t = config.train
    torch.manual_seed(0)
    if network == "autoencoder":
        net = Autoencoder(config.camera.height, config.camera.width, t.latent).to(device).train()
        x = (torch.rand(size, config.camera.height, config.camera.width, device=device) > 0.85).float()
        loss = lambda: F.binary_cross_entropy_with_logits(net(x), x)  # noqa: E731
    else:
        net = latent_model_class("stream")(5, t.latent, t).to(device).train()
        x = torch.randn(size, t.sequence, 5, device=device)
        y = torch.randn(size, t.sequence, t.latent, device=device)
        loss = lambda: net.trained_loss(net.rnn(x)[0], y)[0]  # noqa: E731
    optimiser = adam(net.parameters(), t.lr_ae)

    def step() -> None:
        value = loss()
        optimiser.zero_grad(set_to_none=True)
        value.backward()
        torch.nn.utils.clip_grad_norm_(net.parameters(), 1.0)
        optimiser.step()
    return step


def steps_per_second(step: Callable[[], None], device: torch.device, steps: int) -> float:
    from softarm.model.device import synchronize

    for _ in range(3):
        step()  # warm up: kernels chosen, memory allocated
    synchronize(device)
    start = time.perf_counter()
    for _ in range(steps):
        step()
    synchronize(device)
    return steps / (time.perf_counter() - start)


def learning_rows(cuda: bool, quick: bool) -> list[dict]:
    devices = [torch.device("cuda")] * cuda + [torch.device("cpu")]
    torch.backends.cudnn.benchmark = True
    rows = []
    for network, sizes in SHAPES.items():
        for size in sizes[:1] if quick else sizes:
            rates = {d.type: steps_per_second(step_of(network, size, d), d, 3 if quick else 20) for d in devices}
            per = "frames" if network == "autoencoder" else "streams x 100 samples"
            rows.append({"section": "learning: optimisation steps per second", "unit": "steps/s",
                         "name": f"{network}, {size} {per}", "gpu": rates.get("cuda"), "cpu": rates["cpu"],
                         "note": f"CPU: {torch.get_num_threads()} threads, fp32"})
    return rows


def pipeline_rows(cuda: bool, quick: bool, suite: bool = False) -> list[dict]:
    """`softarm corpus DIR --arch gpu && softarm train DIR --device cuda` on defaults, in a process of its own; with
    `suite`, the trained model on the held-out suite too (written and scored on the GPU)."""
    if not cuda:
        return [{"section": "pipeline: corpus and training on defaults", "name": "softarm corpus && softarm train",
                 "unit": "s", "note": "needs a CUDA GPU (on CPUs: the benchmarks page's training figures)"}]
    with tempfile.TemporaryDirectory() as folder:
        run = subprocess.run([sys.executable, "-m", "bench.gpu_learning", folder, "quick" if quick else "full",
                              "suite" if suite else "no-suite"], capture_output=True, text=True,
                             cwd=Path(__file__).parents[1])
        if run.returncode != 0:
            tail = run.stderr.strip().splitlines()[-3:]
            return [{"section": "pipeline: corpus and training on defaults", "name": "failed", "unit": "",
                     "note": " / ".join(tail)}]
        found = json.loads(run.stdout.splitlines()[-1])
    rows = [{"section": "pipeline: corpus and training on defaults", "unit": "s", "name": name, "gpu": seconds,
             "note": note} for name, seconds, note in (
        ("softarm corpus DIR --arch gpu", found["corpus_s"], f"{found['frames']:,} frames"),
        ("softarm train DIR --device cuda", found["train_s"],
         f"peak GPU {found['gpu_gb']:.1f} GB, host {found['host_gb']:.1f} GB; validation IoU {found['iou']:.3f}"),
        ("both", found["corpus_s"] + found["train_s"], "goal: 120 s (moonshot 60 s)"))]
    if "suite" in found:
        rows.append({"section": "pipeline: corpus and training on defaults", "unit": "IoU",
                     "gpu": found["suite"]["all"],
                     "name": "the GPU-trained model on the suite, mean of all families",
                     "note": f"motion {found['suite']['motion']:.3f}, world {found['suite']['world']:.3f}; "
                             f"suite written and scored in {found['suite']['seconds']:.0f} s"})
    return rows


def pipeline(folder: Path, quick: bool, suite: bool) -> dict:
    """The default corpus and training on the GPU, timed, with the peak memories (in this child process); with
    `suite`, its scores on the held-out suite."""
    from softarm.config import load_config
    from softarm.corpus.build import write_corpus
    from softarm.learn.training import train
    from softarm.sim.runtime import init_taichi

    init_taichi("gpu")
    start = time.perf_counter()
    write_corpus(folder / "corpus", arch="gpu", **({"arms": 16, "duration": 20.0} if quick else {}))
    corpus_s = time.perf_counter() - start
    overrides = {"train.device": "cuda", **({"train.max_steps_ae": 300, "train.max_steps_lstm": 600} if quick else {})}
    start = time.perf_counter()
    trained = train([folder / "corpus"], load_config(overrides=overrides), folder / "general.pt")
    train_s = time.perf_counter() - start
    validation = (trained.metrics or {}).get("validation", {}).get("model", {})
    found = {"corpus_s": corpus_s, "train_s": train_s, "gpu_gb": torch.cuda.max_memory_allocated() / 1e9,
             "host_gb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 / 1e9,
             "frames": sum(r["frames"] for r in trained.metrics["recordings"]),
             "iou": validation.get("iou", float("nan"))}
    if suite:
        from softarm.suite.build import write_suite
        from softarm.suite.evaluate import evaluate

        start = time.perf_counter()
        write_suite(folder / "suite", arch="gpu")
        scores = evaluate(folder / "general.pt", folder / "suite", device="cuda")
        groups = {group: means["iou"] for group, means in scores["group_means"].items()}
        found["suite"] = {"seconds": time.perf_counter() - start, "all": scores["mean"]["iou"],
                          "motion": groups.get("motion", float("nan")), "world": groups.get("world", float("nan"))}
    return found


if __name__ == "__main__":  # the child process of the pipeline row
    print(json.dumps(pipeline(Path(sys.argv[1]), sys.argv[2] == "quick", sys.argv[3] == "suite")))
