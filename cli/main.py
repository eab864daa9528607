"""The `softarm` command line: parse options, call the softarm library, print. No logic of its own."""

import json
import sys
import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Callable, Optional, TypeVar

import typer
from rich.console import Console

from softarm import __version__
from softarm.config import DEFAULT_CONFIG_TEXT, load_config
from softarm.errors import SoftarmError
from softarm.sense.reading import parse_imperfections
from softarm.sim import ARCHS
from softarm.corpus.build import DEFAULT_ARMS, DEFAULT_DURATION
from softarm.suite.families import SUITE_VERSION
from softarm_cli.progress import LazyProgress
from softarm_cli.study import study

# Plain help (no rich markup): rich would read every "[default: ...]" as a markup tag and drop it,
# and would show flags as if they took a <bool> value.
app = typer.Typer(help="softarm: a simulated soft arm that learns to picture its own body from its stretch sensors.",
                  no_args_is_help=True, add_completion=False, pretty_exceptions_enable=False, rich_markup_mode=None,
                  context_settings={"help_option_names": ["-h", "--help"], "max_content_width": 120})
err = Console(stderr=True, highlight=False, soft_wrap=True)
out = Console(highlight=False, soft_wrap=True)
if TYPE_CHECKING:
    from softarm.config import Config
    from softarm.learn.run import TrainResult  # imports torch: only for the commands that train
D = load_config()  # the defaults that --help shows come from the config, their one source of truth

T = TypeVar("T")
ArchOption = Annotated[str, typer.Option(help=f"Taichi backend: {' | '.join(ARCHS)}.")]
CheckpointArgument = Annotated[Path, typer.Argument(metavar="CHECKPOINT", help="Checkpoint from `softarm train`.")]
SENSOR_NOISE_HELP = ("Sensor imperfections to read with, replacing the checkpoint's, e.g. noise=2e-5,drift=1e-5 "
                     "(keys of the [sensing] config section but pairs; see `softarm config`).")


def one_line_warning(message: Warning | str, category: type[Warning], *_: object, **__: object) -> None:
    """Warnings (a truncated recording, an unreachable viewer) as one 'warning:' line, no source echo."""
    err.print(f"warning: {message}", markup=False)


warnings.showwarning = one_line_warning


def run_or_exit(action: Callable[[], T]) -> T:
    """Run a library call; a user-caused error becomes one line on stderr and exit code 1."""
    try:
        return action()
    except SoftarmError as e:
        err.print(f"error: {e}", markup=False)
        raise typer.Exit(1) from None
    except OSError as e:
        err.print(f"error: {e.strerror or e}" + (f": {e.filename}" if e.filename else ""), markup=False)
        raise typer.Exit(1) from None


def version_callback(value: bool) -> None:
    if value:
        out.print(f"softarm {__version__}")
        raise typer.Exit()


@app.callback()
def main(version: Annotated[Optional[bool], typer.Option("--version", callback=version_callback, is_eager=True,
                                                          help="Print the version and exit.")] = None) -> None:
    """softarm: simulate a soft octopus arm, record it, learn to imagine it from its stretch sensors."""


@app.command()
def config() -> None:
    """Print the documented default config (TOML); save it, edit it, pass it to --config.

    Example: softarm config > my_arm.toml
    """
    out.print(DEFAULT_CONFIG_TEXT, markup=False, end="")


@app.command()
def sim(
    config: Annotated[Optional[Path], typer.Option("--config", "-c", help="TOML config; omitted keys keep their defaults (see `softarm config`).")] = None,
    duration: Annotated[Optional[float], typer.Option(help=f"Seconds to simulate [default: {D.run.duration:g}].")] = None,
    amplitude: Annotated[Optional[float], typer.Option(help=f"Excitation amplitude A in metres [default: {D.excitation.amplitude:g}].")] = None,
    substeps: Annotated[Optional[int], typer.Option(help=f"Integration substeps per {D.integration.frame_dt:g} s frame [default: {D.integration.substeps}].")] = None,
    arms: Annotated[Optional[int], typer.Option(help=f"Arms simulated together; arm i uses seed + i and gets its own file [default: {D.run.arms}].")] = None,
    seed: Annotated[Optional[int], typer.Option(help=f"Seed of arm 0; seed 0 is the paper's run [default: {D.run.seed}].")] = None,
    arch: ArchOption = "cpu",
    out_path: Annotated[Optional[Path], typer.Option("--out", "-o", help="Output .mcap [default: recordings/seed<SEED>.mcap]; a batch writes <stem>_arm<i>.mcap.")] = None,
    force: Annotated[bool, typer.Option("--force", help="Overwrite existing output files.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar and no summary.")] = False,
) -> None:
    """Simulate the arm and record camera frames, stretch sensors, node positions and excitation as MCAP.

    \b
    Example: softarm sim --duration 10 --arms 4 --out recordings/short.mcap
    """
    from softarm.sim.run import simulate  # imports Taichi: only for the commands that need it

    overrides = {"run.duration": duration, "excitation.amplitude": amplitude, "integration.substeps": substeps,
                 "run.arms": arms, "run.seed": seed}
    cfg = run_or_exit(lambda: load_config(config, overrides))
    with LazyProgress(err, "simulating", cfg.n_frames, "frames", scale=cfg.run.arms, quiet=quiet) as bar:
        result = run_or_exit(lambda: simulate(cfg, out_path, force=force, arch=arch, progress=bar.update))
    files = ", ".join(str(p) for p in result.paths)
    size = result.bytes / 1e6
    if not result.complete:
        err.print(f"interrupted: kept {result.frames} frames per arm in {files} ({size:.1f} MB, complete = false)",
                  markup=False)
        raise typer.Exit(130)
    if not quiet:
        out.print(f"wrote {result.frames} frames x {len(result.paths)} arm(s) to {files} ({size:.1f} MB) in "
                  f"{result.wall_seconds:.1f} s: {result.real_time_factor:.0f}x real time", markup=False)


