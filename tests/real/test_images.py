"""Every camera encoding the import reads decodes to the pixels OpenCV makes of the same bytes."""

from types import SimpleNamespace

import cv2
import numpy as np
import pytest
from foxglove_schemas_protobuf.CompressedImage_pb2 import CompressedImage
from foxglove_schemas_protobuf.RawImage_pb2 import RawImage

from softarm.errors import RecordingError
from softarm.real.images import decode_image

RGB = np.random.default_rng(0).integers(0, 256, (6, 5, 3), dtype=np.uint8)


def raw(encoding: str, pixels: np.ndarray, step_pad: int = 0):
    rows = pixels.reshape(pixels.shape[0], -1).view(np.uint8)
    data = np.concatenate([rows, np.zeros((rows.shape[0], step_pad), np.uint8)], axis=1)
    return SimpleNamespace(encoding=encoding, height=pixels.shape[0], width=pixels.shape[1], step=data.shape[1],
                           is_bigendian=0, data=data.tobytes())


@pytest.mark.parametrize("encoding, pixels, expected", [
    ("rgb8", RGB, RGB),
    ("bgr8", RGB[..., ::-1].copy(), RGB),
    ("rgba8", np.dstack([RGB, np.full(RGB.shape[:2], 7, np.uint8)]), RGB),
    ("bgra8", np.dstack([RGB[..., ::-1], np.full(RGB.shape[:2], 7, np.uint8)]), RGB),
    ("mono8", RGB[..., 0].copy()[..., None], np.repeat(RGB[..., :1], 3, axis=2)),
    ("mono16", (RGB[..., 0].astype(np.uint16) * 257)[..., None], np.repeat(RGB[..., :1], 3, axis=2)),
])
def test_raw_images_decode_to_rgb(encoding, pixels, expected):
    image, size = decode_image(raw(encoding, pixels, step_pad=3), "t")
    assert np.array_equal(image, expected) and size == (5, 6)
    foxglove = RawImage(encoding=encoding, width=5, height=6, step=raw(encoding, pixels).step,
                        data=raw(encoding, pixels).data)
    assert np.array_equal(decode_image(foxglove, "t")[0], expected)


@pytest.mark.parametrize("fmt, ext", [("png", ".png"), ("jpeg", ".jpg"), ("rgb8; jpeg compressed bgr8", ".jpg")])
def test_compressed_images_decode_as_opencv_does(fmt, ext):
    ok, data = cv2.imencode(ext, np.ascontiguousarray(np.repeat(np.repeat(RGB, 8, 0), 8, 1)[..., ::-1]))
    expected = cv2.imdecode(data, cv2.IMREAD_COLOR)[..., ::-1]
    for message in (SimpleNamespace(format=fmt, data=data.tobytes()), CompressedImage(format=fmt, data=data.tobytes())):
        image, size = decode_image(message, "t")
        assert size == (40, 48) and np.abs(image.astype(int) - expected).max() <= (0 if ext == ".png" else 3)


def test_unsupported_encodings_are_named():
    with pytest.raises(RecordingError, match="yuv422"):
        decode_image(raw("yuv422", RGB), "t")
    with pytest.raises(RecordingError, match="'tiff'"):
        decode_image(SimpleNamespace(format="tiff", data=b"x"), "t")
