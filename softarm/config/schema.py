"""Which config keys exist and what type each has: one frozen dataclass per TOML section.

The values live in `default.toml` beside this module (print it with `softarm config`); these classes
hold no defaults of their own, so the TOML file is the one source of truth.
"""

import dataclasses
from dataclasses import dataclass
from typing import Any, Union


@dataclass(frozen=True)
class BodyConfig:
    rows: int
    columns: int
    length: float
    base_width: float
    tip_width: float
    node_mass: float
    gravity: tuple[float, float]
    driven: Union[tuple[int, ...], None] = None


@dataclass(frozen=True)
class SpringsConfig:
    stiffness: float
    damping: float


@dataclass(frozen=True)
class SumOfSinesConfig:
    amplitudes: tuple[float, ...]
    frequencies: tuple[float, ...]
    phases: tuple[float, ...]
    band: tuple[float, ...]
    components: int
    rms: float


@dataclass(frozen=True)
class ExcitationConfig:
    kind: str
    direction: tuple[float, float]
    amplitude: float
    frequencies: tuple[float, ...]
    time_offset: float
    offset_range: float
    amplitude_jitter: float
    sum_of_sines: SumOfSinesConfig
    rhythm_jitter: float = 0.0  # recordings made before it existed played every arm at the listed frequencies


@dataclass(frozen=True)
class SensorsConfig:
    pairs: tuple[tuple[int, int], ...]
    bend: Union[tuple[tuple[int, int, int], ...], None] = None  # bend sensors recorded on /arm/bend (softarm.sensors)


@dataclass(frozen=True)
class SensingConfig:
    pairs: tuple[tuple[int, int], ...]
    noise: float
    bias: float
    drift: float
    quantisation: float
    dropout_sensor: int
    dropout_time: float
    seed: int
    bend: Union[tuple[tuple[int, int, int], ...], None] = None  # bend sensors recomputed from the node positions
    bend_noise: Union[float, None] = None  # rad: white noise of each bend reading


@dataclass(frozen=True)
class CameraConfig:
    width: int
    height: int
    pixels_per_metre: float
    origin: tuple[float, float]
    outline: Union[tuple[int, ...], None] = None


@dataclass(frozen=True)
class IntegrationConfig:
    frame_dt: float
    substeps: int
    integrator: str
    blowup_distance: float


@dataclass(frozen=True)
class RunConfig:
    duration: float
    arms: int
    seed: int


@dataclass(frozen=True)
class DisturbanceConfig:
    """One [[disturbances]] table: a kind, its interval and the parameters of its kind (docs/model.md)."""
    kind: str
    start: float
    end: Union[float, None] = None
    force: Union[tuple[float, float], None] = None
    nodes: Union[tuple[int, ...], None] = None
    mass: Union[float, None] = None
    factor: Union[float, None] = None
    springs: Union[tuple[int, ...], None] = None
    centre: Union[tuple[float, float], None] = None
    radius: Union[float, None] = None
    stiffness: Union[float, None] = None
    damping: Union[float, None] = None
    velocity: Union[tuple[float, float], None] = None
    coefficient: Union[float, None] = None
    quadratic: Union[float, None] = None


@dataclass(frozen=True)
class RandomDisturbanceConfig:
    """One [[world.random]] table: how every arm draws disturbances of one kind from its seed."""
    kind: str
    share: float
    count: tuple[int, int]
    start: tuple[float, float]
    rows: Union[tuple[int, int], None] = None
    duration: Union[tuple[float, float], None] = None
    force: Union[tuple[float, float], None] = None
    mass: Union[tuple[float, float], None] = None
    factor: Union[tuple[float, float], None] = None
    span: Union[int, None] = None
    radius: Union[tuple[float, float], None] = None
    gap: Union[tuple[float, float], None] = None
    speed: Union[tuple[float, float], None] = None
    coefficient: Union[tuple[float, float], None] = None
    quadratic: Union[tuple[float, float], None] = None


@dataclass(frozen=True)
class WorldConfig:
    contact_stiffness: float
    contact_damping: float
    random: tuple[RandomDisturbanceConfig, ...]


@dataclass(frozen=True)
class MuscleGroupConfig:
    """One [[muscles.groups]] table: springs that contract together (docs/model.md, Muscles), named either by an
    edge (`side` and `rows`) or as spring indices (`springs`)."""
    name: str
    max_contraction: float
    side: Union[str, None] = None
    rows: Union[tuple[int, int], None] = None
    springs: Union[tuple[int, ...], None] = None


@dataclass(frozen=True)
class MusclesConfig:
    time_constant: float
    groups: tuple[MuscleGroupConfig, ...]


@dataclass(frozen=True)
class ControlConfig:
    """[control]: the tasks of the control environments (softarm.envs)."""
    episode: float
    tolerance: float
    hold: float
    track_period: float
    shake_amplitude: float
    reward_scale: float
    workspace_samples: int
    push_force: tuple[float, float]
    push_duration: tuple[float, float]


@dataclass(frozen=True)
class TrainConfig:
    train_fraction: float
    test_fraction: float
    latent: int
    history: int
    include_current: bool
    inputs: tuple[str, ...]
    model: str
    sequence: int
    streams: int
    validation_recordings: float
    epochs_ae: int
    epochs_lstm: int
    max_steps_ae: int
    max_steps_lstm: int
    batch_ae: int
    batch_lstm: int
    lr_ae: float
    lr_lstm: float
    lstm_hidden: int
    min_feature_std: float
    seed: int
    precision: str = "auto"
    device: str = "auto"
    node_target: float = 0.0
    ensemble: int = 1
    confidence: str = "calibrated"
    false_alarms_per_minute: float = 1.0

    @property
    def lead(self) -> int:
        """Frames between the last input sample a model reads and the frame it imagines from it: 1 with the
        paper's set-up (samples up to k - 1 imagine frame k), 0 with `include_current`."""
        return 0 if self.include_current else 1


@dataclass(frozen=True)
class Config:
    disturbances: tuple[DisturbanceConfig, ...]
    body: BodyConfig
    springs: SpringsConfig
    excitation: ExcitationConfig
    sensors: SensorsConfig
    sensing: SensingConfig
    camera: CameraConfig
    integration: IntegrationConfig
    run: RunConfig
    world: WorldConfig
    muscles: MusclesConfig
    control: ControlConfig
    train: TrainConfig

    @property
    def n_frames(self) -> int:
        return round(self.run.duration / self.integration.frame_dt)

    def to_dict(self) -> dict[str, Any]:
        """Plain nested dict (lists, no tuples, no unset optional keys): the form written to recordings."""
        return _plain(dataclasses.asdict(self))


def _plain(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items() if v is not None}
    if isinstance(value, (tuple, list)):
        return [_plain(v) for v in value]
    return value
