"""Rerun views: the live view of `softarm train` and replay timelines. The only softarm module that
imports rerun: it logs, it computes nothing.

Losses are points on the sequence timeline `step`. Each epoch's held-out clip is three image entities,
`clip/truth`, `clip/reconstruction` and `clip/imagination`, on two timelines: `clip_time` (seconds into
the clip) and `epoch`. An .rrd is written as `<name>.part` and renamed on close, so a path without
`.part` is always a whole file that `rerun rrd verify` accepts.
"""

from __future__ import annotations

import warnings
from pathlib import Path
from types import TracebackType
from typing import TYPE_CHECKING

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from softarm.replay import DIFFERENCE_CLASSES, DIFFERENCE_COLOURS, difference_codes, probability_bytes

if TYPE_CHECKING:
    from softarm.replay import Replay

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
    """Live view of `softarm train`: loss curves and, each epoch, a held-out clip: truth | reconstruction | imagination."""

    def __init__(self, spawn: bool = False, rrd: Path | None = None, application_id: str = "softarm-train"):
        # A stream of our own, not rerun's global one, so that nothing else in the process logs into it.
        # With neither a viewer nor a file it is disabled: a bare stream would buffer everything in memory.
        self.rrd = Path(rrd) if rrd is not None else None
        self.part = self.rrd.with_name(self.rrd.name + ".part") if self.rrd is not None else None
        self._closed = not (spawn or rrd is not None)  # nothing to log to: every call is a no-op, no stream is made
        if self._closed:
            return
        self._rec = rr.RecordingStream(application_id)
        sinks: list[rr.GrpcSink | rr.FileSink] = []
        if spawn:
            self._rec.spawn(connect=False)  # start the viewer; the GrpcSink below connects to its default port
            sinks.append(rr.GrpcSink())
        if self.part is not None:
            sinks.append(rr.FileSink(self.part))
        # One call for both: a later save() or connect_grpc() would replace the earlier sink.
        self._rec.set_sinks(*sinks, default_blueprint=blueprint())

    def loss(self, name: str, step: int, value: float) -> None:
        """One point of the curve `loss/<name>` (e.g. ae_train, ae_test, lstm_train, lstm_val) at `step`."""
        if self._closed:
            return
        self._rec.set_time("step", sequence=step)
        self._rec.log(f"loss/{name}", rr.Scalars(float(value)))

    def clip(self, epoch: int, times: np.ndarray, truth: np.ndarray, reconstruction: np.ndarray,
             imagination: np.ndarray | None) -> None:
        """One epoch's held-out clip: three (T, H, W) arrays in [0, 1] at `times` (T,) seconds.

        Sent column-wise (one chunk per entity instead of one message per frame), so a long clip costs
        three calls. In the viewer, the timeline `clip_time` plays the newest epoch's clip and `epoch`
        steps through the epochs (showing each clip's last frame).
        """
        if self._closed:
            return
        times = np.asarray(times, np.float64)
        indexes = [rr.TimeColumn("epoch", sequence=np.full(len(times), epoch, np.int64)),
                   rr.TimeColumn("step", sequence=np.full(len(times), epoch, np.int64)),
                   rr.TimeColumn("clip_time", duration=times)]
        for name, frames in zip(CLIPS, (truth, reconstruction, imagination)):
            if frames is None:  # e.g. no imagination before the LSTM is trained
                continue
            frames = np.asarray(frames)
            if frames.ndim != 3 or len(frames) != len(times):
                raise ValueError(f"clip/{name}: expected ({len(times)}, H, W) frames, got shape {frames.shape}")
            pixels = probability_bytes(frames)
            count, height, width = pixels.shape
            image_format = rr.components.ImageFormat(width=width, height=height, color_model="L",
                                                     channel_datatype="U8")
            self._rec.send_columns(f"clip/{name}", indexes=indexes, columns=rr.Image.columns(
                buffer=pixels.reshape(count, -1), format=[image_format] * count))

    def close(self) -> None:
        """Flush, finish the file (its footer is written when the sink is dropped) and give it its final name."""
        if self._closed:
            return
        self._closed = True
        try:
            self._rec.flush()
        except RuntimeError as e:  # the viewer was closed or never came up; the file must still be finished
            warnings.warn(f"rerun viewer unreachable, it may lack the end of the run: {e}", stacklevel=2)
        self._rec.disconnect()  # drops the sinks: the FileSink writes its footer and closes the file
        if self.part is not None and self.part.exists():
            self.part.replace(self.rrd)

    def __enter__(self) -> TrainingView:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()


