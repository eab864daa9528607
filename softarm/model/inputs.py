"""What a latent model reads: a declared list of input channels, each read from a recording and normalised by
its own scaler, fitted on the training data and kept in the checkpoint.

A channel is one class here and one line of `registry.INPUT_CHANNELS`; every reader (training, replay,
evaluation, the streamer) reads through `Inputs`, so a new channel is not an edit of each of them.
"""

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar, Sequence

import numpy as np

from softarm.config import Config
from softarm.errors import RecordingError
from softarm.model.scaler import Scaler
from softarm.registry import input_channel_class
from softarm.sense.reading import kind_count, needs_nodes, sensed_kind, sensed_stretch, sensor_count
from softarm.sensors import KINDS

if TYPE_CHECKING:
    from softarm.record.reader import Recording

PAPER = ("stretch",)              # the paper's model: the stretch alone


class InputChannel:
    """One signal a latent model reads: how many features a recording gives and how they are read."""
    name: ClassVar[str]
    what: ClassVar[str]  # its features, as an error message names them
    felt: ClassVar[bool] = False  # a sensor's reading (what the surprise predicts), not a command

    def features(self, model: dict[str, Any], config: Config) -> int:
        """How many features a recording with this model document gives (read before its frames)."""
        raise NotImplementedError

    def read(self, recording: "Recording", config: Config) -> np.ndarray:
        """(T, F) float64: the channel's signal at every frame."""
        raise NotImplementedError

    def needs_nodes(self, config: Config) -> bool:
        """Whether reading it needs the recording's node positions."""
        return False


class Stretch(InputChannel):
    """The stretch sensors, as the [sensing] section reads them (pairs, imperfections)."""
    name = "stretch"
    what = "stretch sensors"
    felt = True

    def features(self, model: dict[str, Any], config: Config) -> int:
        return sensor_count(model, config.sensing)

    def read(self, recording: "Recording", config: Config) -> np.ndarray:
        return sensed_stretch(recording, config.sensing)

    def needs_nodes(self, config: Config) -> bool:
        return needs_nodes(config.sensing)


class SensorInput(InputChannel):
    """The readings of a sensor kind other than the stretch (softarm.sensors), as [sensing] reads them."""
    felt = True

    def features(self, model: dict[str, Any], config: Config) -> int:
        return kind_count(model, KINDS[self.name](), config.sensing)

    def read(self, recording: "Recording", config: Config) -> np.ndarray:
        return sensed_kind(recording, KINDS[self.name](), config.sensing)

    def needs_nodes(self, config: Config) -> bool:
        return bool(getattr(config.sensing, self.name))


class Bend(SensorInput):
    name = "bend"
    what = "bend sensors"


class Drive(InputChannel):
    """The robot's own motor command (the efference copy): the driven nodes' displacement along the drive
    direction, as `/arm/excitation` records it (m)."""
    name = "drive"
    what = "drive signals"

    def features(self, model: dict[str, Any], config: Config) -> int:
        return 1

    def read(self, recording: "Recording", config: Config) -> np.ndarray:
        return np.asarray(recording.drive(), np.float64)[:, None]


class DriveRate(InputChannel):
    """The command's rate (m/s): the displacement's backward difference over one frame, 0 at the first; causal,
    so the streamer reads it as a batch replay does."""
    name = "drive_rate"
    what = "drive-rate signals"

    def features(self, model: dict[str, Any], config: Config) -> int:
        return 1

    def read(self, recording: "Recording", config: Config) -> np.ndarray:
        d = np.asarray(recording.drive(), np.float64)
        return np.concatenate([[0.0], np.diff(d)])[:, None] / recording.frame_dt


