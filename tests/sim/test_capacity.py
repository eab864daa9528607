"""A block that Taichi could not index, or a GPU could not hold, is refused in one SimulationError before any of it
is allocated (Taichi 1.7 would end the process in its C++ runtime instead)."""

import numpy as np
import pytest

from softarm.config import load_config
from softarm.errors import SimulationError
from softarm.sim import capacity, physics, raster
from softarm.sim.batch import arm_batch
from softarm.sim.physics import Simulator
from softarm.sim.raster import Rasteriser


def test_a_block_of_more_values_than_taichi_indexes_is_refused_with_what_fits():
    config = load_config()
    one = arm_batch(config, seeds=[0])
    arms = 20_000  # x 1000 frames x 57 nodes x 2 = 2.3e9 values > 2^31
    with pytest.raises(SimulationError, match=r"more than Taichi can index \(2\^31\): use blocks of at most 941 frame"):
        Simulator(one.body, one.drives * arms, 0.01, 30, 0.5, one.positions[0], one.velocities[0], block_frames=1000)
    with pytest.raises(SimulationError, match="camera frames"):
        Rasteriser(config.camera, one.body.outline, arms, 100)


def test_a_block_larger_than_the_gpus_free_memory_is_refused(monkeypatch):
    config = load_config()
    batch = arm_batch(config, seeds=range(4))
    for module in (physics, raster):
        monkeypatch.setattr(module, "on_cpu", lambda: False)  # as on a GPU ...
    monkeypatch.setattr(capacity, "gpu_free_memory", lambda: 10**5)  # ... with 100 kB free
    with pytest.raises(SimulationError, match=r"the physics of 4 arms needs .* on the GPU, which has 0.0001 GB free"):
        Simulator.from_config(config, batch, block_frames=100)
    with pytest.raises(SimulationError, match="the camera"):
        Rasteriser(config.camera, batch.body.outline, 4, 100)


def test_the_limits_themselves():
    capacity.check_block(2**10, 2**10, 2**11 - 1, "x")  # just under 2^31 values
    with pytest.raises(SimulationError, match="at most"):
        capacity.check_block(2**10, 2**10, 2**11, "x")
    capacity.check_device_memory(8 * 10**8, 10**9, 1, "x")
    with pytest.raises(SimulationError):
        capacity.check_device_memory(int(8.1 * 10**8), 10**9, 1, "x")
    assert np.isfinite(capacity.DEVICE_HEADROOM)


def test_the_block_shrinks_to_fit_the_gpus_free_memory():
    from softarm.sim.budget import block_frames_for

    config = load_config(overrides={"run.arms": 64, "run.duration": 10.0})
    host = block_frames_for(config)
    assert block_frames_for(config, device_bytes=10**12) == host  # a big GPU: the host's block
    per_frame = 64 * (57 * 16 + 84 * 52 + 84 * 8)
    small = block_frames_for(config, device_bytes=int((64 * 57 * 64 + 10 * per_frame) / capacity.DEVICE_HEADROOM))
    assert small == 10 < host
