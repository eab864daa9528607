"""The one rule for combining recordings and checkpoints: same image size, same sensor count.

Training checks each recording against the first; replay and evaluation check a recording against
the checkpoint. Either way the one-line refusal says what differs.
"""

from typing import Any, Sequence

from softarm.config import SensingConfig
from softarm.errors import RecordingError
from softarm.sense.reading import sensor_count


def check_fits(name: str, image_shape: Sequence[int], sensor_count: int, expected_shape: Sequence[int],
               expected_sensors: int, other: str, trained: bool = False) -> None:
    """Refuse `name` when its images or sensors differ from those of `other` (a checkpoint when `trained`)."""
    shape, expected = tuple(image_shape), tuple(expected_shape)
    if shape != expected:
        verb = "was trained on" if trained else "has"
        raise RecordingError(f"{name} has {shape[0]}x{shape[1]} images but {other} {verb} "
                             f"{expected[0]}x{expected[1]}")
    if sensor_count != expected_sensors:
        verb = "was trained with" if trained else "has"
        raise RecordingError(f"{name} has {sensor_count} stretch sensors but {other} {verb} {expected_sensors}")


def check_recording_fits_checkpoint(state: dict[str, Any], model: dict[str, Any], recording: str,
                                    checkpoint: str, sensing: SensingConfig) -> None:
    """Refuse a recording (by its model document) whose camera or sensors, as `sensing` reads them,
    differ from the checkpoint's."""
    check_fits(recording, (model["camera"]["height"], model["camera"]["width"]), sensor_count(model, sensing),
               state["image_shape"], state["sensor_count"], checkpoint, trained=True)
