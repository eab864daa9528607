"""`softarm study`: parse the options, run the study with a progress bar, print its table and files."""

from pathlib import Path
from typing import Annotated, Optional

import typer
from softarm_cli.console import complain, err, out, run_or_exit, say, stop_interrupted
from softarm_cli.options import Device, Quiet
from softarm_cli.progress import StagedProgress

from softarm.study.builtin import BUILTIN
from softarm.study.scale import FULL, QUICK

SENSORS = BUILTIN["sensors"]()
STAGES = {"corpus": ("corpus", "arm-frames"), "suite": ("suite", "arm-frames"), "trials": ("trials", "trials")}


def study(
    name: Annotated[str, typer.Argument(metavar="NAME", help=f"A built-in study ({' | '.join(BUILTIN)}) or a TOML file of trials (see softarm.study.plan).")],
    out_dir: Annotated[Path, typer.Option("--out", "-o", help="Folder of the study: corpus/, suite/, trials/, trials.jsonl, results.json, results.md and NAME.png. On a cluster, a path every node shares.")],
    quick: Annotated[bool, typer.Option("--quick", help=f"A small corpus ({QUICK.arms} arms x {QUICK.duration:g} s), {QUICK.train['train.max_steps_ae']} + {QUICK.train['train.max_steps_lstm']} training steps, one recording per suite level, and only the study's quick trials (sensors: {len(SENSORS.quick)} of {len(SENSORS.trials)}); a few minutes here.")] = False,
    address: Annotated[Optional[str], typer.Option("--address", help="Join this running Ray cluster (e.g. 10.0.0.1:6379) [default: start Ray here, one trial per core].")] = None,
    trials: Annotated[Optional[int], typer.Option("--trials", help="Run only the first N trials of the study (of its quick ones with --quick).")] = None,
    device: Device = "auto",
    force: Annotated[bool, typer.Option("--force", help="Forget the trials recorded in DIR and run every one again (also another study's DIR).")] = False,
    quiet: Quiet = False,
) -> None:
    """Run a comparative study: each trial trains on a shared corpus with its own settings and is scored on the
    held-out suite, as a Ray task. Trials recorded in DIR are skipped, so an interrupted study resumes.

    \b
    Example: softarm study sensors --out recordings/studies/sensors --quick
    """
    from softarm.study.report import results_table
    from softarm.study.runner import run_study

    with StagedProgress(err, STAGES, quiet=quiet, log=out) as progress:
        result = run_or_exit(lambda: run_study(name, out_dir, QUICK if quick else FULL, address=address, trials=trials,
                                               force=force, progress=progress, device=device))
    finished = sum(r.status != "pending" for r in result.records)
    if not result.complete:
        stop_interrupted(f"interrupted: {out_dir / 'trials.jsonl'} keeps {finished} of {len(result.records)} trials; "
                         "run the command again to run the rest")
    if not quiet:
        say(results_table(result.study, result.records))
        for label, path in (("results", result.results), ("table", result.markdown), ("plot", result.png)):
            say(f"{label:>8}: {path}")
    failed = [r for r in result.records if r.status == "failed"]
    for record in failed:
        complain(f"failed: {record.name}: {record.error}")
    if failed:
        raise typer.Exit(1)
