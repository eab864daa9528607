"""A Rerun recording stream of our own, to a viewer and/or an .rrd file that appears only when whole.

A stream of our own, not rerun's global one, so that nothing else in the process logs into it. Both
sinks are set in one call: a later save() or connect_grpc() would replace the earlier sink. The file
grows as `<name>.part` and is renamed when the stream closes; a failed run removes it.
"""

import warnings
from pathlib import Path
from typing import Optional

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from softarm.files import part_path, publish


class RerunStream:
    def __init__(self, application_id: str, blueprint: rrb.Blueprint, rrd: Optional[Path] = None,
                 spawn: bool = False):
        if rrd is None and not spawn:
            raise ValueError("a Rerun stream needs an .rrd file, a viewer, or both")
        self.rrd = Path(rrd) if rrd is not None else None
        self.rec = rr.RecordingStream(application_id)
        sinks: list[rr.GrpcSink | rr.FileSink] = []
        if spawn:
            self.rec.spawn(connect=False)  # start the viewer; the GrpcSink below connects to its default port
            sinks.append(rr.GrpcSink())
        if self.rrd is not None:
            sinks.append(rr.FileSink(part_path(self.rrd)))
        self.rec.set_sinks(*sinks, default_blueprint=blueprint)

    def close(self) -> Optional[Path]:
        """Flush, finish the file (its footer is written when the sink is dropped) and give it its final name."""
        try:
            self.rec.flush()
        except RuntimeError as e:  # the viewer was closed or never came up; the file must still be finished
            warnings.warn(f"rerun viewer unreachable, it may lack the end of the run: {e}", stacklevel=2)
        self.rec.disconnect()
        if self.rrd is not None and part_path(self.rrd).exists():
            return publish(self.rrd)
        return None

    def discard(self) -> None:
        """Stop logging and leave no file behind."""
        self.rec.disconnect()
        if self.rrd is not None:
            part_path(self.rrd).unlink(missing_ok=True)


def send_images(rec: rr.RecordingStream, entity: str, indexes: list[rr.TimeColumn], pixels: np.ndarray) -> None:
    """A column of (T, H, W) grey or (T, H, W, 3) colour byte images, one per time of `indexes`."""
    count, height, width = pixels.shape[:3]
    model = "L" if pixels.ndim == 3 else "RGB"
    image_format = rr.components.ImageFormat(width=width, height=height, color_model=model, channel_datatype="U8")
    rec.send_columns(entity, indexes=indexes, columns=rr.Image.columns(buffer=pixels.reshape(count, -1),
                                                                       format=[image_format] * count))