def train_with_progress(recordings: list[Path], cfg: "Config", out_file: Optional[Path], **options: Any) -> "TrainResult":
    """softarm.train with a progress bar over both networks' epochs."""
    from softarm.learn.run import train as run_training

    with LazyProgress(err, "training", 1, "steps", quiet=options.pop("quiet", False)) as bar:
        def progress(done: int, total: int, losses: dict[str, float]) -> None:
            bar.update(done, total=total, **{k: f"{k} {v:.4f}" for k, v in losses.items()})

        return run_or_exit(lambda: run_training(recordings, cfg, out_file, progress=progress, **options))


@app.command()
def train(
    recordings: Annotated[list[Path], typer.Argument(metavar="RECORDING...", help="Recordings (.mcap) to learn from, or folders of them (a corpus); each is split by time.")],
    out_path: Annotated[Optional[Path], typer.Option("--out", "-o", help="Checkpoint file [default: recordings/<first recording>.pt]; metrics go beside it as .metrics.json.")] = None,
    config: Annotated[Optional[Path], typer.Option("--config", "-c", help="TOML config; its [train] section sets the defaults below.")] = None,
    epochs_ae: Annotated[Optional[int], typer.Option(help=f"Autoencoder epochs [default: {D.train.epochs_ae}].")] = None,
    epochs_lstm: Annotated[Optional[int], typer.Option(help=f"LSTM epochs [default: {D.train.epochs_lstm}].")] = None,
    model: Annotated[Optional[str], typer.Option(help=f"Latent model: window (the paper's LSTM over the last --history samples) or stream (an LSTM that carries its state through the whole stream) [default: {D.train.model}].")] = None,
    history: Annotated[Optional[int], typer.Option(help=f"Stretch samples the LSTM sees [default: {D.train.history}].")] = None,
    include_current: Annotated[Optional[bool], typer.Option("--include-current/--previous-only", help="End the window at the predicted frame's own sample [default: previous only, as the paper].", show_default=False)] = None,
    latent: Annotated[Optional[int], typer.Option(help=f"Latent features of the autoencoder [default: {D.train.latent}].")] = None,
    seed: Annotated[Optional[int], typer.Option(help=f"Seed of initialisation and shuffling [default: {D.train.seed}].")] = None,
    minutes: Annotated[Optional[float], typer.Option(help="Fit the schedules into this many minutes of training, measured on this machine (sets train.max_steps_*; not reproducible elsewhere).")] = None,
    resume: Annotated[bool, typer.Option("--resume", help="Continue the interrupted run saved in --out.")] = False,
    spawn: Annotated[bool, typer.Option("--spawn", help="Open a Rerun viewer with live losses and a held-out clip.")] = False,
    rrd: Annotated[Optional[Path], typer.Option("--rrd", help="Save the live view to this .rrd file.")] = None,
    force: Annotated[bool, typer.Option("--force", help="Overwrite an existing checkpoint.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar and no metrics table.")] = False,
) -> None:
    """Train the autoencoder and the LSTM on recordings; print held-out metrics beside baselines.

    \b
    Example: softarm train recordings/seed0.mcap --rrd recordings/train.rrd
    """
    from softarm_cli.tables import metrics_table

    overrides = {"train.epochs_ae": epochs_ae, "train.epochs_lstm": epochs_lstm, "train.model": model, "train.history": history,
                 "train.include_current": include_current, "train.latent": latent, "train.seed": seed}
    cfg = run_or_exit(lambda: load_config(config, overrides))
    result = train_with_progress(recordings, cfg, out_path, resume=resume, force=force, spawn=spawn, rrd=rrd,
                                 quiet=quiet, minutes=minutes)
    if not result.complete:
        if result.checkpoint.exists():
            err.print(f"interrupted: {result.checkpoint} holds the last finished epoch; continue with softarm train "
                      f"{' '.join(map(str, recordings))} --out {result.checkpoint} --resume", markup=False)
        else:
            err.print("interrupted before the first epoch finished: no checkpoint was written", markup=False)
        raise typer.Exit(130)
    if not quiet:
        out.print(metrics_table(result.metrics))
        out.print(f"checkpoint {result.checkpoint}, metrics {result.metrics_path}, {result.wall_seconds:.0f} s",
                  markup=False)


