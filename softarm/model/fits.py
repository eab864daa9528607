"""The one rule for combining recordings and checkpoints: the same image size, and as many features of each
input channel.

Training checks each recording against the first; replay and evaluation check a recording against the
checkpoint, before its frames are read. Either way the one-line refusal says what differs.
"""

from typing import Any, Sequence

from softarm.config import Config
from softarm.errors import RecordingError
from softarm.model.inputs import InputChannel


def recording_shape(model: dict[str, Any], chosen: Sequence[InputChannel],
                    config: Config) -> tuple[tuple[int, int], list[int]]:
    """The image size and each channel's features of a recording, from its model document."""
    return (model["camera"]["height"], model["camera"]["width"]), [c.features(model, config) for c in chosen]


def check_fits(name: str, shape: tuple[Sequence[int], Sequence[int]], expected: tuple[Sequence[int], Sequence[int]],
               chosen: Sequence[InputChannel], other: str, trained: bool = False) -> None:
    """Refuse `name` when its (image size, channel widths) differ from those of `other` (a checkpoint when
    `trained`)."""
    (image, widths), (expected_image, expected_widths) = shape, expected
    if tuple(image) != tuple(expected_image):
        verb = "was trained on" if trained else "has"
        raise RecordingError(f"{name} has {image[0]}x{image[1]} images but {other} {verb} "
                             f"{expected_image[0]}x{expected_image[1]}")
    for channel, width, expected_width in zip(chosen, widths, expected_widths):
        if width != expected_width:
            verb = "was trained with" if trained else "has"
            raise RecordingError(f"{name} has {width} {channel.what} but {other} {verb} {expected_width}")
