"""The recorder's encoder: one arm's frames written to a file by the C encoder against the Python encoder
(the same bytes, checked here too), in the same run. Part of `python -m bench.run`."""

import tempfile
import time
from pathlib import Path

import numpy as np

from softarm.arm.sensors import stretch
from softarm.record import frames
from softarm.record.writer import RecordingWriter, model_metadata
from softarm.sim.batch import arm_batch
from softarm.sim.budget import MAX_BLOCK_FRAMES
from softarm.sim.physics import Simulator
from softarm.sim.raster import Rasteriser


def encoder_rows(config, quick: bool) -> list[dict]:
    """µs per arm-frame of `RecordingWriter.write` + close (encoding, chunking, zstd, CRC, the file), real frames
    of the default arm in blocks as `softarm sim` hands them to a writer."""
    if frames.native is None:
        print("recording encoder: skipped, softarm was installed without its C encoder", flush=True)
        return []
    batch, n = arm_batch(config, seeds=[0]), MAX_BLOCK_FRAMES
    sim = Simulator.from_config(config, batch, n)
    sim.step_block(n)
    positions = sim.history[0, :n].copy()
    images = Rasteriser(config.camera, batch.body.outline, 1, n).render(sim.history, n)[0].copy()
    sim.close()
    block = (images, stretch(positions[None], batch.body.rest, batch.body.sensors)[0], positions,
             batch.drives[0].displacement(np.arange(n) * config.integration.frame_dt))
    model = model_metadata(config, batch.body, batch.drives[0], 0, batch.positions[0], batch.velocities[0])
    blocks = 2 if quick else 8
    native, files = frames.native, {}
    seconds = {}
    with tempfile.TemporaryDirectory() as folder:
        for name, encoder in (("C", native), ("Python", None)):
            frames.native = encoder
            times = []
            for repeat in range(3):
                path = Path(folder) / f"{name}{repeat}.mcap"
                start = time.perf_counter()
                writer = RecordingWriter(path, model, config.integration.frame_dt)
                for _ in range(blocks):
                    writer.write(*block)
                writer.close(True)
                times.append(time.perf_counter() - start)
            seconds[name] = min(times) / (blocks * n) * 1e6
            files[name] = path.read_bytes()
        frames.native = native
    if files["C"] != files["Python"]:
        raise AssertionError("the C and Python encoders wrote different bytes")
    return [{"name": "recording, one arm's frames encoded and written (C encoder)", "ours": seconds["C"],
             "reference": seconds["Python"], "unit": "µs/arm-frame", "against": "the Python encoder, same bytes "
             "(lower is better)", "ratio": seconds["C"] / seconds["Python"]}]
