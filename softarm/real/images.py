"""Camera messages to pixels: `sensor_msgs/msg/Image` (mono8, rgb8, bgr8, rgba8, bgra8, mono16),
`sensor_msgs/msg/CompressedImage` (jpeg, png) and Foxglove's `RawImage` / `CompressedImage`.

A JPEG is decoded at a reduced scale where the mask needs fewer pixels than the camera has (libjpeg's DCT
scaling, `Image.draft`): most of an import's time is decoding, and the models' camera is 84x52.
"""

import io
import math
from typing import Any, Callable

import numpy as np

from softarm.errors import RecordingError

RAW = {"mono8": (1, np.uint8), "8uc1": (1, np.uint8), "rgb8": (3, np.uint8), "bgr8": (3, np.uint8),
       "rgba8": (4, np.uint8), "bgra8": (4, np.uint8), "mono16": (1, np.uint16), "16uc1": (1, np.uint16)}
COMPRESSED = ("jpeg", "jpg", "png")


Scale = Callable[[tuple[int, int]], float]  # the camera's (width, height) -> the least scale the caller needs


def decode_image(message: Any, where: str, scale: Scale = lambda size: 1.0) -> tuple[np.ndarray, tuple[int, int]]:
    """(H, W, 3) RGB uint8 of an image message and the camera's own (width, height); `scale` says how few
    pixels the caller needs, which lets a JPEG decode at 1/2, 1/4 or 1/8 scale. Unsupported encodings are
    refused by name."""
    if hasattr(message, "format"):
        return _compressed(bytes(message.data), str(message.format), where, scale)
    rgb = _raw(message, where)
    return rgb, (rgb.shape[1], rgb.shape[0])


def _compressed(data: bytes, fmt: str, where: str, scale: Scale) -> tuple[np.ndarray, tuple[int, int]]:
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
