"""`softarm train` as one call: check the outputs, train (or resume), evaluate, write checkpoint and metrics.

Light to import: torch loads when `train()` first runs.
"""

import json
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Optional, Sequence, Union

from softarm.config import Config, load_config
from softarm.errors import CheckpointError, ConfigError, OutputError, RecordingError
from softarm.files import check_outputs, write_json
from softarm.interrupt import stop_on_signal
from softarm.learn.observer import Progress, open_observer
from softarm.model.registry import check_latent_model

DEFAULT_FOLDER = Path("recordings")
PathLike = Union[str, Path]


@dataclass(frozen=True)
class TrainResult:
    checkpoint: Path
    metrics_path: Optional[Path]
    metrics: Optional[dict[str, Any]]
    complete: bool
    wall_seconds: float


def expand_folders(recordings: Sequence[PathLike]) -> list[Path]:
    """A folder stands for the recordings its corpus.json lists (a corpus), or else every recording in it,
    sorted by name."""
    out: list[Path] = []
    for path in map(Path, recordings):
        found = folder_recordings(path) if path.is_dir() else [path]
        if not found:
            raise RecordingError(f"{path} holds no recordings (.mcap files)")
        out.extend(found)
    return out


def folder_recordings(folder: Path) -> list[Path]:
    manifest = folder / "corpus.json"
    if manifest.is_file():
        groups = json.loads(manifest.read_text()).get("groups", {})
        return sorted(folder / name for group in groups.values() for name in group["recordings"])
    return sorted(p for p in folder.glob("*.mcap") if p.is_file())


def default_checkpoint(recordings: Sequence[PathLike]) -> Path:
    """recordings/<first recording's (or folder's) stem>.pt"""
    return DEFAULT_FOLDER / f"{Path(recordings[0]).stem}.pt"


def metrics_path_for(checkpoint: Path) -> Path:
    """The metrics JSON sits beside its checkpoint: model.pt -> model.metrics.json."""
    return checkpoint.with_suffix(".metrics.json")


def check_train_outputs(checkpoint: Path, rrd: Optional[PathLike], resume: bool, force: bool) -> None:
    """Refuse before any work: a checkpoint that exists (unless resume or force), nothing to resume, bad folders."""
    checkpoint = Path(checkpoint)
    if resume and not checkpoint.exists():
        raise CheckpointError(f"--resume: there is no checkpoint {checkpoint} to continue")
    if checkpoint.exists() and not (resume or force):
        raise OutputError(f"checkpoint {checkpoint} already exists; pass --resume to continue it or --force to replace it")
    check_outputs([checkpoint, metrics_path_for(checkpoint)], force=True)  # folders and permissions
    if rrd is not None:
        check_outputs([Path(rrd)], force)


def train(recordings: Sequence[PathLike], config: Optional[Config] = None, out: Optional[PathLike] = None,
          resume: bool = False, force: bool = False, rrd: Optional[PathLike] = None, spawn: bool = False,
          progress: Optional[Progress] = None, stop: Callable[[], bool] = lambda: False,
          minutes: Optional[float] = None) -> TrainResult:
    """Train (or with resume, continue) on recordings; write the checkpoint and, at the end, its metrics JSON.

    `minutes` fits a new run's schedules into that wall-clock budget (softarm.learn.budget). `rrd` saves and
    `spawn` shows a live Rerun view. Ctrl-C (or SIGTERM, or `stop()` returning True)
    ends training within a batch; the checkpoint of the last finished epoch stays (`complete` False).
    """
    start = time.perf_counter()
    if minutes is not None and minutes <= 0:
        raise ConfigError(f"--minutes {minutes:g}: give a positive budget")
    config = config if config is not None else load_config()
    check_latent_model(config.train.model)  # an unknown model is refused before any work
    out = Path(out) if out is not None else default_checkpoint(recordings)
    recordings = expand_folders(recordings)
    check_train_outputs(out, rrd, resume, force)
    from softarm.learn.evaluate import evaluate, fit_baselines  # torch loads here, not when softarm is imported
    from softarm.learn.train import fit
    from softarm.learn.train_state import start_state

    with tempfile.TemporaryDirectory(prefix=f".{out.stem}-frames-", dir=out.parent) as cache:
        state = start_state(recordings, config, out, resume, Path(cache) if len(recordings) > 1 else None)
        if minutes is not None and not resume:
            from softarm.learn.budget import fit_to_minutes

            fit_to_minutes(state, minutes, time.perf_counter() - start)
        with open_observer(rrd, spawn) as observer, stop_on_signal() as caught:
            complete = fit(state, out, observer, progress or (lambda *_: None), lambda: bool(caught) or stop())
        if not complete:
            return TrainResult(out, None, None, False, time.perf_counter() - start)
        baselines = fit_baselines(state)
        metrics = evaluate(state, baselines)
        state.save(out, metrics, baselines)
    metrics_file = write_json(metrics_path_for(out), metrics)
    return TrainResult(out, metrics_file, metrics, True, time.perf_counter() - start)