@app.command()
def replay(
    checkpoint: CheckpointArgument,
    recording: Annotated[Path, typer.Argument(metavar="RECORDING", help="Recording (.mcap) to imagine; any seed, offset or amplitude.")],
    rrd: Annotated[Optional[Path], typer.Option("--rrd", help="Write the Rerun timeline (camera | imagined | difference | fused, signals, IoU).")] = None,
    mcap: Annotated[Optional[Path], typer.Option("--mcap", help="Write the imagination as MCAP (/imagination/image, /imagination/iou).")] = None,
    png: Annotated[Optional[Path], typer.Option("--png", help="Write a filmstrip: camera / imagined / difference at evenly spaced times.")] = None,
    blind: Annotated[Optional[list[str]], typer.Option("--blind", metavar="START:END", help="Camera blackout START:END in seconds (repeatable); metrics split blind / seeing.")] = None,
    sensor_noise: Annotated[Optional[str], typer.Option("--sensor-noise", metavar="KEY=VALUE,...", help=SENSOR_NOISE_HELP)] = None,
    spawn: Annotated[bool, typer.Option("--spawn", help="Show the timeline in a Rerun viewer.")] = False,
    force: Annotated[bool, typer.Option("--force", help="Overwrite existing outputs.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No metrics table.")] = False,
) -> None:
    """Imagine a recording frame by frame from its stretch sensors and compare with the camera.

    \b
    Example: softarm replay recordings/seed0.pt recordings/seed0.mcap --blind 95:100 --rrd recordings/replay.rrd
    """
    from softarm.imagine.run import replay as run_replay
    from softarm_cli.tables import replay_table

    noise = run_or_exit(lambda: parse_imperfections(sensor_noise)) if sensor_noise else None
    result = run_or_exit(lambda: run_replay(checkpoint, recording, blind or [], rrd=rrd, mcap=mcap, png=png,
                                            spawn=spawn, force=force, sensor_noise=noise))
    if not quiet:
        out.print(replay_table(result.metrics))
        written = ", ".join(str(p) for p in (rrd, mcap, png) if p is not None)
        out.print(f"replayed {result.metrics['frames']} frames in {result.wall_seconds:.1f} s "
                  f"({result.real_time_factor:.0f}x real time)" + (f"; wrote {written}" if written else ""), markup=False)


@app.command()
def corpus(
    folder: Annotated[Path, typer.Argument(metavar="DIR", help="Folder for the corpus's recordings and corpus.json.")],
    preset: Annotated[str, typer.Option(help="general: every kind of motion; paper: the paper's drive at many time offsets.")] = "general",
    arms: Annotated[int, typer.Option(help="Arms in all, spread over the preset's groups.")] = DEFAULT_ARMS,
    duration: Annotated[float, typer.Option(help="Seconds simulated per arm.")] = DEFAULT_DURATION,
    arch: ArchOption = "cpu",
    force: Annotated[bool, typer.Option("--force", help="Write over a corpus already in DIR.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar and no summary.")] = False,
) -> None:
    """Simulate a training corpus: many arms and kinds of motion, from seeds below the held-out suite's.

    \b
    Example: softarm corpus recordings/corpus && softarm train recordings/corpus --out general.pt
    """
    from softarm.corpus.build import write_corpus

    with LazyProgress(err, "corpus", 1, "arm-frames", quiet=quiet) as bar:
        manifest = run_or_exit(lambda: write_corpus(folder, preset=preset, arms=arms, duration=duration, force=force,
                                                    arch=arch, progress=bar.update))
    if manifest is None:
        err.print(f"interrupted: {folder} holds part of the corpus and no corpus.json; run the command again",
                  markup=False)
        raise typer.Exit(130)
    if not quiet:
        written = json.loads(manifest.read_text())["arms"]
        out.print(f"wrote a {preset} corpus of {written} arm(s) x {duration:g} s to {folder}", markup=False)


