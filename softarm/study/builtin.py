"""The built-in studies, and finding a study by name or TOML file.

Each asks one question of the imagination, everything else at its defaults:
- `sensors`: how many stretch sensors, and where (1 to 16; along the edges, spread, random); and bend sensors
  down the middle column instead (1 to 8), each kind read beside the drive.
- `noise`: how much it suffers from imperfect sensors (white noise, drift, one sensor stuck), trained
  and scored with the same imperfections.
- `history`: how many past stretch samples the window model needs, and the stream model beside it.
- `latent`: how many latent features the autoencoder needs.
"""

from pathlib import Path
from typing import Callable, Union

from softarm.config import load_config
from softarm.errors import ConfigError
from softarm.study.placements import PLACEMENTS, bend_triples, sensor_pairs
from softarm.study.plan import Study, Trial, read_study

SENSOR_COUNTS = (1, 2, 4, 8, 16)
BEND_COUNTS = (1, 2, 4, 8)
NOISE_UM = (0, 10, 30, 100, 300)    # white noise; the signals' spread is 0.7-1.5 mm
DRIFT_UM = (5, 20, 50)              # per sqrt(s)
STUCK = {0: "upper left", 2: "lower left"}  # the right edge mirrors the left
HISTORIES = (1, 3, 6, 12, 24)
LATENTS = (4, 8, 16, 32)


def sensors() -> Study:
    config = load_config()
    trials = tuple(Trial(f"{placement}{n}", n, placement, {"sensing.pairs": sensor_pairs(placement, n, config)})
                   for placement in PLACEMENTS for n in SENSOR_COUNTS)
    bend = tuple(Trial(f"bend{n}", n, "bend (middle column)",
                       {"sensing.bend": bend_triples(n, config), "train.inputs": ["bend", "drive"]})
                 for n in BEND_COUNTS)
    return Study("sensors", "sensor count", "stretch or bend sensors: how many, and where", trials + bend,
                 (*(f"{p}{n}" for p in PLACEMENTS for n in (2, 8)), "bend2", "bend4"))


def noise() -> Study:
    trials = (*(Trial(f"noise{um}um" if um else "clean", um, "white noise σ (µm)", {"sensing.noise": um / 1e6})
                for um in NOISE_UM),
              *(Trial(f"drift{um}um", um, "drift (µm/√s)", {"sensing.drift": um / 1e6}) for um in DRIFT_UM),
              *(Trial(f"stuck{k}", where, "one sensor stuck from t = 0",
                      {"sensing.dropout_sensor": k, "sensing.dropout_time": 0.0}) for k, where in STUCK.items()))
    return Study("noise", "imperfection", "imperfect sensors, in training and in the suite", trials,
                 ("clean", "noise100um", "drift20um", "stuck0"))


def history() -> Study:
    trials = (*(Trial(f"history{h}", h, "window model", {"train.model": "window", "train.history": h})
                for h in HISTORIES),
              Trial("stream", "whole stream", "stream model", {"train.model": "stream"}))
    return Study("history", "stretch samples seen", "how much of the past the imagination needs", trials,
                 ("history1", "history6", "history24", "stream"))


def latent() -> Study:
    trials = tuple(Trial(f"latent{n}", n, "autoencoder", {"train.latent": n}) for n in LATENTS)
    return Study("latent", "latent features", "how small the body's code can be", trials, ("latent4", "latent16"))


BUILTIN: dict[str, Callable[[], Study]] = {"sensors": sensors, "noise": noise, "history": history, "latent": latent}


def load_study(study: Union[str, Path]) -> Study:
    """A built-in study by name, or the study in a TOML file."""
    if str(study) in BUILTIN:
        return BUILTIN[str(study)]()
    if Path(study).suffix == ".toml" or Path(study).exists():
        return read_study(study)
    raise ConfigError(f"study {str(study)!r} is neither a built-in study ({', '.join(BUILTIN)}) nor a .toml file")