class Activation(InputChannel):
    """A commanded arm's motor command: its muscles' activations, one per group, as `/arm/activation` records
    them (the recordings of softarm.envs)."""
    name = "activation"
    what = "muscle activations"

    def features(self, model: dict[str, Any], config: Config) -> int:
        return len(model.get("muscles", {}).get("names", ()))

    def read(self, recording: "Recording", config: Config) -> np.ndarray:
        if recording.activation is None:
            raise RecordingError(f"{recording.path} has no muscle activations (only the control environments' "
                                 "recordings have them): train without the activation input")
        return np.asarray(recording.activation, np.float64)


def channels(names: Sequence[str] = PAPER) -> tuple[InputChannel, ...]:
    return tuple(input_channel_class(name)() for name in names)


def chosen_inputs(asked: Sequence[str], models: Sequence[dict[str, Any]], config: Config,
                  corpus: int) -> tuple[str, ...]:
    """The input channels of a training: those `train.inputs` lists, or when it lists none the paper's (the
    stretch) for a few recordings, and for a corpus of more than `corpus` (their model documents, `models`)
    a model of many motions: the stretch, every other sensor kind each recording carries (or [sensing]
    places), then the command. All the arm feels: a poke bends it sideways more than it stretches its edges."""
    if asked:
        return tuple(asked)
    if len(models) <= corpus:
        return PAPER
    felt = [name for name, kind in KINDS.items()
            if all(kind_count(model, kind(), config.sensing) for model in models)]
    return ("stretch", *felt, "drive")


def read_channels(chosen: Sequence[InputChannel], recording: "Recording", config: Config) -> np.ndarray:
    """(T, F) float64: every channel's features side by side, in the declared order."""
    return np.concatenate([c.read(recording, config) for c in chosen], axis=1)


@dataclass(frozen=True)
class Inputs:
    """The channels a trained model reads, in order, each with the scaler fitted on its training data."""
    channels: tuple[InputChannel, ...]
    scalers: tuple[Scaler, ...]

    @property
    def widths(self) -> list[int]:
        """Features of each channel."""
        return [len(s.mean) for s in self.scalers]

    @property
    def features(self) -> int:
        return sum(self.widths)

    @classmethod
    def fit(cls, chosen: Sequence[InputChannel], widths: Sequence[int], training: np.ndarray) -> "Inputs":
        """Each channel's scaler from its columns of the training samples (M, F)."""
        return cls(tuple(chosen), tuple(Scaler.fit(part) for part in _columns(training, widths)))

    @property
    def spread(self) -> np.ndarray:
        """(F,) the raw standard deviation one unit of each normalised column stands for."""
        return np.concatenate([scaler.std[scaler.keep] for scaler in self.scalers])

    def normalise(self, raw: np.ndarray) -> np.ndarray:
        """(..., F) raw samples -> (..., F) float64, each channel by its own scaler."""
        parts = [scaler.forward(part) for scaler, part in zip(self.scalers, _columns(raw, self.widths))]
        return parts[0] if len(parts) == 1 else np.concatenate(parts, axis=-1)

    def read(self, recording: "Recording", config: Config) -> np.ndarray:
        return read_channels(self.channels, recording, config)

    def needs_nodes(self, config: Config) -> bool:
        return any(c.needs_nodes(config) for c in self.channels)

    def to_state(self) -> list[dict[str, Any]]:
        """What the checkpoint keeps: each channel's name, width and scaler."""
        return [{"name": c.name, "features": len(s.mean), "scaler": s.to_state()}
                for c, s in zip(self.channels, self.scalers)]

    @classmethod
    def from_state(cls, state: Sequence[dict[str, Any]]) -> "Inputs":
        return cls(channels([entry["name"] for entry in state]), tuple(Scaler.from_state(e["scaler"]) for e in state))


def _columns(data: np.ndarray, widths: Sequence[int]) -> list[np.ndarray]:
    """The last axis of `data` cut into consecutive parts of `widths` features."""
    edges = np.cumsum([0, *widths])
    return [data[..., a:b] for a, b in zip(edges[:-1], edges[1:])]
