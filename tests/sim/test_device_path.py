"""The GPU code path (Taichi device ndarrays, one task per arm) exercised on the CPU backend.

No GPU is needed: `runtime.on_cpu` is patched to say "GPU", so the rasteriser allocates Taichi
ndarrays and copies through `to_numpy`, and both kernels lay one task per arm, exactly as on a GPU;
the results must equal the CPU path's bit for bit.
"""

import numpy as np
import pytest

from softarm.config import load_config
from softarm.sim import runtime
from softarm.sim.batch import arm_batch
from softarm.sim.physics import Simulator
from softarm.sim.raster import Rasteriser

pytestmark = pytest.mark.slow  # each test runs the CLI, trains or compiles kernels: seconds


def run(config, arms: int):
    batch = arm_batch(config, seeds=range(arms))
    sim = Simulator.from_config(config, batch, block_frames=50)
    camera = Rasteriser(config.camera, batch.body.outline, arms, 50)
    positions, images = [], []
    for _ in range(3):
        sim.step_block(50)
        positions.append(sim.history[:, :50].copy())
        images.append(camera.render(sim.history, 50).copy())
    return np.concatenate(positions, 1), np.concatenate(images, 1), camera


def test_device_array_path_equals_the_cpu_path(monkeypatch):
    config = load_config()
    cpu_positions, cpu_images, cpu_camera = run(config, 3)
    assert isinstance(cpu_camera.images, np.ndarray)
    monkeypatch.setattr(runtime, "on_cpu", lambda: False)
    assert runtime.task_layout(3) == (3, 1)
    dev_positions, dev_images, dev_camera = run(config, 3)
    assert not isinstance(dev_camera.images, np.ndarray)
    np.testing.assert_array_equal(dev_positions, cpu_positions)
    np.testing.assert_array_equal(dev_images, cpu_images)


def test_a_recording_made_on_the_gpu_path_is_the_cpu_paths_byte_for_byte(monkeypatch, tmp_path):
    """The whole `simulate` as on a GPU (device arrays, the gathered kernel, the next block stepped while the host
    writes the last one, frames drawn from the device's positions) writes the CPU's files."""
    from softarm.sim.simulate import simulate

    config = load_config(overrides={"run.duration": 12.0, "run.arms": 3, "disturbances": [  # blocks of 500 frames
        {"kind": "push", "start": 0.5, "end": 0.8, "force": [0.05, 0.0], "nodes": [42, 43, 44]}]})
    simulate(config, tmp_path / "cpu.mcap")
    monkeypatch.setattr(runtime, "on_cpu", lambda: False)
    simulate(config, tmp_path / "gpu.mcap")
    for arm in range(3):
        assert (tmp_path / f"gpu_arm{arm}.mcap").read_bytes() == (tmp_path / f"cpu_arm{arm}.mcap").read_bytes()
