"""A checkpoint ready to answer: its imaginer, its baselines, and its way of reading a recording.

Replay, the suite's evaluation and the streamer open a checkpoint here. A recording is read as the model
was trained to read it (every input channel, the sensors with their imperfections, unless a caller
replaces those), after a check that its camera and inputs fit the checkpoint, made before its frames are
read.
"""

from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any, Optional, Union

import numpy as np

from softarm.config import Config, override
from softarm.imagine.imaginer import Imaginer
from softarm.model.baselines import Baselines
from softarm.model.checkpoint import checkpoint_config, load_checkpoint
from softarm.model.device import torch_device
from softarm.model.fits import check_fits, recording_shape
from softarm.record.reader import Recording, read_model, read_recording
from softarm.sense.imperfections import SensorModel


@dataclass(frozen=True)
class Reading:
    """A recording and what the model reads from it."""
    recording: Recording
    inputs: np.ndarray     # (T, F) raw, every channel side by side
    config: Config         # the config it was read with (the checkpoint's, with any replaced imperfections)


class TrainedModel:
    def __init__(self, path: Union[str, Path], device: str = "cpu"):
        """The checkpoint at `path`, its networks on `device` (auto | cpu | cuda: `softarm.model.device`)."""
        self.path = Path(path)
        self.state = load_checkpoint(self.path)
        self.config = checkpoint_config(self.state)
        self.imaginer = Imaginer.from_checkpoint(self.state, torch_device(device))

    @cached_property
    def baselines(self) -> Baselines:
        return Baselines.from_checkpoint(self.state)

    def with_sensors(self, sensor_noise: Optional[dict[str, Any]]) -> Config:
        """The checkpoint's config with `sensor_noise` (keys of [sensing] but pairs) replacing its imperfections."""
        return override(self.config, {f"sensing.{k}": v for k, v in (sensor_noise or {}).items()})

    def imaginer_for(self, config: Config) -> Imaginer:
        """The imaginer of readings taken with `config`'s sensors (a `Reading`'s): where they are noisier than
        those the checkpoint was trained with, its surprise expects the difference."""
        white = [SensorModel.from_config(c.sensing).white_variance for c in (config, self.config)]
        return self.imaginer.heard_through(white[0] - white[1])

    def read(self, recording: Union[str, Path], sensor_noise: Optional[dict[str, Any]] = None,
             nodes: bool = False) -> Reading:
        """`recording` as the checkpoint reads it, with `sensor_noise` (keys of [sensing] but pairs) replacing
        its imperfections; `nodes` reads the node positions even where no input needs them."""
        config = self.with_sensors(sensor_noise)
        inputs = self.imaginer.inputs
        expected = (self.state["image_shape"], inputs.widths)
        check_fits(str(recording), recording_shape(read_model(recording), inputs.channels, config), expected,
                   inputs.channels, str(self.path), trained=True)
        rec = read_recording(recording, nodes=nodes or inputs.needs_nodes(config))
        return Reading(rec, inputs.read(rec, config), config)
