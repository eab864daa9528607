"""What a block of arms asks of the device, refused in one line before Taichi is asked for it.

Taichi indexes an array with 32-bit integers, so no array of a block may hold 2^31 values or more; and on a GPU the
block's arrays (the state, the positions and the camera's images of every frame) must fit the device's free memory.
Asked for more, Taichi 1.7 does not raise: the process dies in its C++ runtime. The limits are checked when a
simulator or a rasteriser is made, and `frames_that_fit` tells `softarm sim` how long a block the device allows.
"""

import subprocess
from typing import Optional

import numpy as np

from softarm.errors import SimulationError

MAX_INDEX = 2**31 - 1     # values an array may hold under Taichi's 32-bit indices
DEVICE_HEADROOM = 0.8     # of the GPU's free memory a block may plan to use


def check_block(arms: int, frames: int, values_per_frame: int, what: str) -> None:
    """Refuse an array of arms x frames x values_per_frame values that Taichi cannot index."""
    values = arms * frames * values_per_frame
    if values > MAX_INDEX:
        fit = max(0, MAX_INDEX // (arms * values_per_frame))
        advice = f"blocks of at most {fit} frame(s)" if fit else f"at most {MAX_INDEX // values_per_frame} arms"
        raise SimulationError(f"{what} of {arms} arms x {frames} frames holds {values:.3g} values, more than Taichi "
                              f"can index (2^31): use {advice}")


def check_device_memory(needed: int, free: int, arms: int, what: str) -> None:
    """Refuse a block whose device arrays (`needed` bytes) exceed DEVICE_HEADROOM of the GPU's `free` memory."""
    if needed > free * DEVICE_HEADROOM:
        raise SimulationError(f"{what} of {arms} arms needs {needed / 1e9:.3g} GB on the GPU, which has "
                              f"{free / 1e9:.3g} GB free: run fewer arms or shorter blocks")


def gpu_free_memory() -> int:
    """Bytes free on the CUDA device now (asked through torch, which softarm has anyway)."""
    import torch

    return int(torch.cuda.mem_get_info()[0])


def gpu_free_memory_of_driver() -> Optional[int]:
    """Bytes free on the first GPU as `nvidia-smi` reports them, without starting CUDA in this process (which
    must not hold CUDA when it forks its writers); None where there is no such tool or GPU."""
    try:
        run = subprocess.run(["nvidia-smi", "--query-gpu=memory.free", "--format=csv,noheader,nounits"],
                             capture_output=True, text=True, timeout=10)
        return int(run.stdout.split()[0]) * 2**20 if run.returncode == 0 and run.stdout.strip() else None
    except (OSError, ValueError, subprocess.TimeoutExpired):
        return None


def check_physics(arms: int, nodes: int, block_frames: int, on_gpu: bool) -> None:
    """A simulator's block: its positions indexable, and on a GPU its state (two buffers of positions and
    velocities) and positions within the device's free memory."""
    check_block(arms, block_frames, nodes * 2, "a block of node positions")
    if on_gpu:
        check_device_memory(arms * nodes * 2 * 8 * (4 + block_frames), gpu_free_memory(), arms, "the physics")


def check_camera(arms: int, block_frames: int, height: int, width: int, on_gpu: bool) -> None:
    """A rasteriser's block: its images indexable, and on a GPU they and each row's span of markers within the
    device's free memory."""
    check_block(arms, block_frames, height * width, "a block of camera frames")
    if on_gpu:
        check_device_memory(arms * block_frames * height * (width + 8), gpu_free_memory(), arms, "the camera")


def raise_on_blowup(status: np.ndarray, arms: int, frame_dt: float, blowup_distance: float, substeps: int) -> None:
    """SimulationError naming the first blow-up of a block's status (arms, 2): (frame, node) of each arm's first,
    (-1, -1) where none."""
    bad = np.flatnonzero(status[:, 0] >= 0)
    if len(bad) == 0:
        return
    arm = bad[np.argmin(status[bad, 0])]
    frame, node = status[arm]
    where = f" (arm {arm})" if arms > 1 else ""
    raise SimulationError(
        f"the simulation blew up at t = {frame * frame_dt:.6g} s{where}: node {node} went further than "
        f"integration.blowup_distance = {blowup_distance} m from rest (or became NaN); "
        f"raise integration.substeps (now {substeps}) or lower excitation.amplitude")
