"""Taichi rasteriser: binary camera frames of every arm and frame of a block, in parallel (docs/model.md, Camera).

A pixel is 1 exactly when its centre lies inside the outline polygon by the even-odd rule. Each
task draws whole frames, edge by edge: an edge that crosses the centre line of row r at u = xc
flips every pixel whose centre lies left of it (c + 0.5 < xc), the same test as a ray cast to the
right from each centre. Rather than flipping those pixels one by one, the edge leaves a marker at
the last of them and one right-to-left sweep per row, over the span where it has markers, turns the
markers into parity: O(edges x rows crossed + arm width x rows) per frame, on a frame cleared beforehand.
"""

from typing import TYPE_CHECKING

import numpy as np
import taichi as ti

from softarm.arm.camera import world_to_pixel
from softarm.config import CameraConfig
from softarm.sim.capacity import check_camera
from softarm.sim.runtime import device_array, host, on_cpu, task_layout, upload

if TYPE_CHECKING:
    import torch

f64nd = ti.types.ndarray(dtype=ti.f64)
i32nd = ti.types.ndarray(dtype=ti.i32)
u8nd = ti.types.ndarray(dtype=ti.u8)


@ti.func
def mark_edge(a: int, f: int, x0: ti.f64, y0: ti.f64, x1: ti.f64, y1: ti.f64, images: ti.template(),
              spans: ti.template()):
    """Flip the marker of every row whose centre line the edge crosses, at the last pixel left of the
    crossing, and widen that row's span of markers [spans[.., 0], spans[.., 1])."""
    height, width = images.shape[2], images.shape[3]
    # Rows r with y > r + 0.5 are those below ceil(y - 0.5); the crossings lie between the two ends'
    # counts. One row of slack on each side, tested exactly, keeps ties identical to the direct rule.
    lo = ti.cast(ti.max(ti.min(ti.ceil(ti.min(y0, y1) - 0.5), height), 0.0), ti.i32)
    hi = ti.cast(ti.max(ti.min(ti.ceil(ti.max(y0, y1) - 0.5), height), 0.0), ti.i32)
    for r in range(ti.max(lo - 1, 0), ti.min(hi + 1, height)):
        y = r + 0.5
        if (y0 > y) != (y1 > y):
            xc = x0 + (y - y0) * (x1 - x0) / (y1 - y0)
            left = ti.cast(ti.min(ti.max(ti.ceil(xc - 0.5), 0.0), width), ti.i32)  # clamp, then convert
            if left > 0:
                images[a, f, r, left - 1] = images[a, f, r, left - 1] ^ ti.u8(1)
                spans[a, f, r, 0] = ti.min(spans[a, f, r, 0], left - 1)
                spans[a, f, r, 1] = ti.max(spans[a, f, r, 1], left)


@ti.kernel
def rasterise(history: f64nd, n_frames: ti.i32, outline: i32nd, M: f64nd, images: u8nd, spans: i32nd,
              tasks: ti.i32, spacing: ti.i32):
    """images[a, f] = the outline of history[a, f] (node positions, m) seen through M, for f < n_frames.

    `images` must be all zeros on entry (the caller clears it in one go).

    Task k (at slot k * spacing, see runtime.task_layout) draws frames k, k + tasks, ... of the
    flattened (arm, frame) list.
    """
    items = history.shape[0] * n_frames
    height, width = images.shape[2], images.shape[3]
    n_edges = outline.shape[0]
    for slot in range(tasks * spacing):
        if slot % spacing == 0:
            task = slot // spacing
            for j in range((items - task + tasks - 1) // tasks):
                item = task + j * tasks
                a, f = item // n_frames, item % n_frames
                for r in range(height):
                    spans[a, f, r, 0] = width
                    spans[a, f, r, 1] = 0
                first = outline[n_edges - 1]
                x0 = history[a, f, first, 0] * M[0, 0] + history[a, f, first, 1] * M[0, 1] + M[0, 2]
                y0 = history[a, f, first, 0] * M[1, 0] + history[a, f, first, 1] * M[1, 1] + M[1, 2]
                for e in range(n_edges):
                    node = outline[e]
                    x1 = history[a, f, node, 0] * M[0, 0] + history[a, f, node, 1] * M[0, 1] + M[0, 2]
                    y1 = history[a, f, node, 0] * M[1, 0] + history[a, f, node, 1] * M[1, 1] + M[1, 2]
                    mark_edge(a, f, x0, y0, x1, y1, images, spans)
                    x0, y0 = x1, y1
                for r in range(height):  # markers -> parity, right to left, over the span of markers only
                    lo, hi = spans[a, f, r, 0], spans[a, f, r, 1]
                    parity = ti.u8(0)
                    for k in range(hi - lo):
                        c = hi - 1 - k
                        parity = parity ^ images[a, f, r, c]
                        images[a, f, r, c] = parity
                    if parity:  # left of every marker: flipped by all of them (an edge left of the frame has none)
                        for c in range(lo):
                            images[a, f, r, c] = ti.u8(1)


class Rasteriser:
    """Owns the image block of a batch on the Taichi device."""

    def __init__(self, camera: CameraConfig, outline: np.ndarray, arms: int, block_frames: int):
        check_camera(arms, block_frames, camera.height, camera.width, on_gpu=not on_cpu())
        self.outline = upload(np.asarray(outline, np.int32))
        self.M = upload(world_to_pixel(camera))
        self.images = device_array((arms, block_frames, camera.height, camera.width), "uint8")
        self.spans = device_array((arms, block_frames, camera.height, 2), "int32")

    def render(self, history: np.ndarray, n_frames: int) -> np.ndarray:
        """(arms, n_frames, H, W) uint8 frames, 1 = arm, of the first n_frames frames of `history`.

        On the CPU the result is a view of the rasteriser's buffer, valid until the next call.
        """
        arms, block = self.images.shape[:2]
        if history.shape[0] != arms or not 1 <= n_frames <= min(block, history.shape[1]):
            raise ValueError(f"history {tuple(history.shape)} with {n_frames} frames does not fit a "
                             f"rasteriser of {arms} arms x {block} frames")
        self.images.fill(0)  # a memset, far cheaper than clearing pixel by pixel in the kernel
        rasterise(history, n_frames, self.outline, self.M, self.images, self.spans, *task_layout(arms * n_frames))
        return host(self.images)[:, :n_frames]


class TensorRasteriser:
    """The rasteriser over torch tensors on the Taichi device: frames of a batch of arms drawn from positions that
    never leave the device, into images that stay there (a vector env's `pixels`)."""

    def __init__(self, camera: CameraConfig, outline: np.ndarray, arms: int, device: object):
        import torch

        check_camera(arms, 1, camera.height, camera.width, on_gpu=not on_cpu())
        self.arms = arms
        self.outline = torch.as_tensor(np.asarray(outline, np.int32), device=device)
        self.M = torch.as_tensor(world_to_pixel(camera), device=device)
        self.images = torch.zeros((arms, 1, camera.height, camera.width), dtype=torch.uint8, device=device)
        self.spans = torch.zeros((arms, 1, camera.height, 2), dtype=torch.int32, device=device)

    def render(self, positions: "torch.Tensor") -> "torch.Tensor":
        """(arms, H, W) uint8 frames, 1 = arm, of node positions (arms, N, 2) float64 m; a view of the
        rasteriser's buffer, valid until the next call."""
        self.images.zero_()
        rasterise(positions.unsqueeze(1), 1, self.outline, self.M, self.images, self.spans, *task_layout(self.arms))
        return self.images[:, 0]
