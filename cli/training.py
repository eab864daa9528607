"""`softarm train`: learn the autoencoder and the latent model from recordings, print the held-out metrics."""

from pathlib import Path
from typing import Annotated, Optional

import typer
from softarm_cli.console import err, out, run_or_exit, say, stop_interrupted
from softarm_cli.options import DEVICE_HELP, Checkpoint, ConfigFile, D, Device, Force, Quiet
from softarm_cli.progress import StagedProgress
from softarm_cli.tables import metrics_table

from softarm.config import load_config
from softarm.registry import INPUT_CHANNELS, LATENT_MODELS

TRAINING_STAGES = {"reading": ("reading", "recordings"), "training": ("training", "steps"),
                   "fitting": ("fitting", "fits")}  # the surprise, the baselines, the confidence, the metrics


def train(
    recordings: Annotated[list[Path], typer.Argument(metavar="RECORDING...", help="Recordings (.mcap) to learn from, or folders of them (a corpus); each is split by time.")],
    out_path: Annotated[Optional[Path], typer.Option("--out", "-o", help="Checkpoint file [default: recordings/<first recording>.pt]; metrics go beside it as .metrics.json.")] = None,
    config: ConfigFile = None,
    epochs_ae: Annotated[Optional[int], typer.Option(help=f"Autoencoder epochs [default: {D.train.epochs_ae}].")] = None,
    epochs_lstm: Annotated[Optional[int], typer.Option(help=f"Latent model epochs [default: {D.train.epochs_lstm}].")] = None,
    model: Annotated[Optional[str], typer.Option(help=f"Latent model: {' | '.join(LATENT_MODELS)} (window: the paper's LSTM over the last --history samples; stream: an LSTM that carries its state through the whole stream; gru: the same with a GRU; tcn: a causal temporal convolution network over the last 2.56 s) [default: {D.train.model}].")] = None,
    inputs: Annotated[Optional[str], typer.Option(metavar="NAME,...", help=f"Input channels the latent model reads, of {' | '.join(INPUT_CHANNELS)} [default: the stretch for up to 4 recordings; for a corpus stretch,bend,drive, the bend where every recording carries it].")] = None,
    history: Annotated[Optional[int], typer.Option(help=f"Input samples the window model sees, and the first frame any model imagines [default: {D.train.history}].")] = None,
    include_current: Annotated[Optional[bool], typer.Option("--include-current/--previous-only", help="End the window at the predicted frame's own sample [default: previous only, as the paper].", show_default=False)] = None,
    latent: Annotated[Optional[int], typer.Option(help=f"Latent features of the autoencoder [default: {D.train.latent}].")] = None,
    seed: Annotated[Optional[int], typer.Option(help=f"Seed of initialisation and shuffling [default: {D.train.seed}].")] = None,
    minutes: Annotated[Optional[float], typer.Option(help="Fit the schedules into this many minutes of training, measured on this machine (sets train.max_steps_*; not reproducible elsewhere).")] = None,
    device: Annotated[Optional[str], typer.Option("--device", help=f"{DEVICE_HELP} [default: {D.train.device}].")] = None,
    resume: Annotated[bool, typer.Option("--resume", help="Continue the interrupted run saved in --out.")] = False,
    spawn: Annotated[bool, typer.Option("--spawn", help="Open a Rerun viewer with live losses and a held-out clip.")] = False,
    rrd: Annotated[Optional[Path], typer.Option("--rrd", help="Save the live view to this .rrd file.")] = None,
    force: Force = False,
    quiet: Quiet = False,
) -> None:
    """Train the autoencoder and the latent model on recordings; print held-out metrics beside baselines.

    \b
    Example: softarm train recordings/seed0.mcap --rrd recordings/train.rrd
    """
    from softarm.learn.training import train as run_training

    overrides = {"train.epochs_ae": epochs_ae, "train.epochs_lstm": epochs_lstm, "train.model": model, "train.history": history,
                 "train.inputs": [name.strip() for name in inputs.split(",")] if inputs else None,
                 "train.include_current": include_current, "train.latent": latent, "train.seed": seed,
                 "train.device": device}
    cfg = run_or_exit(lambda: load_config(config, overrides))
    with StagedProgress(err, TRAINING_STAGES, quiet=quiet, log=out) as staged:
        result = run_or_exit(lambda: run_training(recordings, cfg, out_path, resume=resume, force=force, spawn=spawn,
                                                  rrd=rrd, minutes=minutes, inputs=[config] if config else [],
                                                  progress=lambda done, total, losses: staged("training", done, total,
                                                                                              losses),
                                                  stages=lambda stage, done, total: staged(stage, done, total)))
    if not result.complete:
        if result.saved:
            stop_interrupted(f"interrupted: {result.checkpoint} holds the last finished epoch; continue with softarm "
                             f"train {' '.join(map(str, recordings))} --out {result.checkpoint} --resume")
        earlier = f"; {result.checkpoint} is still the earlier run's" if result.checkpoint.exists() else ""
        stop_interrupted(f"interrupted before the first epoch finished: nothing was written{earlier}")
    if not quiet:
        out.print(metrics_table(result.metrics))
        say(f"checkpoint {result.checkpoint} (reads {', '.join(result.metrics['inputs'])}), "
            f"metrics {result.metrics_path}, {result.wall_seconds:.0f} s")


def adapt(
    checkpoint: Checkpoint,
    recording: Annotated[Path, typer.Argument(metavar="RECORDING", help="Recording (.mcap) after a lasting change of the body (a load, damage).")],
    seconds: Annotated[float, typer.Option("--seconds", "-s", help="Seconds of camera to adapt on.")],
    out_path: Annotated[Path, typer.Option("--out", "-o", help="The adapted checkpoint.")],
    start: Annotated[Optional[float], typer.Option("--from", metavar="SECONDS", help="When the camera turns on [default: the recording's first lasting disturbance, else the surprise's first alarm].")] = None,
    device: Device = "auto",
    force: Force = False,
    quiet: Quiet = False,
) -> None:
    """Learn a changed body from a few seconds of camera: fine-tune the latent model (and refit the surprise's
    forward model) on them, then imagine the rest of the recording with the camera off, before and after.

    \b
    Example: softarm adapt recordings/general.pt recordings/payload.mcap --seconds 5 --out recordings/adapted.pt
    """
    from softarm.learn.adapt import adapt as run_adapt

    result = run_or_exit(lambda: run_adapt(checkpoint, recording, seconds, out_path, start=start, force=force,
                                           device=device))
    m = result.metrics
    if not quiet:
        say(f"adapted on {m['camera_frames']} frames from {m['from_s']:.2f} s in {m['adapt_seconds']:.2f} s; the rest "
            f"({m['rest_frames']} frames, camera off): IoU {m['rest_iou']['before']:.3f} before, "
            f"{m['rest_iou']['after']:.3f} after; checkpoint {result.checkpoint}")
