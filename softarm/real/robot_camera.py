"""The robot-style log's camera: a fixed textured scene, the arm drawn over it each frame at high resolution,
then lighting flicker, blur and pixel noise (PIL; loaded only when a log is made)."""

import io
from typing import Any

import numpy as np
from PIL import Image, ImageChops, ImageDraw, ImageFilter

from softarm.errors import ConfigError
from softarm.real.robot_settings import RobotLogSettings, ros_header
from softarm.record.recording import Recording

_SUPERSAMPLE = 4
_NOISE_PAD = 61


class ArmCamera:
    """The big camera: a fixed textured scene, the arm drawn over it each frame, then flicker and noise."""

    def __init__(self, rec: Recording, settings: RobotLogSettings, rng: np.random.Generator):
        small_h, small_w = rec.frames.shape[1:]
        self.s = min(settings.width // small_w, settings.height // small_h)
        if self.s < 1:
            raise ConfigError(f"a {settings.width}x{settings.height} image cannot hold the {small_w}x{small_h} view")
        self.roi = ((settings.width - self.s * small_w) // 2, (settings.height - self.s * small_h) // 2,
                    self.s * small_w, self.s * small_h)
        self.settings, self.rng, self.size = settings, rng, (settings.width, settings.height)
        self.span = float(rec.times[-1]) if len(rec.times) else 0.0  # s: the run, over which `progress` goes 0..1
        self.M, self.outline = rec.world_to_pixel, np.asarray(rec.model["outline"], np.int64)
        self.background = texture(settings, rng)
        if settings.blur > 0:  # the scene is fixed: blur it once (blur is linear; the arm's edge is blurred below)
            self.background = self.background.filter(ImageFilter.GaussianBlur(settings.blur))
        yy, xx = np.mgrid[0:settings.height, 0:settings.width]
        shade = 1.05 - 0.1 * yy / settings.height - 0.04 * xx / settings.width
        self.arm = Image.fromarray(np.clip(np.multiply.outer(shade, settings.arm_rgb), 0, 255).astype(np.uint8))
        bank = rng.normal(128.0, settings.pixel_noise, (settings.height + _NOISE_PAD, settings.width + _NOISE_PAD, 3))
        self.noise = Image.fromarray(np.clip(np.rint(bank), 0, 255).astype(np.uint8))

    def arm_patch(self, nodes: np.ndarray) -> tuple[tuple[int, int], Image.Image] | None:
        """Where the arm lies and its coverage (0..255) there: the outline polygon, supersampled, then blurred.
        `nodes` (N, 2), or (E, N, 2) for the positions within one exposure: the coverage is their mean."""
        poses = nodes.reshape(-1, *nodes.shape[-2:])
        # model pixel [u, u+1) -> big pixels [x + s*u, x + s*(u+1))
        qs = [np.array(self.roi[:2]) + self.s * (p[self.outline] @ self.M[:, :2].T + self.M[:, 2]) for p in poses]
        margin = int(3 * self.settings.blur) + 2
        lo = np.clip(np.floor(np.min([q.min(0) for q in qs], axis=0)).astype(int) - margin, 0, self.size)
        hi = np.clip(np.ceil(np.max([q.max(0) for q in qs], axis=0)).astype(int) + margin, 0, self.size)
        if np.any(hi <= lo):
            return None
        masks = []
        for q in qs:
            sub = Image.new("L", tuple(int(v) for v in _SUPERSAMPLE * (hi - lo)), 0)
            # PIL puts pixel i at coordinate i: shift by half a pixel so that a pixel is filled when its centre is
            # inside
            ImageDraw.Draw(sub).polygon([tuple(v) for v in (_SUPERSAMPLE * (q - lo) - 0.5).tolist()], fill=255)
            masks.append(sub.reduce(_SUPERSAMPLE))
        mask = masks[0] if len(masks) == 1 else Image.fromarray(
            np.rint(np.mean([np.asarray(m, np.float64) for m in masks], axis=0)).astype(np.uint8))
        if self.settings.blur > 0:
            mask = mask.filter(ImageFilter.GaussianBlur(self.settings.blur))
        return (int(lo[0]), int(lo[1])), mask

    def image(self, nodes: np.ndarray, progress: float = 0.0) -> Image.Image:
        """One camera frame of the arm at these node positions (m; (E, N, 2) within an exposure), `progress`
        (0..1) of the way through the run."""
        img = self.background.copy()
        if self.settings.distractor:
            self.draw_distractor(img, progress)
        if (patch := self.arm_patch(nodes)) is not None:
            (x, y), mask = patch
            img.paste(self.arm.crop((x, y, x + mask.width, y + mask.height)), (x, y), mask)
        gain = self.rng.normal(1.0, self.settings.light_noise)
        if self.settings.lighting_drift:
            gain *= 1.0 + self.settings.lighting_drift * (2.0 * progress - 1.0)
        img = img.point(np.clip(np.rint(np.arange(256) * gain), 0, 255).astype(np.uint8).tolist() * 3)
        if self.settings.pixel_noise > 0:
            dx, dy = (int(v) for v in self.rng.integers(0, _NOISE_PAD, 2))
            noise = self.noise.crop((dx, dy, dx + self.size[0], dy + self.size[1]))
            img = ImageChops.add(img, noise, 1.0, -128)  # saturating img + noise - 128
        return img

    def draw_distractor(self, img: Image.Image, progress: float) -> None:
        """A dark disc on a string from the top edge, swinging across the scene behind the arm (never over it, so
        the arm's true mask stays the recording's): it moves, so no background model learns it away."""
        w, h = self.size
        pivot = (0.3 * w, 0.0)
        angle = 0.9 * np.sin(2 * np.pi * 0.37 * progress * self.span + 0.4)
        length = 0.75 * h
        centre = (pivot[0] + length * np.sin(angle), pivot[1] + length * np.cos(angle))
        radius = 0.06 * min(w, h)
        draw = ImageDraw.Draw(img)
        draw.line([pivot, centre], fill=(40, 40, 40), width=max(1, w // 320))
        draw.ellipse([centre[0] - radius, centre[1] - radius, centre[0] + radius, centre[1] + radius],
                     fill=(55, 50, 70))

    def message(self, nodes: np.ndarray, stamp_ns: int, progress: float = 0.0) -> dict[str, Any]:
        """The ROS message of one frame, in the settings' format."""
        img, fmt = self.image(nodes, progress), self.settings.image_format
        header = ros_header(stamp_ns, "camera")
        if fmt == "rgb8":
            return {"header": header, "height": self.size[1], "width": self.size[0], "encoding": "rgb8",
                    "is_bigendian": 0, "step": 3 * self.size[0], "data": img.tobytes()}
        buffer = io.BytesIO()
        options = {"quality": self.settings.jpeg_quality} if fmt == "jpeg" else {"compress_level": 3}
        img.save(buffer, fmt.upper(), **options)
        return {"header": header, "format": f"rgb8; {fmt} compressed bgr8", "data": buffer.getvalue()}


def texture(settings: RobotLogSettings, rng: np.random.Generator) -> Image.Image:
    """A fixed, smooth lab scene around `scene_rgb` (by default greyish blue-green): upsampled coarse noise, faint
    stripes and a few blobs, each scaled by `texture`."""
    w, h = settings.width, settings.height
    coarse = rng.normal(0.0, 7.0, (6, 8, 3)) + rng.normal(0.0, 14.0, (6, 8, 1))
    smooth = Image.fromarray(np.clip(coarse + 128, 0, 255).astype(np.uint8)).resize((w, h), Image.BICUBIC)
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
    strength = np.float32(settings.texture)
    scene = (np.asarray(smooth, np.float32) - 128) * strength + np.array(settings.scene_rgb, np.float32)
    angle, period = rng.uniform(0, np.pi), rng.uniform(30, 60)
    scene += strength * 5.0 * np.sin(2 * np.pi * (xx * np.cos(angle) + yy * np.sin(angle)) / period)[..., None]
    for cx, cy, r, level in zip(rng.uniform(0, w, 6), rng.uniform(0, h, 6), rng.uniform(15, 60, 6),
                                rng.uniform(-35, 25, 6)):
        scene += strength * level * np.exp(-((xx - cx) ** 2 + (yy - cy) ** 2) / (2 * r * r))[..., None]
    if settings.scene_rgb[0] < settings.scene_rgb[1]:  # a greenish scene never turns the reddish arm's hue
        scene[..., 0] = np.minimum(scene[..., 0], scene[..., 1] - 10)
    return Image.fromarray(np.clip(scene, 20, 235).astype(np.uint8))
