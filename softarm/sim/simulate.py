"""`simulate`: a batch of arms from config to recordings (physics -> camera -> sensors -> MCAP), block by block."""

import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Callable, Optional, Sequence, Union

import numpy as np

from softarm.arm.sensors import stretch
from softarm.config import Config
from softarm.errors import RecordingError, SimulationError
from softarm.files import check_outputs, claimed, made_folders
from softarm.interrupt import Escalated, stop_on_signal
from softarm.record.kept import describe_kept
from softarm.record.process import RecorderProcess, WriterFailed
from softarm.record.slots import BlockShape
from softarm.record.writer import ArmMetadata
from softarm.sim import check_arch
from softarm.sim.batch import ArmBatch, arm_batch
from softarm.sim.budget import block_frames_for, check_resources
from softarm.sim.capacity import gpu_free_memory_of_driver

if TYPE_CHECKING:
    from softarm.sim.physics import Simulator
    from softarm.sim.raster import Rasteriser

DEFAULT_FOLDER = Path("recordings")


class Laps:
    """Wall time per stage of the loop, so a user (and the benchmark) sees which stage is the slowest."""

    def __init__(self) -> None:
        self.seconds: dict[str, float] = {}
        self._last = time.perf_counter()

    def lap(self, stage: str) -> None:
        now = time.perf_counter()
        self.seconds[stage] = self.seconds.get(stage, 0.0) + now - self._last
        self._last = now


@dataclass(frozen=True)
class SimResult:
    paths: list[Path]
    frames: int           # frames written to each file
    complete: bool        # False when the run was interrupted
    wall_seconds: float
    simulated_seconds: float
    stage_seconds: dict[str, float]  # wall time of setup, physics, camera, sensors, recording

    @property
    def bytes(self) -> int:
        return sum(p.stat().st_size for p in self.paths)

    @property
    def real_time_factor(self) -> float:
        """Simulated seconds per wall-clock second, over all arms."""
        return len(self.paths) * self.simulated_seconds / self.wall_seconds


def output_paths(config: Config, out: Union[str, Path, None] = None) -> list[Path]:
    """One file per arm: `out` itself for one arm, `<stem>_arm<i>.mcap` for a batch; default recordings/seed<s>.mcap."""
    seeds = [config.run.seed + i for i in range(config.run.arms)]
    if out is None:
        return [DEFAULT_FOLDER / f"seed{s}.mcap" for s in seeds]
    out = Path(out)
    if config.run.arms == 1:
        return [out]
    return [out.with_name(f"{out.stem}_arm{i}{out.suffix or '.mcap'}") for i in range(config.run.arms)]


def simulate(config: Config, out: Union[str, Path, None] = None, force: bool = False, arch: str = "cpu",
             progress: Optional[Callable[[int], None]] = None, inputs: Sequence[Union[str, Path]] = ()) -> SimResult:
    """Run config.run.arms arms for config.run.duration seconds and record each to its MCAP file.

    `progress(frames_done)` is called after every block. Ctrl-C stops at the next block boundary and
    closes every file with complete = "false". A blow-up removes every file of the run; any other failure
    keeps every frame that reached the disk and says where. Taichi starts on `arch` at the first call
    (cpu | gpu | auto). `inputs` (the config file, say) are files no output may replace; another run
    writing one of the outputs is refused.
    """
    start = time.perf_counter()
    check_arch(arch)
    check_resources(config, DEFAULT_FOLDER if out is None else Path(out).parent)  # before any array is made
    batch = arm_batch(config)  # config errors first: a refused run creates no folder
    paths = output_paths(config, out)
    check_outputs(paths, force, inputs)
    with stop_on_signal(), made_folders(paths), claimed(paths):  # a request from now on ends the run cleanly
        return record_batch(config, batch, paths, arch, progress, start)


