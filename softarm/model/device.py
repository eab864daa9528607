"""Where torch runs: the device a user names (`train.device`, `--device`), resolved once, and the crossings
between NumPy arrays and the tensors on it.

`auto` takes a CUDA GPU when torch sees one and the CPU otherwise; `cuda` is refused in one line where torch sees
none (a CPU build of torch, or no driver). Every crossing goes through `tensor_on` and `array_of`, which on the
CPU neither copy nor change a bit, so a run on the CPU is the same run whatever the device code around it.
Checkpoints hold CPU tensors only (`on_cpu`), so a model trained on a GPU loads and answers anywhere.
"""

from typing import Any

import numpy as np
import torch

from softarm.config.keys import DEVICES
from softarm.errors import ConfigError


def torch_device(name: str) -> torch.device:
    """The device `name` (auto | cpu | cuda) stands for here."""
    if name not in DEVICES:
        raise ConfigError(f"device {name!r}: give one of {list(DEVICES)}")
    if name == "cpu" or (name == "auto" and not torch.cuda.is_available()):
        return torch.device("cpu")
    if not torch.cuda.is_available():
        build = f"torch {torch.__version__}" + ("" if torch.version.cuda else ", a CPU-only build")
        raise ConfigError(f"device 'cuda': torch sees no CUDA GPU here ({build}); use --device cpu or auto")
    return torch.device("cuda")


def device_of(module: torch.nn.Module) -> torch.device:
    """The device a network's weights live on."""
    return next(module.parameters()).device


def tensor_on(array: np.ndarray, device: torch.device) -> torch.Tensor:
    """A NumPy array as a tensor on `device` (on the CPU: the array's own memory, no copy)."""
    return torch.from_numpy(np.ascontiguousarray(array)).to(device)


def array_of(tensor: torch.Tensor) -> np.ndarray:
    """A tensor's values as a NumPy array on the host (on the CPU: its own memory, no copy)."""
    return tensor.detach().cpu().numpy()


def on_cpu(value: Any) -> Any:
    """`value` (nested dicts, lists and tuples of tensors, arrays, numbers and strings) with every tensor on the CPU
    and every NumPy array a CPU tensor of its dtype: torch reads a tensor back at once where a list of numbers goes
    through its restricted unpickler number by number (0.2 s for the surprise's 86 000 floats)."""
    if isinstance(value, torch.Tensor):
        return value.cpu()
    if isinstance(value, np.ndarray):
        return torch.from_numpy(np.ascontiguousarray(value))
    if isinstance(value, dict):
        return {key: on_cpu(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return type(value)(on_cpu(item) for item in value)
    return value


def synchronize(device: torch.device) -> None:
    """Wait for the device's queued work (a GPU runs ahead of Python): before a clock is read."""
    if device.type == "cuda":
        torch.cuda.synchronize(device)
