"""The arithmetic a training step runs in: fp32, or bf16 autocast.

Which is faster depends on the chip, not on its flags, so `train.precision = "auto"` is settled by measuring
both at the start of a run (`softarm.learn.step_times.fastest_precision`) and the checkpoint keeps the choice.
`bench/training.py` measured: bf16 autocast 1.2x faster for both networks on an AMD EPYC with AVX-512 BF16,
and on an Intel Xeon with the same flags (no AMX) no faster for the autoencoder (0.99x) and slower for the
stream LSTM (0.68x). Autocast keeps the weights, the optimiser and the losses in fp32 (PyTorch's autocast
lists), so only the matrix products and convolutions of the forward pass round to bf16; the trained networks
answer in fp32 like any other.
"""

import contextlib
from typing import ContextManager

import torch

from softarm.errors import ConfigError


def cpu_has_bf16() -> bool:
    """Whether oneDNN runs bf16 natively here (AVX-512 BF16 or AMX); elsewhere bf16 is emulated and slower."""
    return bool(torch.backends.mkldnn.is_available() and torch.ops.mkldnn._is_mkldnn_bf16_supported())


def has_bf16(device: torch.device) -> bool:
    """Whether `device` runs bf16 natively: the CPU's oneDNN as above, a GPU from Ampere on."""
    if device.type == "cuda":
        return bool(torch.cuda.is_bf16_supported())
    return cpu_has_bf16()


def require_native(precision: str, device: torch.device) -> None:
    """Refuse bf16 on a chip that only emulates it, before any step: emulated bf16 runs slower than fp32, and
    oneDNN has no LSTM primitive for it (torch 2.13 raises at the latent phase's first step, after the whole
    autoencoder phase)."""
    if precision == "bf16" and not has_bf16(device):
        chip = "this CPU" if device.type == "cpu" else f"the GPU {device}"
        raise ConfigError(f"train.precision = \"bf16\" needs a chip that runs bf16 natively (a CPU with AVX-512 BF16 "
                          f"or AMX, a GPU from Ampere on), and {chip} does not: set train.precision to \"auto\" or "
                          f"\"fp32\"")


def forward_precision(precision: str, device: str = "cpu") -> ContextManager:
    """The context a training step's forward pass (and loss) runs in on a `device` of that type ("cpu", "cuda"),
    for "fp32" or "bf16" ("auto" is settled before training starts); the backward pass runs outside it."""
    if precision == "bf16":
        return torch.autocast(device, dtype=torch.bfloat16)
    if precision == "fp32":
        return contextlib.nullcontext()
    raise ValueError(f"precision {precision!r}: settle 'auto' with step_times.fastest_precision first")
