"""`softarm train` as one call: check the inputs and outputs, train (or resume), evaluate, write the checkpoint
and its metrics.

Light to import: torch loads when `train()` first runs. A stop request (Ctrl-C, SIGTERM, SIGHUP) is honoured
from the first moment: while the recordings are read it ends the run with nothing written, later it keeps the
last finished epoch.
"""

import math
import time
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Optional, Sequence, Union

from softarm.config import Config, load_config, override
from softarm.corpus.manifest import folder_recordings
from softarm.errors import CheckpointError, ConfigError, OutputError, RecordingError
from softarm.files import check_outputs, claimed, made_folders, part_path, write_json
from softarm.interrupt import Stopped, stop_on_signal
from softarm.learn.observer import Progress, StageProgress, open_observer
from softarm.registry import check_inputs, check_latent_model

DEFAULT_FOLDER = Path("recordings")
PathLike = Union[str, Path]


@dataclass(frozen=True)
class TrainResult:
    checkpoint: Path
    metrics_path: Optional[Path]
    metrics: Optional[dict[str, Any]]
    complete: bool
    wall_seconds: float
    saved: bool = True   # the checkpoint is this run's (False: stopped before its first epoch ended, nothing written)


def expand_folders(recordings: Sequence[PathLike]) -> tuple[list[Path], list[Path]]:
    """The recordings to read, a folder standing for its corpus's (or else for every recording in it), and
    the folders' own files that are read too (their manifests)."""
    out, manifests = [], []
    for path in map(Path, recordings):
        found, read = folder_recordings(path) if path.is_dir() else ([path], [])
        if not found:
            raise RecordingError(f"{path} holds no recordings (.mcap files)")
        out.extend(found)
        manifests.extend(read)
    return out, manifests


def default_checkpoint(recordings: Sequence[PathLike]) -> Path:
    """recordings/<first recording's (or folder's) stem>.pt"""
    return DEFAULT_FOLDER / f"{Path(recordings[0]).stem}.pt"


def metrics_path_for(checkpoint: Path) -> Path:
    """The metrics JSON sits beside its checkpoint: model.pt -> model.metrics.json."""
    return checkpoint.with_suffix(".metrics.json")


def train_outputs(checkpoint: Path, rrd: Optional[PathLike]) -> list[Path]:
    return [checkpoint, metrics_path_for(checkpoint), *([Path(rrd)] if rrd is not None else [])]


def check_train_outputs(checkpoint: Path, rrd: Optional[PathLike], resume: bool, force: bool,
                        inputs: Sequence[PathLike] = ()) -> None:
    """Refuse before any work: a checkpoint that is a folder or exists (unless resume or force), nothing to
    resume, outputs that are one file or an input, folders that cannot be written."""
    checkpoint = Path(checkpoint)
    if checkpoint.is_dir():
        raise OutputError(f"--out {checkpoint} is a folder; give a checkpoint file name, "
                          f"e.g. {checkpoint / 'model.pt'}")
    if resume and not checkpoint.exists():
        raise CheckpointError(f"--resume: there is no checkpoint {checkpoint} to continue")
    if checkpoint.exists() and not (resume or force):
        raise OutputError(f"checkpoint {checkpoint} already exists; "
                          f"pass --resume to continue it or --force to replace it")
    check_outputs(train_outputs(checkpoint, rrd), force=True, inputs=inputs)
    if rrd is not None and Path(rrd).exists() and not force:
        raise OutputError(f"output {rrd} already exists; pass --force to overwrite it")
    unfinished = [part_path(p) for p in train_outputs(checkpoint, rrd) if part_path(p).exists()]
    if unfinished and not force:  # the same rule as every output's: an earlier run's .part goes only with --force
        raise OutputError(f"{unfinished[0]} holds an earlier run's unfinished file: move it away, or pass --force to "
                          "replace it")


def check_minutes(minutes: Optional[float]) -> None:
    if minutes is not None and not (math.isfinite(minutes) and minutes > 0):
        raise ConfigError(f"--minutes {minutes:g}: give a finite, positive budget in minutes")


