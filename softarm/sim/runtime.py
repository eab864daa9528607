"""Taichi start-up: called once, at the edge (CLI or a notebook), never on import."""

import contextlib
import io
from typing import Union

import numpy as np
import taichi as ti

from softarm.errors import SoftarmError
from softarm.sim import check_arch

_started: list[str] = []


def init_taichi(arch: str = "cpu", debug: bool = False) -> str:
    """Start Taichi on `arch` (cpu | gpu | auto) with float64 and the offline kernel cache.

    Returns the backend in use ("x64", "cuda", ...). `auto` takes a GPU when there is one; `gpu`
    refuses to fall back to the CPU silently. A second call with the same arch does nothing.
    """
    check_arch(arch)
    if _started:
        if _started[0] != arch:
            raise SoftarmError(f"Taichi is already running with arch {_started[0]!r}; restart to use {arch!r}")
        return backend_name()
    # CUDA, not ti.gpu: Taichi 1.7's probe of the other GPU backends can crash the process on a machine
    # without them, while a missing CUDA is a clean RuntimeError.
    try:
        _start(ti.cpu if arch == "cpu" else ti.cuda, debug)
    except RuntimeError as e:
        if arch == "gpu":
            raise SoftarmError(f"--arch gpu: no CUDA GPU is available here ({e}); use --arch cpu or auto") from None
        _start(ti.cpu, debug)  # auto: fall back to the CPU
    _started.append(arch)
    return backend_name()


def ensure_taichi() -> str:
    """Taichi as it runs, or on the CPU where nothing started it yet (work that renders a few frames for a
    score, not a simulation the user placed on a device)."""
    return backend_name() if _started else init_taichi("cpu")


def _start(backend: object, debug: bool) -> None:
    with contextlib.redirect_stdout(io.StringIO()):  # ti.init prints "Starting on arch=..." itself
        ti.init(arch=backend, default_fp=ti.f64, offline_cache=True, debug=debug, log_level=ti.ERROR,
                enable_fallback=False)


def backend_name() -> str:
    return str(ti.lang.impl.current_cfg().arch).rsplit(".", 1)[-1]


def on_cpu() -> bool:
    return ti.lang.impl.current_cfg().arch in (ti.x64, ti.arm64)


def device_array(shape: tuple[int, ...], dtype: str) -> Union[np.ndarray, ti.Ndarray]:
    """A kernel argument array: plain NumPy on the CPU (kernels work on it in place, no copies), device memory on
    a GPU."""
    if on_cpu():
        return np.zeros(shape, dtype)
    return ti.ndarray({"float64": ti.f64, "int32": ti.i32, "uint8": ti.u8}[dtype], shape)


def upload(array: np.ndarray) -> Union[np.ndarray, ti.Ndarray]:
    """A device copy of `array` (on the CPU: a contiguous NumPy copy)."""
    array = np.ascontiguousarray(array)
    out = device_array(array.shape, array.dtype.name)
    if isinstance(out, np.ndarray):
        out[...] = array
    else:
        out.from_numpy(array)
    return out


def host(array: Union[np.ndarray, ti.Ndarray]) -> np.ndarray:
    """The array as NumPy: itself on the CPU, a copy from the GPU."""
    return array if isinstance(array, np.ndarray) else array.to_numpy()


CPU_TASK_SPACING = 512  # Taichi 1.7 gives each CPU thread at least 512 iterations of a parallel range-for


def task_layout(items: int) -> tuple[int, int]:
    """(tasks, spacing) so that `for slot in range(tasks * spacing)` with work at every spacing-th slot
    runs one task per thread.

    Taichi's CPU backend hands each thread a block of at least 512 consecutive iterations, so a loop
    over 64 arms would run on one thread; spacing the tasks 512 iterations apart puts one task on
    each thread. On a GPU every arm is its own thread (spacing 1).
    """
    if on_cpu():
        return min(items, ti.lang.impl.current_cfg().cpu_max_num_threads), CPU_TASK_SPACING
    return items, 1


MAX_LANES = 4  # arms a CPU thread steps side by side: one 256-bit register of float64 per coordinate


def lane_layout(arms: int, plain: bool) -> tuple[int, int]:
    """(lanes, groups): the simulator steps `groups` groups of `lanes` arms, lanes side by side (vectorised).

    On a CPU, for a plain batch, the most lanes (a power of two up to MAX_LANES) that divide the arms and still
    leave a group for every thread; otherwise, and on a GPU (every arm its own thread), one lane.
    """
    lanes = MAX_LANES if on_cpu() and plain else 1
    threads = ti.lang.impl.current_cfg().cpu_max_num_threads
    while lanes > 1 and (arms % lanes or arms // lanes < threads):
        lanes //= 2
    return lanes, arms // lanes
