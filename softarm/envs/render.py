"""A colour view of one arm for `render_mode="rgb_array"`: the camera's view at `SCALE` times its resolution, the
arm filled, the target with its tolerance disc, the tip marked; drawn with Pillow, so it works headless."""

import numpy as np
from PIL import Image, ImageDraw

from softarm.arm.camera import world_to_pixel
from softarm.envs.arms import Arms

SCALE = 4
ARM, TARGET, ON_TARGET, TIP, BACKGROUND = (70, 110, 170), (220, 60, 50), (40, 170, 80), (20, 20, 20), (250, 250, 250)


def colour_view(arms: Arms, arm: int) -> np.ndarray:
    """(SCALE H, SCALE W, 3) uint8 image of `arm` now."""
    camera = arms.config.camera
    M = world_to_pixel(camera) * SCALE

    def pixel(points: np.ndarray) -> list[tuple[float, float]]:
        uv = np.asarray(points).reshape(-1, 2) @ M[:, :2].T + M[:, 2]
        return [(float(u), float(v)) for u, v in uv]

    image = Image.new("RGB", (camera.width * SCALE, camera.height * SCALE), BACKGROUND)
    draw = ImageDraw.Draw(image)
    draw.polygon(pixel(arms.x[arm, arms.body.outline]), fill=ARM)
    (tu, tv), = pixel(arms.target[arm])
    r = arms.config.control.tolerance * camera.pixels_per_metre * SCALE
    on = arms.distance[arm] < arms.config.control.tolerance
    draw.ellipse([tu - r, tv - r, tu + r, tv + r], outline=ON_TARGET if on else TARGET, width=2)
    draw.ellipse([tu - 2, tv - 2, tu + 2, tv + 2], fill=TARGET)
    (pu, pv), = pixel(arms.x[arm, arms.tip].mean(axis=0))
    draw.ellipse([pu - 3, pv - 3, pu + 3, pv + 3], fill=TIP)
    return np.asarray(image)