def train(recordings: Sequence[PathLike], config: Optional[Config] = None, out: Optional[PathLike] = None,
          resume: bool = False, force: bool = False, rrd: Optional[PathLike] = None, spawn: bool = False,
          progress: Optional[Progress] = None, stop: Callable[[], bool] = lambda: False,
          minutes: Optional[float] = None, inputs: Sequence[PathLike] = (),
          stages: Optional[StageProgress] = None) -> TrainResult:
    """Train (or with resume, continue) on recordings; write the checkpoint and, at the end, its metrics JSON.

    `minutes` fits a new run's schedules into that wall-clock budget (softarm.learn.budget). `rrd` saves and
    `spawn` shows a live Rerun view. Ctrl-C (or SIGTERM, SIGHUP, or `stop()` returning True) ends training
    within a batch; the checkpoint of the last finished epoch stays (`complete` False). `inputs` (a config
    file, say) are files besides the recordings that no output may replace. `progress` hears of the
    optimisation steps, `stages` of the work before and after them: the recordings read ("reading") and the
    fits and scores after training ("fitting": the surprise, the baselines, the confidence, the metrics).
    """
    from softarm.record.reader import read_model

    start = time.perf_counter()
    check_minutes(minutes)
    config = config if config is not None else load_config()
    check_latent_model(config.train.model)  # an unknown model or input is refused before any work
    check_inputs(list(config.train.inputs))
    out = Path(out) if out is not None else default_checkpoint(recordings)
    recordings, manifests = expand_folders(recordings)
    check_train_outputs(out, rrd, resume, force, [*recordings, *manifests, *inputs])
    for recording in recordings:  # a missing, foreign or damaged one is refused before torch loads (metadata only)
        read_model(recording)
    outputs = train_outputs(out, rrd)
    try:
        with stop_on_signal() as caught, made_folders(outputs), claimed(outputs):
            return _train(recordings, config, out, resume, rrd, spawn, progress, stages or (lambda *_: None),
                          lambda: bool(caught) or stop(), minutes, start)
    except Stopped:  # while the recordings were read: nothing was written, and no folder made for it is left
        return TrainResult(out, None, None, False, time.perf_counter() - start, saved=False)


def _train(recordings: list[Path], config: Config, out: Path, resume: bool, rrd: Optional[PathLike], spawn: bool,
           progress: Optional[Progress], stages: StageProgress, stop: Callable[[], bool], minutes: Optional[float],
           start: float) -> TrainResult:
    """Read, fit, evaluate and save, once every input and output is checked and held."""
    from softarm.learn.evaluate import fit_baselines, training_metrics  # torch loads here, not when softarm is imported
    from softarm.learn.loop import fit
    from softarm.learn.train_state import start_state
    from softarm.learn.trust_fits import fit_calibration, fit_surprise_of

    if not resume:
        metrics_path_for(out).unlink(missing_ok=True)  # it described the checkpoint this run replaces
    state = start_state(recordings, config, out, resume, stop, lambda done, total: stages("reading", done, total))
    if state.config.train.precision == "auto":  # chosen once, by measuring; the checkpoint keeps the choice
        from softarm.learn.step_times import fastest_precision

        state.config = override(state.config, {"train.precision": fastest_precision(state)})
    elif state.phase != "done":  # steps to run: in an arithmetic this chip has
        from softarm.learn.precision import require_native

        require_native(state.config.train.precision, state.device)
    if minutes is not None and resume:
        warnings.warn(f"--minutes {minutes:g} is ignored with --resume: the saved run keeps its own schedule",
                      stacklevel=3)
    elif minutes is not None:
        from softarm.learn.budget import fit_to_minutes

        fit_to_minutes(state, minutes, time.perf_counter() - start)
    with open_observer(rrd, spawn) as observer:
        complete = fit(state, out, observer, progress or (lambda *_: None), stop)
    if not complete:
        return TrainResult(out, None, None, False, time.perf_counter() - start, saved=resume or state.saves > 0)
    stages("fitting", 0, 4)
    state.surprise = fit_surprise_of(state)
    stages("fitting", 1, 4)
    state.baselines = fit_baselines(state)
    stages("fitting", 2, 4)
    state.calibration = fit_calibration(state)
    stages("fitting", 3, 4)
    metrics = training_metrics(state)
    stages("fitting", 4, 4)
    state.save(out, metrics)
    metrics_file = write_json(metrics_path_for(out), metrics)
    return TrainResult(out, metrics_file, metrics, True, time.perf_counter() - start)