def record_batch(config: Config, batch: ArmBatch, paths: list[Path], arch: str,
                 progress: Optional[Callable[[int], None]], start: float) -> SimResult:
    """Simulate and record a batch whose outputs are checked and held."""
    from softarm.sim.physics import Simulator  # Taichi loads here, not when softarm is imported
    from softarm.sim.raster import Rasteriser
    from softarm.sim.runtime import init_taichi

    laps = Laps()
    # On a GPU the block also fits the device: its free memory asked of the driver (no CUDA in this process yet: the
    # writers fork first).
    block_frames = block_frames_for(config, gpu_free_memory_of_driver() if arch == "gpu" else None)
    # The writers fork before Taichi starts its threads: a child never inherits a lock held by one of them.
    recorder = start_recorder(config, batch, paths, block_frames)
    try:
        init_taichi(arch)
        sim = Simulator.from_config(config, batch, block_frames)
    except BaseException:
        recorder.discard()
        raise
    try:
        camera = Rasteriser(config.camera, batch.body.outline, batch.arms, block_frames)
        laps.lap("setup")
        done, complete = record_blocks(config, batch, sim, camera, recorder, laps, progress)
    except SimulationError:  # a blow-up leaves nothing behind
        recorder.discard()
        raise
    except WriterFailed as failure:  # everything that reached the disk stays, and the message says where
        recorder.keep()
        raise WriterFailed(f"recording stopped: {failure}; {describe_kept(paths)}") from None
    except Escalated:  # a second stop request: now, with what is on disk
        recorder.abandon()
        raise Escalated(f"stopped at once by a second stop request; {describe_kept(paths)}") from None
    except Exception as error:  # anything else cut the run short: keep the frames, say where they are
        recorder.keep()
        raise RecordingError(f"recording stopped by {type(error).__name__}: {error}; {describe_kept(paths)}") from error
    except BaseException:
        recorder.keep()
        raise
    finally:
        sim.close()
    return SimResult(paths=paths, frames=done, complete=complete, wall_seconds=time.perf_counter() - start,
                     simulated_seconds=done * config.integration.frame_dt, stage_seconds=laps.seconds)


def start_recorder(config: Config, batch: ArmBatch, paths: list[Path], block_frames: int) -> RecorderProcess:
    """The writer processes of a run, each file opened with its arm's model metadata."""
    body, metadata = batch.body, ArmMetadata(config, batch.body)
    specs = [(path, metadata(drive, seed, p0, v0, world), config.integration.frame_dt)
             for path, drive, seed, p0, v0, world in zip(paths, batch.drives, batch.seeds, batch.positions,
                                                         batch.velocities, batch.disturbances)]
    return RecorderProcess(specs, BlockShape(batch.arms, block_frames, config.camera.height, config.camera.width,
                                             len(body.sensors), body.n_nodes))


def record_blocks(config: Config, batch: ArmBatch, sim: "Simulator", camera: "Rasteriser", recorder: RecorderProcess,
                  laps: Laps, progress: Optional[Callable[[int], None]]) -> tuple[int, bool]:
    """Step, photograph, sense and record block after block; (frames done, whether the run completed).

    Ctrl-C (or SIGTERM) stops at the next block boundary and closes the files with what they hold.
    """
    body, frame_dt, block_frames = batch.body, config.integration.frame_dt, sim.block_frames
    from softarm.sim import runtime  # Taichi is running by now

    overlap = not runtime.on_cpu()  # a GPU's block is a host copy: the next block may run while this one is written
    done, n = 0, min(block_frames, config.n_frames)
    with stop_on_signal() as caught:
        sim.launch(n)
        while not caught:
            images = camera.render(sim.device_positions, n)  # drawn where the kernel wrote the positions
            laps.lap("camera")
            positions = sim.collect()[:, :n]
            laps.lap("physics")
            after = min(block_frames, config.n_frames - done - n)
            if overlap and after:
                sim.launch(after)
            readings = stretch(positions, body.rest, body.sensors)
            times = np.arange(done, done + n) * frame_dt
            displacements = np.stack([d.displacement(times) for d in batch.drives])
            laps.lap("sensors")
            recorder.write(images, readings, positions, displacements)
            laps.lap("recording (queue)")
            done += n
            if progress:
                progress(done)
            if not after:
                break
            n = after
            if not overlap and not caught:
                sim.launch(n)
        complete = not caught
        recorder.close(complete)  # inside: a Ctrl-C during the final flush must not discard the files
    laps.lap("recording (rest, after the physics)")
    return done, complete
