"""The arithmetic a training runs in: bf16 autocast where the CPU computes bf16 natively, fp32 elsewhere.

`bench/training.py` measured the choice on this project's 2-core machines (AVX-512 BF16): the autoencoder's
step 1.2-1.5x and the stream LSTM's 1.2-1.8x faster under bf16 autocast (between runs), while channels-last
convolutions and `torch.compile` paid back less or nothing. Autocast keeps the weights, the optimiser and the losses in fp32
(PyTorch's autocast lists), so only the matrix products and convolutions of the forward pass round to bf16;
the trained networks answer in fp32 like any other.
"""

import contextlib
from typing import ContextManager

import torch


def cpu_has_bf16() -> bool:
    """Whether oneDNN runs bf16 natively here (AVX-512 BF16 or AMX); elsewhere bf16 is emulated and slower."""
    return bool(torch.backends.mkldnn.is_available() and torch.ops.mkldnn._is_mkldnn_bf16_supported())


def resolved(precision: str) -> str:
    """"auto" as this machine answers it: "bf16" where the CPU has it, "fp32" elsewhere."""
    if precision == "auto":
        return "bf16" if cpu_has_bf16() else "fp32"
    return precision


def forward_precision(precision: str) -> ContextManager:
    """The context a training step's forward pass (and loss) runs in; the backward pass runs outside it."""
    if resolved(precision) == "bf16":
        return torch.autocast("cpu", dtype=torch.bfloat16)
    return contextlib.nullcontext()