@app.command()
def suite(
    folder: Annotated[Path, typer.Argument(metavar="DIR", help="Folder for the suite's recordings and suite.json.")],
    arch: ArchOption = "cpu",
    force: Annotated[bool, typer.Option("--force", help="Write over a suite already in DIR.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar and no summary.")] = False,
) -> None:
    """Write the held-out imagination suite: every family and level from its reserved seeds (no corpus uses them).

    \b
    Example: softarm suite recordings/suite
    """
    from softarm.suite.build import write_suite

    with LazyProgress(err, "suite", 1, "arm-frames", quiet=quiet) as bar:
        manifest = run_or_exit(lambda: write_suite(folder, force=force, arch=arch, progress=bar.update))
    if manifest is None:
        err.print(f"interrupted: {folder} holds part of the suite and no suite.json; run the command again",
                  markup=False)
        raise typer.Exit(130)
    if not quiet:
        out.print(f"wrote {SUITE_VERSION} to {folder} ({manifest.name} and its recordings)", markup=False)


@app.command()
def evaluate(
    checkpoint: CheckpointArgument,
    suite_folder: Annotated[Path, typer.Argument(metavar="SUITE_DIR", help="Folder written by `softarm suite`.")],
    json_path: Annotated[Optional[Path], typer.Option("--json", help="Write every family's scores as JSON.")] = None,
    png: Annotated[Optional[Path], typer.Option("--png", help="Write the per-family IoU bars (model vs baselines).")] = None,
    sensor_noise: Annotated[Optional[str], typer.Option("--sensor-noise", metavar="KEY=VALUE,...", help=SENSOR_NOISE_HELP + " Replaces each level's own too.")] = None,
    force: Annotated[bool, typer.Option("--force", help="Overwrite existing outputs.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar and no table.")] = False,
) -> None:
    """Imagine every recording of the suite; print one row per family beside the mean-frame, ridge and AE-ceiling answers.

    \b
    Example: softarm evaluate recordings/seed0.pt recordings/suite --json suite.json --png suite.png
    """
    from softarm.suite.run import evaluate as run_evaluation
    from softarm_cli.tables import suite_table

    noise = run_or_exit(lambda: parse_imperfections(sensor_noise)) if sensor_noise else None
    with LazyProgress(err, "evaluating", 1, "recordings", quiet=quiet) as bar:
        evaluation = run_or_exit(lambda: run_evaluation(checkpoint, suite_folder, json_path=json_path, png=png,
                                                        sensor_noise=noise, force=force, progress=bar.update))
    if not quiet:
        out.print(suite_table(evaluation))


@app.command()
def demo(
    folder: Annotated[Path, typer.Option("--folder", help="Where everything goes.")] = Path("recordings/demo"),
    force: Annotated[bool, typer.Option("--force", help="Overwrite an earlier demo.")] = False,
) -> None:
    """The whole pipeline on defaults: simulate 100 s, train, replay with a 5 s camera blackout.

    \b
    Example: softarm demo
    """
    from softarm.imagine.run import replay as run_replay
    from softarm.learn.run import check_train_outputs
    from softarm.sim.run import simulate
    from softarm_cli.tables import metrics_table, replay_table

    cfg = load_config()
    source, ckpt, view = folder / "seed0.mcap", folder / "model.pt", folder / "train.rrd"
    run_or_exit(lambda: check_train_outputs(ckpt, view, resume=False, force=force))
    with LazyProgress(err, "simulating", cfg.n_frames, "frames") as bar:
        simulated = run_or_exit(lambda: simulate(cfg, source, force=force, progress=bar.update))
    if not simulated.complete:
        err.print(f"interrupted: kept {simulated.frames} frames in {source}; the demo stops here", markup=False)
        raise typer.Exit(130)
    trained = train_with_progress([source], cfg, ckpt, force=force, rrd=view)
    if not trained.complete:
        err.print(f"interrupted: {ckpt} holds the last finished epoch; the demo stops here", markup=False)
        raise typer.Exit(130)
    out.print(metrics_table(trained.metrics))
    outputs = {"rrd": folder / "replay.rrd", "mcap": folder / "imagination.mcap", "png": folder / "filmstrip.png"}
    result = run_or_exit(lambda: run_replay(ckpt, source, ["95:100"], force=True, **outputs))
    out.print(replay_table(result.metrics))
    for label, path in [("recording", source), ("checkpoint", ckpt), ("training view", view),
                        *[(f"replay {k}", v) for k, v in outputs.items()]]:
        out.print(f"{label:>15}: {path}", markup=False)
    out.print(f"open the timelines with: rerun {outputs['rrd']}", markup=False)


app.command()(study)

if __name__ == "__main__":
    sys.exit(app())
