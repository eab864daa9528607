"""`softarm study`: parse the options, run the study with a progress bar, print its table and files."""

from pathlib import Path
from typing import Annotated, Optional

import typer

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
    force: Annotated[bool, typer.Option("--force", help="Forget the trials recorded in DIR and run every one again (also another study's DIR).")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar and no table.")] = False,
) -> None:
    """Run a comparative study: each trial trains on a shared corpus with its own settings and is scored on the
    held-out suite, as a Ray task. Trials recorded in DIR are skipped, so an interrupted study resumes.

    \b
    Example: softarm study sensors --out recordings/studies/sensors --quick
    """
    from softarm.study.report import results_table
    from softarm.study.run import run_study
    from softarm_cli.main import err, out, run_or_exit
    from softarm_cli.progress import LazyProgress

    bars: dict[str, LazyProgress] = {}

    def progress(stage: str, done: int, total: int) -> None:
        if stage not in bars:
            for bar in bars.values():
                bar.close()
            label, unit = STAGES[stage]
            bars[stage] = LazyProgress(err, label, total, unit, quiet=quiet)
        bars[stage].update(done, total=total)

    try:
        result = run_or_exit(lambda: run_study(name, out_dir, QUICK if quick else FULL, address=address, trials=trials,
                                               force=force, progress=progress))
    finally:
        for bar in bars.values():
            bar.close()
    finished = sum(r.status != "pending" for r in result.records)
    if not result.complete:
        err.print(f"interrupted: {out_dir / 'trials.jsonl'} keeps {finished} of {len(result.records)} trials; run the "
                  "command again to run the rest", markup=False)
        raise typer.Exit(130)
    if not quiet:
        out.print(results_table(result.study, result.records), markup=False)
        for label, path in (("results", result.results), ("table", result.markdown), ("plot", result.png)):
            out.print(f"{label:>8}: {path}", markup=False)
    failed = [r for r in result.records if r.status == "failed"]
    for record in failed:
        err.print(f"failed: {record.name}: {record.error}", markup=False)
    if failed:
        raise typer.Exit(1)
