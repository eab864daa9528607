"""`softarm replay` and `softarm evaluate`: what a checkpoint imagines, on one recording or on the suite."""

from pathlib import Path
from typing import Annotated, Optional

import typer
from softarm_cli.console import err, out, run_or_exit, say
from softarm_cli.options import Checkpoint, Device, Force, Quiet, SensorNoise
from softarm_cli.progress import LazyProgress
from softarm_cli.tables import replay_table, suite_table

from softarm.sense.imperfections import parse_imperfections


def replay(
    checkpoint: Checkpoint,
    recording: Annotated[Path, typer.Argument(metavar="RECORDING", help="Recording (.mcap) to imagine; any seed, offset or amplitude.")],
    rrd: Annotated[Optional[Path], typer.Option("--rrd", help="Write the Rerun timeline (camera | imagined | difference | fused, signals, IoU).")] = None,
    mcap: Annotated[Optional[Path], typer.Option("--mcap", help="Write the imagination as MCAP (/imagination/image, /imagination/iou, /imagination/confidence).")] = None,
    png: Annotated[Optional[Path], typer.Option("--png", help="Write a filmstrip: camera / imagined / difference at evenly spaced times.")] = None,
    png_span: Annotated[Optional[str], typer.Option("--png-span", metavar="START:END", help="The filmstrip's frames from this stretch of time (s) [default: the whole recording].")] = None,
    blind: Annotated[Optional[list[str]], typer.Option("--blind", metavar="START:END", help="Camera blackout START:END in seconds (repeatable); metrics split blind / seeing.")] = None,
    sensor_noise: SensorNoise = None,
    spawn: Annotated[bool, typer.Option("--spawn", help="Show the timeline in a Rerun viewer.")] = False,
    device: Device = "auto",
    force: Force = False,
    quiet: Quiet = False,
) -> None:
    """Imagine a recording frame by frame from its inputs (the stretch sensors) and compare with the camera.

    \b
    Example: softarm replay recordings/seed0.pt recordings/seed0.mcap --blind 95:100 --rrd recordings/replay.rrd
    """
    from softarm.imagine.replay import replay as run_replay

    noise = run_or_exit(lambda: parse_imperfections(sensor_noise)) if sensor_noise else None
    result = run_or_exit(lambda: run_replay(checkpoint, recording, blind or [], rrd=rrd, mcap=mcap, png=png,
                                            spawn=spawn, force=force, sensor_noise=noise, png_span=png_span,
                                            device=device))
    if not quiet:
        out.print(replay_table(result.metrics))
        written = ", ".join(str(p) for p in (rrd, mcap, png) if p is not None)
        say(f"replayed {result.metrics['frames']} frames in {result.wall_seconds:.1f} s "
            f"({result.real_time_factor:.0f}x real time)" + (f"; wrote {written}" if written else ""))


def evaluate(
    checkpoint: Checkpoint,
    suite_folder: Annotated[Path, typer.Argument(metavar="SUITE_DIR", help="Folder written by `softarm suite`.")],
    json_path: Annotated[Optional[Path], typer.Option("--json", help="Write every family's scores as JSON.")] = None,
    png: Annotated[Optional[Path], typer.Option("--png", help="Write the per-family IoU bars (model vs baselines).")] = None,
    trust_png: Annotated[Optional[Path], typer.Option("--trust-png", help="Write every confidence's sparsification curve beside the oracle's.")] = None,
    sensor_noise: SensorNoise = None,
    device: Device = "auto",
    force: Force = False,
    quiet: Quiet = False,
) -> None:
    """Imagine every recording of the suite; print one row per family beside the mean-frame, ridge and AE-ceiling
    answers. --sensor-noise replaces each level's own imperfections too.

    \b
    Example: softarm evaluate recordings/seed0.pt recordings/suite --json recordings/suite_scores.json --png suite.png
    """
    from softarm.suite.evaluate import evaluate as run_evaluation

    noise = run_or_exit(lambda: parse_imperfections(sensor_noise)) if sensor_noise else None
    with LazyProgress(err, "evaluating", 1, "recordings", quiet=quiet, log=out) as bar:
        evaluation = run_or_exit(lambda: run_evaluation(checkpoint, suite_folder, json_path=json_path, png=png,
                                                        sensor_noise=noise, force=force, progress=bar.update,
                                                        trust_png=trust_png, device=device))
    if not quiet:
        out.print(suite_table(evaluation))
