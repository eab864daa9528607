"""A preview of the segmentation: a few frames of the log beside their masks, before a whole log is converted."""

from pathlib import Path
from typing import Union

from softarm.files import check_outputs
from softarm.real.camera import CameraReader
from softarm.real.convert import check_camera
from softarm.real.formats import log_inputs, open_log
from softarm.real.settings import ImportSettings


def preview_log(log_path: Union[str, Path], png: Union[str, Path], settings: ImportSettings, count: int = 4,
                force: bool = False) -> Path:
    """Write `png`: `count` frames spread over the log, each with its mask as the import would make it."""
    from softarm.view.preview import write_preview  # PIL drawing: only when a preview is asked for

    log_path, png = Path(log_path), Path(png)
    check_outputs([png], force=force, inputs=[*log_inputs(log_path), *settings.input_files()])
    with open_log(log_path) as log:
        check_camera(log, settings)
        camera = CameraReader(log, settings)
        camera.first_look(camera.samples())
        examples = camera.examples(count)
    threshold = f", Otsu threshold {camera.threshold:.0f}" if camera.threshold is not None else ""
    return write_preview(png, examples, f"{log_path.name} {settings.camera}: --mask {settings.mask}{threshold}")
