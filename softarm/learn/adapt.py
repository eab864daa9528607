"""`softarm adapt` as one call: a checkpoint, a recording after a lasting change, S seconds of its camera; the
adapted checkpoint, and the imagination of the rest of the recording (camera off) before and after.

The camera is on from `start` (s): by default the start of the recording's first lasting disturbance where it
lists one (a simulated load or damage), else the first alarm of the checkpoint's surprise: the arm feels that
its body changed and looks. Torch loads when `adapt()` first runs.
"""

import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Optional, Union

import numpy as np

from softarm.errors import CheckpointError, ConfigError, RecordingError
from softarm.files import check_outputs, claimed, input_file, made_folders
from softarm.interrupt import Escalated, Interrupted, Stopped, stop_on_signal

PathLike = Union[str, Path]


@dataclass(frozen=True)
class AdaptResult:
    checkpoint: Path
    metrics: dict[str, Any]   # the window, the time it took, and the rest's IoU before and after


def adapt(checkpoint: PathLike, recording: PathLike, seconds: float, out: PathLike, start: Optional[float] = None,
          force: bool = False, device: str = "auto") -> AdaptResult:
    """Fine-tune the latent models to `seconds` of `recording`'s camera from `start` on `device` and save the
    result in `out`."""
    if not (np.isfinite(seconds) and seconds > 0):
        raise ConfigError(f"--seconds {seconds:g}: give a finite, positive number of seconds of camera")
    from softarm.record.reader import read_model

    check_outputs([Path(out)], force, inputs=[checkpoint, recording])
    input_file(checkpoint, "checkpoint", CheckpointError)  # missing inputs are refused before torch loads
    read_model(recording)
    from softarm.imagine.trained import TrainedModel  # torch loads here, not when softarm is imported

    try:
        with stop_on_signal() as caught:
            return _adapt(TrainedModel(checkpoint, device), recording, seconds, Path(out), start, lambda: bool(caught))
    except Stopped:  # the checkpoint is written whole at the end, so nothing was
        raise Interrupted(f"nothing was written to {out}") from None
    except Escalated:
        raise Escalated(f"stopped at once by a second stop request; nothing was written to {out}") from None


def _adapt(model: Any, recording: PathLike, seconds: float, out: Path, start: Optional[float],
           stop: Callable[[], bool]) -> AdaptResult:
    """Adapt and save, once the inputs and output are checked; `stop()` ends it (Stopped) before the save."""
    from softarm.learn.finetune import Window, adapt_models
    from softarm.model.checkpoint import save_checkpoint
    from softarm.model.metrics import iou_per_frame

    reading = model.read(recording)
    rec, imaginer = reading.recording, model.imaginer
    before = imaginer.predict(reading.inputs)
    begin = camera_start(rec.model, rec.times, before, imaginer, start)
    end = begin + int(round(seconds / rec.frame_dt))
    if end >= len(rec.times) - 1:
        raise RecordingError(f"{rec.path}: {seconds:g} s of camera from {rec.times[begin]:.2f} s reach past its end "
                             f"({rec.times[-1]:.2f} s); give fewer --seconds or an earlier --from")
    clock = time.perf_counter()
    adapted = adapt_models(imaginer,
                           Window(begin, end, imaginer.normalised(reading.inputs).astype(np.float64), rec.frames), stop)
    took = time.perf_counter() - clock
    after = adapted.predict(reading.inputs)
    rest = (before.targets >= end) & rec.seen[before.targets]
    truth = rec.frames[before.targets[rest]]
    scores = {name: float(iou_per_frame(im.decode(p.latents[rest]), truth).mean())
              for name, im, p in (("before", imaginer, before), ("after", adapted, after))}
    metrics = {"recording": str(rec.path), "from_s": float(rec.times[begin]), "seconds": float(seconds),
               "camera_frames": int(end - begin), "adapt_seconds": took, "rest_frames": int(rest.sum()),
               "rest_iou": scores}
    state = dict(model.state)
    state["latent_model"] = adapted.latent.state_dict()
    state["members"] = [m.state_dict() for m in adapted.members]
    if adapted.surprise is not None:
        state["surprise"] = adapted.surprise.to_state()
    state["adaptation"] = metrics
    if stop():
        raise Stopped()
    outputs = [Path(out)]
    with made_folders(outputs), claimed(outputs):
        save_checkpoint(out, {k: v for k, v in state.items() if k != "format"})
    return AdaptResult(Path(out), metrics)


def camera_start(model: dict[str, Any], times: np.ndarray, prediction: Any, imaginer: Any,
                 start: Optional[float]) -> int:
    """The frame the camera turns on at: `start`, else the first lasting disturbance, else the first alarm."""
    if start is None:
        lasting = [float(d["start"]) for d in model.get("disturbances", []) if d.get("end") is None]
        start = min(lasting) if lasting else first_alarm(prediction, imaginer, times)
    if not (np.isfinite(start) and times[0] <= start < times[-1]):
        raise ConfigError(f"--from {start:g}: give a time within the recording ({times[0]:.2f}-{times[-1]:.2f} s)")
    return int(np.searchsorted(times, start - 1e-9))


def first_alarm(prediction: Any, imaginer: Any, times: np.ndarray) -> float:
    if prediction.surprise is None or imaginer.surprise is None:
        raise ConfigError("the recording lists no lasting disturbance and the checkpoint has no surprise model: "
                          "give --from SECONDS, when the camera turns on")
    alarms = np.flatnonzero(np.nan_to_num(prediction.surprise) > imaginer.surprise.threshold)
    if not len(alarms):
        raise ConfigError("the recording lists no lasting disturbance and its surprise never raised the alarm: "
                          "give --from SECONDS, when the camera turns on")
    return float(times[prediction.targets[alarms[0]]])
