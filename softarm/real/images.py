"""Camera messages to pixels: `sensor_msgs/msg/Image` (mono8, rgb8, bgr8, rgba8, bgra8, mono16),
`sensor_msgs/msg/CompressedImage` (jpeg, png) and Foxglove's `RawImage` / `CompressedImage`.

A JPEG is decoded at a reduced scale where the mask needs fewer pixels than the camera has (libjpeg's DCT
scaling, `Image.draft`): most of an import's time is decoding, and the models' camera is 84x52.
"""

import io
import math
from typing import Any, Callable, Optional

import numpy as np

from softarm.errors import ConfigError, RecordingError

RAW = {"mono8": (1, np.uint8), "8uc1": (1, np.uint8), "rgb8": (3, np.uint8), "bgr8": (3, np.uint8),
       "rgba8": (4, np.uint8), "bgra8": (4, np.uint8), "mono16": (1, np.uint16), "16uc1": (1, np.uint16)}
COMPRESSED = ("jpeg", "jpg", "png")


Scale = Callable[[tuple[int, int]], float]  # the camera's (width, height) -> the least scale the caller needs
Roi = Optional[tuple[int, int, int, int]]     # x, y, width, height in the camera's own pixels


def decode_image(message: Any, where: str, scale: Scale = lambda size: 1.0,
                 roi: Roi = None) -> tuple[np.ndarray, tuple[int, int]]:
    """(H, W, 3) RGB uint8 of an image message, cut to `roi` where one is given, and the camera's own (width,
    height); `scale` says how few pixels the caller needs, which lets a JPEG decode at 1/2, 1/4 or 1/8 scale.
    Unsupported encodings are refused by name."""
    if hasattr(message, "format"):
        return _compressed(bytes(message.data), str(message.format), where, scale, roi)
    if int(message.width) < 1 or int(message.height) < 1:
        raise RecordingError(f"{where}: an image of {message.width}x{message.height} pixels holds nothing to find the "
                             "arm in; check the topic")
    rgb = _raw(message, where)
    size = (rgb.shape[1], rgb.shape[0])
    return rgb[crop_box(roi, size, size)], size


def crop_box(roi: Roi, size: tuple[int, int], decoded: tuple[int, int]) -> tuple[slice, slice]:
    """The rows and columns of `roi` in an image of the camera's `size` decoded at `decoded` (width, height)."""
    if roi is None:
        return slice(None), slice(None)
    x, y, w, h = roi
    if x + w > size[0] or y + h > size[1]:
        raise ConfigError(f"--roi {x},{y},{w},{h} reaches outside the camera's {size[0]}x{size[1]} image")
    fx, fy = decoded[0] / size[0], decoded[1] / size[1]  # a JPEG may have been decoded at a smaller scale
    return slice(round(y * fy), round((y + h) * fy)), slice(round(x * fx), round((x + w) * fx))


def _compressed(data: bytes, fmt: str, where: str, scale: Scale, roi: Roi) -> tuple[np.ndarray, tuple[int, int]]:
    from PIL import Image  # loaded when an image is met: importing softarm stays light

    words = fmt.lower().replace(";", " ").split()  # ROS: "jpeg", or "rgb8; jpeg compressed bgr8"
    kind = next((k for k in COMPRESSED if k in words), None)
    if kind is None:
        raise RecordingError(f"{where}: compressed image format {fmt!r} is not supported (jpeg and png are)")
    try:
        image = Image.open(io.BytesIO(data))
        size = image.size
        least = min(1.0, scale(size))
        if image.format == "JPEG" and least < 1.0:
            image.draft("RGB", (math.ceil(size[0] * least), math.ceil(size[1] * least)))
        rows, columns = crop_box(roi, size, image.size)
        if roi is not None:  # cut before the pixels become an array: fewer bytes to copy
            image = image.crop((columns.start, rows.start, columns.stop, rows.stop))
        return np.asarray(image if image.mode == "RGB" else image.convert("RGB")), size
    except (OSError, ValueError, Image.DecompressionBombError) as e:
        raise RecordingError(f"{where}: a {kind} image does not decode ({e})") from None


def _raw(message: Any, where: str) -> np.ndarray:
    encoding = str(message.encoding).lower()
    if encoding not in RAW:
        raise RecordingError(f"{where}: image encoding {message.encoding!r} is not supported "
                             f"(supported: {', '.join(k for k in RAW if not k[0].isdigit())})")
    channels, dtype = RAW[encoding]
    height, width, step = int(message.height), int(message.width), int(message.step)
    data = bytes(message.data)
    size = np.dtype(dtype).itemsize
    if step < width * channels * size or len(data) < height * step:
        raise RecordingError(f"{where}: an image holds {len(data)} bytes, not {height} rows of {step}")
    big = bool(getattr(message, "is_bigendian", False))
    rows = np.frombuffer(data, np.uint8)[:height * step].reshape(height, step)[:, :width * channels * size]
    pixels = rows.copy().view(np.dtype(dtype).newbyteorder(">" if big else "<")).reshape(height, width, channels)
    if dtype == np.uint16:  # mono16: the top byte is what a mask can see
        pixels = (pixels >> 8).astype(np.uint8)
    if channels == 1:
        return np.repeat(pixels, 3, axis=2)
    rgb = pixels[..., :3]
    return rgb[..., ::-1] if encoding.startswith("bgr") else rgb
