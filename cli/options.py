"""Options several commands share, each declared once with its help; defaults shown in --help come from the
config, their one source of truth."""

from pathlib import Path
from typing import Annotated, Optional

import typer

from softarm.config import load_config
from softarm.config.keys import DEVICES
from softarm.sim import ARCHS

D = load_config()

Arch = Annotated[str, typer.Option(help=f"Taichi backend: {' | '.join(ARCHS)}.")]
DEVICE_HELP = f"Where torch runs: {' | '.join(DEVICES)} (auto: a CUDA GPU when torch sees one, else the CPU)."
Device = Annotated[str, typer.Option("--device", help=DEVICE_HELP)]
Force = Annotated[bool, typer.Option("--force", help="Overwrite existing outputs (never an input).")]
Quiet = Annotated[bool, typer.Option("--quiet", "-q", help="No progress and no summary.")]
ConfigFile = Annotated[Optional[Path], typer.Option("--config", "-c", help="TOML config; omitted keys keep their defaults (see `softarm config`).")]
Checkpoint = Annotated[Path, typer.Argument(metavar="CHECKPOINT", help="Checkpoint from `softarm train`.")]
SENSOR_NOISE_HELP = ("Sensor imperfections to read with, replacing the checkpoint's, e.g. noise=2e-5,drift=1e-5 "
                     "(keys of the [sensing] config section but pairs; see `softarm config`).")
SensorNoise = Annotated[Optional[str], typer.Option("--sensor-noise", metavar="KEY=VALUE,...", help=SENSOR_NOISE_HELP)]
