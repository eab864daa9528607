"""The body in a camera image: a binary mask per frame, at the camera size the models use.

A rule picks the arm's pixels: a threshold on one channel (`r`, `g`, `b`, `gray`, `h`, `s`, `v`, or `diff`, the
largest colour difference to a background frame), fixed or by Otsu over the recording, or a range in HSV. The
image is cut to a region of interest first; the mask is then area-averaged down to the camera size and
thresholded at one half, as softarm's own camera counts a pixel as arm when the arm covers most of it.
"""

import re
from dataclasses import dataclass
from typing import Optional

import numpy as np

from softarm.errors import ConfigError

CHANNELS = ("r", "g", "b", "gray", "h", "s", "v", "diff")
_THRESHOLD = re.compile(r"^(r|g|b|gray|h|s|v|diff)\s*([<>])\s*(otsu|\d+(?:\.\d*)?)$")
_HSV = re.compile(r"^hsv\s*=\s*(\d+)-(\d+)\s*,\s*(\d+)-(\d+)\s*,\s*(\d+)-(\d+)$")


class MaskRule:
    """Which pixels are arm, from the channels of an (H, W, 3) image."""
    text: str

    def channel(self, rgb: np.ndarray, background: Optional[np.ndarray]) -> np.ndarray:
        raise NotImplementedError

    def apply(self, values: np.ndarray, threshold: Optional[float]) -> np.ndarray:
        raise NotImplementedError

    @property
    def needs_otsu(self) -> bool:
        return False


@dataclass(frozen=True)
class Threshold(MaskRule):
    """`s>otsu`, `r>120`, `gray<80`, `diff>30`: one channel against a value (0..255; hue in degrees 0..360)."""
    text: str
    name: str
    above: bool
    value: Optional[float]  # None: Otsu's threshold over the recording

    def channel(self, rgb: np.ndarray, background: Optional[np.ndarray]) -> np.ndarray:
        if self.name == "diff":
            if background is None:
                raise ConfigError(f"--mask {self.text}: diff needs a background (--background median or an image)")
            return np.abs(rgb.astype(np.int16) - background).max(axis=2).astype(np.float32)
        return channel_values(rgb, self.name)

    def apply(self, values: np.ndarray, threshold: Optional[float]) -> np.ndarray:
        limit = self.value if self.value is not None else threshold
        return values > limit if self.above else values < limit

    @property
    def needs_otsu(self) -> bool:
        return self.value is None


@dataclass(frozen=True)
class HsvRange(MaskRule):
    """`hsv=H0-H1,S0-S1,V0-V1`: hue in degrees (H0 > H1 wraps through red), saturation and value 0..255."""
    text: str
    hue: tuple[float, float]
    saturation: tuple[float, float]
    value: tuple[float, float]

    def channel(self, rgb: np.ndarray, background: Optional[np.ndarray]) -> np.ndarray:
        from PIL import Image  # loaded when an image is met: importing softarm stays light

        hsv = np.asarray(Image.fromarray(rgb).convert("HSV"), np.float32)
        hsv[..., 0] *= 360.0 / 256.0
        return hsv

    def apply(self, values: np.ndarray, threshold: Optional[float]) -> np.ndarray:
        h, s, v = values[..., 0], values[..., 1], values[..., 2]
        lo, hi = self.hue
        hue = (h >= lo) & (h <= hi) if lo <= hi else (h >= lo) | (h <= hi)
        return (hue & (s >= self.saturation[0]) & (s <= self.saturation[1])
                & (v >= self.value[0]) & (v <= self.value[1]))


def parse_mask(text: str) -> MaskRule:
    """A mask rule from its text (see the classes above); one line naming the syntax otherwise."""
    clean = text.strip().lower()
    if (m := _THRESHOLD.match(clean)) is not None:
        name, op, value = m.groups()
        return Threshold(text, name, op == ">", None if value == "otsu" else float(value))
    if (m := _HSV.match(clean)) is not None:
        n = [float(x) for x in m.groups()]
        return HsvRange(text, (n[0], n[1]), (n[2], n[3]), (n[4], n[5]))
    raise ConfigError(f"--mask {text!r}: give CHANNEL>VALUE or CHANNEL<VALUE with CHANNEL one of "
                      f"{', '.join(CHANNELS)} and VALUE a number or otsu (e.g. s>otsu), or hsv=H0-H1,S0-S1,V0-V1")


def channel_values(rgb: np.ndarray, name: str) -> np.ndarray:
    """(H, W) one channel, 0..255 (hue in degrees): r, g, b, s and v as uint8, gray and hue as float32."""
    from PIL import Image  # loaded when an image is met: importing softarm stays light

    if name in "rgb":
        return rgb[..., "rgb".index(name)]
    if name == "gray":
        return np.asarray(Image.fromarray(rgb).convert("L"), np.float32)
    if name in "sv":  # as PIL's HSV: V = max, S = 255 (max - min) / max, in integers, channel by channel
        r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
        high = np.maximum(np.maximum(r, g), b)
        if name == "v":
            return high
        spread = (high - np.minimum(np.minimum(r, g), b)).astype(np.uint16) * 255
        return (spread // np.maximum(high, 1)).astype(np.uint8)
    hsv = np.asarray(Image.fromarray(rgb).convert("HSV"), np.float32)
    index = "hsv".index(name)
    return hsv[..., index] * (360.0 / 256.0 if index == 0 else 1.0)


def otsu(values: np.ndarray) -> float:
    """Otsu's threshold of values in 0..255 (hue 0..360): the cut that best separates two classes."""
    top = 360.0 if values.max() > 255 else 255.0
    counts, edges = np.histogram(values, bins=256, range=(0.0, top))
    p = counts / max(counts.sum(), 1)
    centres = (edges[:-1] + edges[1:]) / 2
    w0, m0 = np.cumsum(p), np.cumsum(p * centres)
    between = (m0[-1] * w0 - m0) ** 2 / np.maximum(w0 * (1 - w0), 1e-12)
    return float(edges[int(np.argmax(between[:-1])) + 1])


def downsample(mask: np.ndarray, width: int, height: int) -> np.ndarray:
    """(height, width) uint8 0/1: the share of arm pixels over each camera pixel (area average, as a grey level),
    at least half (128 of 255)."""
    from PIL import Image  # loaded when an image is met: importing softarm stays light

    covered = Image.fromarray(mask.astype(np.uint8) * np.uint8(255)).resize((width, height), Image.Resampling.BOX)
    return (np.asarray(covered) >= 128).astype(np.uint8)
