"""Runs that cannot fit this machine are refused before any work: memory, disk, open files, frame count.

The estimates come from the config alone, before a body or an output path exists, so a refusal of a
ten-million-arm batch or a 1e-9 s frame step costs milliseconds and leaves nothing behind. Each
refusal says what the run would need, what the machine has, and what would fit.
"""

import resource
import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

from softarm.config import Config
from softarm.errors import ConfigError
from softarm.limits import available_memory
from softarm.record.process import writer_processes
from softarm.sim.capacity import DEVICE_HEADROOM

MAX_FRAMES = 10**9           # frames per arm: 116 days at the default 100 Hz; more is a typo, not a study
WRITER_BYTES_PER_ARM = 4 * 2**20   # a writer's chunk in progress, its joined copy and its compressed copy
SLOTS = 2                    # blocks in flight to the writers (record.process.IN_FLIGHT)
HEADROOM = 0.8               # of the available memory or free disk a run may plan to use
FILE_BYTES = 64 * 1024       # metadata, summary and index of one recording
PIXEL_BYTES_ON_DISK = 0.03   # zstd keeps about 3 % of a binary frame's bytes ...
JSON_BYTES_ON_DISK = 0.4     # ... and 40 % of the JSON; the default run writes 0.86 kB a frame, this says 0.84


BLOCK_BYTES = 256 * 2**20  # memory for one block of positions and images, all arms together
MAX_BLOCK_FRAMES = 500      # 5 s: long enough that Taichi's cost per kernel launch does not show
BLOCK_ARM_FRAMES = 6400     # arm-frames per block: the writers' work left after the last block stays short
MIN_BLOCK_FRAMES = 50


def block_frames_for(config: Config, device_bytes: Optional[int] = None) -> int:
    """Frames per kernel launch: about BLOCK_ARM_FRAMES arm-frames (one arm: MAX_BLOCK_FRAMES), never more than
    fit BLOCK_BYTES for the whole batch, nor, on a GPU with `device_bytes` free, what fits DEVICE_HEADROOM of it
    beside the state. Smaller blocks for big batches keep the writers close behind."""
    nodes, pixels = config.body.rows * config.body.columns, config.camera.height * config.camera.width
    per_frame = config.run.arms * (nodes * 2 * 8 + pixels)
    target = min(MAX_BLOCK_FRAMES, max(MIN_BLOCK_FRAMES, BLOCK_ARM_FRAMES // config.run.arms))
    frames = min(target, config.n_frames, BLOCK_BYTES // per_frame)
    if device_bytes is not None:  # the state (two buffers of positions and velocities) stays; the rest per frame
        device_frame = config.run.arms * (nodes * 2 * 8 + pixels + config.camera.height * 8)
        frames = min(frames, int((device_bytes * DEVICE_HEADROOM - config.run.arms * nodes * 64) // device_frame))
    return max(1, frames)


@dataclass(frozen=True)
class Footprint:
    frames: int        # per arm
    frame_bytes: int   # memory of one frame of one arm in a block: positions, image, row spans, shared copy
    arm_bytes: int     # memory of one arm whatever the block: physics state and its writer
    disk_bytes: int    # estimated size of the whole run's files

    def memory(self, arms: int, block_frames: int) -> int:
        return arms * (self.arm_bytes + block_frames * self.frame_bytes)


def footprint(config: Config) -> Footprint:
    nodes = config.body.rows * config.body.columns
    sensors = len(config.sensors.pairs)
    pixels = config.camera.width * config.camera.height
    json_bytes = nodes * 2 * 14 + sensors * 22 + 80
    # positions (kernel array and the block handed on), image and row spans, the shared slots, and a writer's
    # copies of a block (the 0/255 image, the encoded messages, the joined chunk)
    frame_bytes = (nodes * 2 * 8 * 2 + pixels + config.camera.height * 8) \
        + SLOTS * (pixels + nodes * 16 + sensors * 8 + 8) + 3 * (pixels + json_bytes)
    disk = config.run.arms * (FILE_BYTES
                              + config.n_frames * (PIXEL_BYTES_ON_DISK * pixels + JSON_BYTES_ON_DISK * json_bytes))
    return Footprint(frames=config.n_frames, frame_bytes=frame_bytes,
                     arm_bytes=nodes * 2 * 8 * 3 + WRITER_BYTES_PER_ARM, disk_bytes=int(disk))


def check_resources(config: Config, out_folder: Path) -> None:
    """Refuse a run whose frame count is absurd, or that cannot fit the memory, the disk or the open files."""
    need = footprint(config)
    arms = config.run.arms
    if need.frames > MAX_FRAMES:
        raise ConfigError(f"{need.frames:.3g} frames per arm (run.duration {config.run.duration:g} s at "
                          f"integration.frame_dt {config.integration.frame_dt:g} s) is more than any run needs "
                          f"(at most {MAX_FRAMES:.0e}): check the two keys")
    available = available_memory() * HEADROOM
    block = block_frames_for(config)
    if need.memory(1, 1) > available:
        pixels = config.camera.width * config.camera.height
        fit = available / need.memory(1, 1) * pixels
        raise ConfigError(f"a {config.camera.width} x {config.camera.height} camera needs "
                          f"{gigabytes(need.memory(1, 1))} of memory for one frame of one arm, "
                          f"{gigabytes(available)} are available: make "
                          f"camera.width x camera.height at most about {fit:.3g} pixels")
    if need.memory(arms, block) > available:
        per_arm = need.memory(1, block)
        raise ConfigError(f"{arms} arm(s) with a {config.camera.width} x {config.camera.height} camera need about "
                          f"{gigabytes(need.memory(arms, block))} of memory ({gigabytes(per_arm)} an arm in blocks of "
                          f"{block} frames), {gigabytes(available)} are available: at most {int(available // per_arm)} "
                          f"arm(s) fit")
    free = shutil.disk_usage(existing(out_folder)).free * HEADROOM
    if need.disk_bytes > free:
        seconds = config.run.duration * free / need.disk_bytes
        raise ConfigError(f"the run would write about {gigabytes(need.disk_bytes)} to {existing(out_folder)}, "
                          f"which has {gigabytes(free)} free: at most {seconds:.3g} s of {arms} arm(s) fit")
    _check_open_files(arms)


def _check_open_files(arms: int) -> None:
    """Every arm's file stays open in its writer: raise the limit if it allows, else refuse."""
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    needed = -(-arms // writer_processes(arms)) + 64
    if needed <= soft:
        return
    if hard == resource.RLIM_INFINITY or needed <= hard:
        resource.setrlimit(resource.RLIMIT_NOFILE, (needed, hard))
        return
    raise ConfigError(f"{arms} arms need {needed - 64} files open in each writer, but a process may open {hard}: "
                      f"run at most {(hard - 64) * writer_processes(arms)} arms at a time")


def existing(folder: Path) -> Path:
    """The folder, or its nearest parent that exists (a run creates the rest)."""
    folder = Path(folder).resolve()
    return next(p for p in (folder, *folder.parents) if p.exists())


def gigabytes(n: float) -> str:
    return f"{n / 1e9:.3g} GB" if n >= 1e8 else f"{n / 1e6:.3g} MB"
