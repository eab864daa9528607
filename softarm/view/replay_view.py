"""The replay timeline in Rerun: camera (with the arm's nodes) | imagined | difference | fused on top,
the input channels (the stretch), excitation and per-frame IoU below, all on the `sim_time` timeline. It logs;
`softarm.imagine` computed everything."""

from pathlib import Path
from typing import Any, Optional

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from softarm.view.images import DIFFERENCE_CLASSES, DIFFERENCE_COLOURS, difference_codes, probability_bytes
from softarm.view.stream import RerunStream, send_images

IMAGES = ("camera", "imagined", "difference", "fused")


def replay_blueprint(channels: list[str]) -> rrb.Blueprint:
    """Camera | imagined | difference | fused on top; every input channel, the excitation, IoU and confidence
    below, on sim_time."""
    return rrb.Blueprint(
        rrb.Vertical(
            rrb.Horizontal(*(rrb.Spatial2DView(origin=name, name=name) for name in IMAGES)),
            rrb.Horizontal(*(rrb.TimeSeriesView(origin=f"signals/{name}", name=f"{name} (input)") for name in channels),
                           rrb.TimeSeriesView(origin="signals/excitation", name="excitation (m)"),
                           rrb.TimeSeriesView(origin="signals/iou", name="imagination IoU"),
                           rrb.TimeSeriesView(origin="signals/confidence", name="confidence")),
            row_shares=[3, 2],
        ),
        rrb.TimePanel(timeline="sim_time"),
    )


def log_replay(result: Any, rrd: Optional[Path] = None, spawn: bool = False,
               imagined_bytes: Optional[np.ndarray] = None) -> Optional[Path]:
    """Write a replay (`softarm.imagine.replay_data.Replay`) as an .rrd and/or show it in a spawned viewer.

    `imagined_bytes` (the imagined frames as grey bytes) may be passed when another writer made them already.
    """
    if rrd is None and not spawn:
        return None
    stream = RerunStream("softarm-replay", replay_blueprint([name for name, _ in result.channels]), rrd=rrd,
                         spawn=spawn)
    try:
        _log_images(stream.rec, result, imagined_bytes)
        _log_signals(stream.rec, result)
    except BaseException:
        stream.discard()
        raise
    return stream.close()


def _log_images(rec: rr.RecordingStream, result: Any, imagined_bytes: Optional[np.ndarray]) -> None:
    times = [rr.TimeColumn("sim_time", duration=result.times)]
    seen = result.recording.seen  # a camera's gaps: the viewer keeps showing its last frame
    seen_times = [rr.TimeColumn("sim_time", duration=result.times[seen])]
    truth = result.recording.frames[seen]
    send_images(rec, "camera/image", seen_times, truth * np.uint8(255))
    send_images(rec, "imagined/image", times,
                imagined_bytes if imagined_bytes is not None else probability_bytes(result.imagined))
    rec.log("difference", rr.AnnotationContext([(i, name, tuple(int(c) for c in colour)) for i, (name, colour)
                                                in enumerate(zip(DIFFERENCE_CLASSES, DIFFERENCE_COLOURS))]),
            static=True)
    codes = difference_codes(truth, result.imagined[seen])  # one byte a pixel; the viewer colours the classes
    fmt = rr.components.ImageFormat(width=codes.shape[2], height=codes.shape[1], channel_datatype="U8")
    rec.send_columns("difference/image", indexes=seen_times, columns=rr.SegmentationImage.columns(
        buffer=codes.reshape(len(codes), -1), format=[fmt] * len(codes)))
    send_images(rec, "fused/image", times, probability_bytes(result.fused))
    nodes = result.nodes_px
    if nodes is not None:
        rec.send_columns("camera/nodes", indexes=times, columns=rr.Points2D.columns(
            positions=nodes.reshape(-1, 2)).partition([nodes.shape[1]] * len(nodes)))


def _log_signals(rec: rr.RecordingStream, result: Any) -> None:
    times = [rr.TimeColumn("sim_time", duration=result.times)]
    column = 0
    for name, width in result.channels:  # what the imagination read: the sensors' imperfections included
        for i in range(width):
            rec.send_columns(f"signals/{name}/{i}", indexes=times,
                             columns=rr.Scalars.columns(scalars=result.inputs[:, column + i]))
        column += width
    if result.recording.displacement is not None:  # an imported log may have no drive
        rec.send_columns("signals/excitation", indexes=times,
                         columns=rr.Scalars.columns(scalars=result.recording.displacement))
    seen = result.predicted
    imagined_times = [rr.TimeColumn("sim_time", duration=result.times[seen])]
    rec.send_columns("signals/iou", indexes=imagined_times, columns=rr.Scalars.columns(scalars=result.iou[seen]))
    rec.send_columns("signals/confidence", indexes=imagined_times,
                     columns=rr.Scalars.columns(scalars=result.confidence[seen]))
    if np.isfinite(result.surprise).any():  # a checkpoint with a forward model (docs/model.md, Surprise)
        felt = seen & np.isfinite(result.surprise)
        felt_times = [rr.TimeColumn("sim_time", duration=result.times[felt])]
        rec.send_columns("signals/surprise", indexes=felt_times,
                         columns=rr.Scalars.columns(scalars=result.surprise[felt]))
        rec.send_columns("signals/alarm", indexes=imagined_times,
                         columns=rr.Scalars.columns(scalars=result.alarm[seen].astype(np.float64)))
    rec.send_columns("signals/blind", indexes=times, columns=rr.Scalars.columns(
        scalars=result.blind.astype(np.float64)))
