"""Taichi rasteriser: binary camera frames of every arm and frame of a block, in parallel (MODEL.md, Camera).

A pixel is 1 exactly when its centre lies inside the outline polygon by the even-odd rule. Each
thread fills one image row by scanline: every outline edge that crosses the row's centre line at
u = xc flips the pixels whose centre lies left of it (c + 0.5 < xc), the same test as a ray cast
to the right from each centre, at O(edges + width) per row instead of O(edges x width).
"""

import numpy as np
import taichi as ti

from softarm.config import CameraConfig
from softarm.camera import world_to_pixel
from softarm.runtime import device_array, host, upload

f64nd = ti.types.ndarray(dtype=ti.f64)
i32nd = ti.types.ndarray(dtype=ti.i32)
u8nd = ti.types.ndarray(dtype=ti.u8)


@ti.kernel
def rasterise(history: f64nd, n_frames: ti.i32, outline: i32nd, M: f64nd, polygon: f64nd, images: u8nd):
    """images[a, f] = the outline of history[a, f] (node positions, m) seen through M, for f < n_frames."""
    for a, f, e in ti.ndrange(history.shape[0], n_frames, outline.shape[0]):
        x, y = history[a, f, outline[e], 0], history[a, f, outline[e], 1]
        polygon[a, f, e, 0] = x * M[0, 0] + y * M[0, 1] + M[0, 2]
        polygon[a, f, e, 1] = x * M[1, 0] + y * M[1, 1] + M[1, 2]
    for a, f, r in ti.ndrange(history.shape[0], n_frames, images.shape[2]):
        width = images.shape[3]
        for c in range(width):
            images[a, f, r, c] = ti.u8(0)
        y = r + 0.5
        n_edges = outline.shape[0]
        for e in range(n_edges):
            x0, y0 = polygon[a, f, e, 0], polygon[a, f, e, 1]
            e1 = (e + 1) % n_edges
            x1, y1 = polygon[a, f, e1, 0], polygon[a, f, e1, 1]
            if (y0 > y) != (y1 > y):
                xc = x0 + (y - y0) * (x1 - x0) / (y1 - y0)
                left = ti.cast(ti.min(ti.max(ti.ceil(xc - 0.5), 0.0), width), ti.i32)  # clamp, then convert
                for c in range(left):  # plain read-modify-write: the row belongs to this thread alone
                    images[a, f, r, c] = images[a, f, r, c] ^ ti.u8(1)


class Rasteriser:
    """Owns the image block of a batch on the Taichi device."""

    def __init__(self, camera: CameraConfig, outline: np.ndarray, arms: int, block_frames: int):
        self.outline = upload(np.asarray(outline, np.int32))
        self.M = upload(world_to_pixel(camera))
        self.polygon = device_array((arms, block_frames, len(outline), 2), "float64")
        self.images = device_array((arms, block_frames, camera.height, camera.width), "uint8")

    def render(self, history: ti.Ndarray, n_frames: int) -> np.ndarray:
        """(arms, n_frames, H, W) uint8 frames, 1 = arm, of the first n_frames frames of `history`.

        On the CPU the result is a view of the rasteriser's buffer, valid until the next call.
        """
        arms, block = self.images.shape[:2]
        if history.shape[0] != arms or not 1 <= n_frames <= min(block, history.shape[1]):
            raise ValueError(f"history {tuple(history.shape)} with {n_frames} frames does not fit a "
                             f"rasteriser of {arms} arms x {block} frames")
        rasterise(history, n_frames, self.outline, self.M, self.polygon, self.images)
        return host(self.images)[:, :n_frames]