IMAGES = ("camera", "imagined", "difference", "fused")


def replay_blueprint() -> rrb.Blueprint:
    """Camera | imagined | difference | fused on top; stretch, excitation and IoU below, on sim_time."""
    return rrb.Blueprint(
        rrb.Vertical(
            rrb.Horizontal(*(rrb.Spatial2DView(origin=name, name=name) for name in IMAGES)),
            rrb.Horizontal(rrb.TimeSeriesView(origin="signals/stretch", name="stretch (m)"),
                           rrb.TimeSeriesView(origin="signals/excitation", name="excitation (m)"),
                           rrb.TimeSeriesView(origin="signals/iou", name="imagination IoU")),
            row_shares=[3, 2],
        ),
        rrb.TimePanel(timeline="sim_time"),
    )


def _image_columns(rec: rr.RecordingStream, entity: str, times: rr.TimeColumn, pixels: np.ndarray) -> None:
    count, height, width = pixels.shape[:3]
    model = "L" if pixels.ndim == 3 else "RGB"
    image_format = rr.components.ImageFormat(width=width, height=height, color_model=model, channel_datatype="U8")
    rec.send_columns(entity, indexes=[times], columns=rr.Image.columns(buffer=pixels.reshape(count, -1),
                                                                       format=[image_format] * count))


def log_replay(result: "Replay", rrd: Path | None = None, spawn: bool = False) -> Path | None:
    """Write a replay as an .rrd (atomically, via .part) and/or show it in a spawned viewer."""
    if rrd is None and not spawn:
        return None
    rec = rr.RecordingStream("softarm-replay")
    sinks: list[rr.GrpcSink | rr.FileSink] = []
    if spawn:
        rec.spawn(connect=False)
        sinks.append(rr.GrpcSink())
    part = Path(rrd).with_name(Path(rrd).name + ".part") if rrd is not None else None
    if part is not None:
        sinks.append(rr.FileSink(part))
    rec.set_sinks(*sinks, default_blueprint=replay_blueprint())
    try:
        times = rr.TimeColumn("sim_time", duration=result.times)
        truth = result.recording.frames
        _image_columns(rec, "camera/image", times, truth * np.uint8(255))
        _image_columns(rec, "imagined/image", times, result.imagined_bytes)
        rec.log("difference", rr.AnnotationContext([(i, name, tuple(int(c) for c in colour)) for i, (name, colour)
                                                    in enumerate(zip(DIFFERENCE_CLASSES, DIFFERENCE_COLOURS))]),
                static=True)
        codes = difference_codes(truth, result.imagined)  # one byte a pixel; the viewer colours the classes
        fmt = rr.components.ImageFormat(width=codes.shape[2], height=codes.shape[1], channel_datatype="U8")
        rec.send_columns("difference/image", indexes=[times], columns=rr.SegmentationImage.columns(
            buffer=codes.reshape(len(codes), -1), format=[fmt] * len(codes)))
        _image_columns(rec, "fused/image", times, probability_bytes(result.fused))
        nodes = result.nodes_px
        if nodes is not None:
            rec.send_columns("camera/nodes", indexes=[times], columns=rr.Points2D.columns(
                positions=nodes.reshape(-1, 2)).partition([nodes.shape[1]] * len(nodes)))
        for i in range(result.recording.stretch.shape[1]):
            rec.send_columns(f"signals/stretch/{i}", indexes=[times],
                             columns=rr.Scalars.columns(scalars=result.recording.stretch[:, i]))
        rec.send_columns("signals/excitation", indexes=[times],
                         columns=rr.Scalars.columns(scalars=result.recording.displacement))
        seen = result.predicted
        rec.send_columns("signals/iou", indexes=[rr.TimeColumn("sim_time", duration=result.times[seen])],
                         columns=rr.Scalars.columns(scalars=result.iou[seen]))
        rec.send_columns("signals/blind", indexes=[times], columns=rr.Scalars.columns(
            scalars=result.blind.astype(np.float64)))
        rec.flush()
    except BaseException:
        rec.disconnect()
        if part is not None:
            part.unlink(missing_ok=True)
        raise
    rec.disconnect()
    if part is not None and part.exists():
        part.replace(rrd)
    return Path(rrd) if rrd is not None else None
