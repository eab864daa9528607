"""`softarm babble`: the arm commands its muscles at random and records episodes to learn its body from."""

from pathlib import Path
from typing import Annotated

import typer
from softarm_cli.console import err, out, run_or_exit, say, stop_interrupted
from softarm_cli.options import Arch, ConfigFile, Quiet
from softarm_cli.progress import LazyProgress

from softarm.config import load_config


def babble(
    folder: Annotated[Path, typer.Argument(metavar="DIR", help="An empty folder (or a new one) for the episodes.")],
    episodes: Annotated[int, typer.Option(help="Episodes to record, one recording each.")] = 24,
    seconds: Annotated[float, typer.Option(help="Seconds per episode.")] = 20.0,
    task: Annotated[str, typer.Option(help="The environment's task: reach (top still), track or hold (top shaken).")] = "reach",
    seed: Annotated[int, typer.Option(help="Episode k uses seed + k.")] = 0,
    config: ConfigFile = None,
    arch: Arch = "cpu",
    quiet: Quiet = False,
) -> None:
    """Motor babbling: random muscle commands, each held 0.2-1 s, recorded with the camera, stretch, nodes and
    activations (README, Control); train on them with train.inputs = ["stretch", "activation"].

    \b
    Example: softarm babble recordings/babble && softarm train recordings/babble --config babble.toml
    """
    from softarm.envs.babble import babble as record

    cfg = run_or_exit(lambda: load_config(config))
    with LazyProgress(err, "babbling", episodes, "episodes", quiet=quiet, log=out) as bar:
        result = run_or_exit(lambda: record(folder, episodes, seconds, task, cfg, seed=seed, arch=arch,
                                            progress=bar.update))
    if not result.complete:
        stop_interrupted(f"interrupted: kept {len(result.paths)} episode(s) in {folder}, the last cut short "
                         "(complete = false)" if result.paths else f"interrupted: no episode was written to {folder}")
    if not quiet:
        say(f"wrote {len(result.paths)} episode(s) of {seconds:g} s to {folder}")
