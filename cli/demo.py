"""`softarm demo`: the whole pipeline on defaults (softarm.demo), with progress and the tables."""

from pathlib import Path
from typing import Annotated

import typer
from softarm_cli.console import err, out, run_or_exit, say, stop_interrupted
from softarm_cli.options import Force
from softarm_cli.progress import StagedProgress
from softarm_cli.tables import metrics_table, replay_table

STAGES = {"simulating": ("simulating", "frames"), "training": ("training", "steps"), "replaying": ("replaying", "replay")}


def demo(
    folder: Annotated[Path, typer.Option("--folder", help="Where everything goes.")] = Path("recordings/demo"),
    force: Force = False,
) -> None:
    """The whole pipeline on defaults: simulate 100 s, train, replay with a 5 s camera blackout.

    \b
    Example: softarm demo
    """
    from softarm.demo import demo as run_demo

    with StagedProgress(err, STAGES, log=out) as progress:
        result = run_or_exit(lambda: run_demo(folder, force=force, progress=progress))
    if result.stopped_in == "simulating":
        stop_interrupted(f"interrupted: kept {result.simulated.frames} frames in {result.outputs['recording']}; "
                         "the demo stops here")
    if result.stopped_in == "training":
        stop_interrupted(f"interrupted: {result.outputs['checkpoint']} holds the last finished epoch; the demo "
                         "stops here")
    out.print(metrics_table(result.trained.metrics))
    out.print(replay_table(result.replayed.metrics))
    for label, path in result.outputs.items():
        say(f"{label:>15}: {path}")
    say(f"open the timelines with: rerun {result.outputs['replay rrd']}")
