"""The live view of `softarm train`: loss curves and, each epoch, a held-out clip side by side.

Losses are points on the sequence timeline `step` (optimisation steps over both networks, so the
latent model's curve continues after the autoencoder's). Each clip is three image entities, `clip/truth`,
`clip/reconstruction` and `clip/imagination`, on the timelines `clip_time` (seconds into the clip)
and `step`. It logs; it computes nothing.
"""

from __future__ import annotations

from pathlib import Path
from types import TracebackType

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from softarm.view.images import probability_bytes
from softarm.view.stream import RerunStream, send_images

CLIPS = ("truth", "reconstruction", "imagination")


def blueprint() -> rrb.Blueprint:
    """The three clips side by side on top, so one glance compares them; the loss curves below."""
    return rrb.Blueprint(
        rrb.Vertical(
            rrb.Horizontal(*(rrb.Spatial2DView(origin=f"clip/{name}", name=name) for name in CLIPS)),
            rrb.TimeSeriesView(origin="loss", name="losses"),
            row_shares=[3, 2],
        ),
    )


class TrainingView:
    """Implements softarm.learn.observer.TrainingObserver on a Rerun stream (a viewer, an .rrd, or both)."""

    def __init__(self, spawn: bool = False, rrd: Path | None = None, application_id: str = "softarm-train"):
        self._stream = RerunStream(application_id, blueprint(), rrd=rrd, spawn=spawn)
        self._rec = self._stream.rec
        self._closed = False

    def loss(self, name: str, step: int, value: float) -> None:
        """One point of the curve `loss/<name>` (e.g. ae_train, ae_test, latent_train, latent_val) at `step`."""
        self._rec.set_time("step", sequence=step)
        self._rec.log(f"loss/{name}", rr.Scalars(float(value)))

    def clip(self, step: int, times: np.ndarray, truth: np.ndarray, reconstruction: np.ndarray,
             imagination: np.ndarray | None) -> None:
        """A held-out clip: three (T, H, W) arrays in [0, 1] at `times` (T,) seconds.

        Sent column-wise (one chunk per entity instead of one message per frame), so a long clip costs
        three calls. In the viewer, `clip_time` plays the newest clip and `step` steps through them.
        """
        times = np.asarray(times, np.float64)
        indexes = [rr.TimeColumn("step", sequence=np.full(len(times), step, np.int64)),
                   rr.TimeColumn("clip_time", duration=times)]
        for name, frames in zip(CLIPS, (truth, reconstruction, imagination)):
            if frames is None:  # e.g. no imagination before the latent model is trained
                continue
            frames = np.asarray(frames)
            if frames.ndim != 3 or len(frames) != len(times):
                raise ValueError(f"clip/{name}: expected ({len(times)}, H, W) frames, got shape {frames.shape}")
            send_images(self._rec, f"clip/{name}", indexes, probability_bytes(frames))

    def close(self) -> None:
        if not self._closed:
            self._closed = True
            self._stream.close()

    def __enter__(self) -> TrainingView:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()

