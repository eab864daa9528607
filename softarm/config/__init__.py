"""Configuration: every constant of the model and of training, one TOML file of documented defaults.

`load_config()` reads the defaults (`default.toml`, printed by `softarm config`), a user's file over
them and dotted-key overrides (`override()` changes keys of a config already read); everything is
validated before anything runs.
"""

from softarm.config.load import DEFAULT_CONFIG_TEXT, config_from_dict, load_config, override
from softarm.config.schema import (
    BodyConfig,
    CameraConfig,
    Config,
    ControlConfig,
    DisturbanceConfig,
    ExcitationConfig,
    IntegrationConfig,
    MuscleGroupConfig,
    MusclesConfig,
    RandomDisturbanceConfig,
    RunConfig,
    SensingConfig,
    SensorsConfig,
    SpringsConfig,
    SumOfSinesConfig,
    TrainConfig,
    WorldConfig,
)

__all__ = ["DEFAULT_CONFIG_TEXT", "BodyConfig", "CameraConfig", "Config", "ControlConfig", "DisturbanceConfig",
           "ExcitationConfig", "IntegrationConfig", "MuscleGroupConfig", "MusclesConfig", "RandomDisturbanceConfig",
           "RunConfig", "SensingConfig", "SensorsConfig", "SpringsConfig", "SumOfSinesConfig", "TrainConfig",
           "WorldConfig", "config_from_dict", "load_config", "override"]
