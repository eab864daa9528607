"""World -> pixel map of the camera (docs/model.md, Camera): [u, v] = M [x, y, 1], u = column, v = row."""

import numpy as np

from softarm.config import CameraConfig


def world_to_pixel(camera: CameraConfig) -> np.ndarray:
    """The 2x3 affine map M; v grows downwards because row 0 is the top of the image."""
    s = camera.pixels_per_metre
    u0, v0 = camera.origin
    return np.array([[s, 0.0, u0], [0.0, -s, v0]])

