"""The body in a camera image: a binary mask per frame, at the camera size the models use.

A rule picks the arm's pixels: a threshold on one channel (`r`, `g`, `b`, `gray`, `h`, `s`, `v`; or against a
background frame, `diff`, the largest colour difference, or `chroma`, the difference in chromaticity, blind to
how bright the light is), fixed or by Otsu over the recording, a range in HSV, or a straight cut through the
colours (`rgb=...`). `auto` chooses among the Otsu rules by how well each separates two classes (`choose_rule`),
fits the colour cut to the classes it found (`fit_colour`) and keeps the mask's main parts (`main_parts`). The
image is cut to a region of interest first; the mask is then area-averaged down to the camera size and
thresholded at one half, as softarm's own camera counts a pixel as arm when the arm covers most of it.
"""

import re
from dataclasses import dataclass
from typing import Optional

import numpy as np

from softarm.errors import ConfigError

CHANNELS = ("r", "g", "b", "gray", "h", "s", "v", "diff", "chroma")
BACKGROUND_CHANNELS = ("diff", "chroma")  # against a background frame
CANDIDATES = ("r", "g", "b", "gray", "s", "v")  # what `auto` tries (hue is circular: left out), and with a
# background given, BACKGROUND_CHANNELS too. Not by default: a median over the log's frames holds the arm wherever it
# hangs most of the time (an arm that swings a little is mostly "background"), and its difference then finds only
# the part that moved (5 % of the pixels where the arm covers 13 %, and a better Otsu score than any colour rule)
SEPARABLE = 0.7  # separability below which `auto` warns: a single Gaussian class scores 0.64, a uniform spread 0.75
_THRESHOLD = re.compile(r"^(r|g|b|gray|h|s|v|diff|chroma)\s*([<>])\s*(otsu|\d+(?:\.\d*)?)$")
_HSV = re.compile(r"^hsv\s*=\s*(\d+)-(\d+)\s*,\s*(\d+)-(\d+)\s*,\s*(\d+)-(\d+)$")
_NUMBER = r"\s*([-+]?\d+(?:\.\d*)?)\s*"
_COLOUR = re.compile(rf"^rgb\s*={_NUMBER},{_NUMBER},{_NUMBER}>{_NUMBER}$")
SURE = 0.5  # the pixels a colour cut is fitted to: beyond this share of the way from Otsu's cut to their class's median
FIT_PIXELS = 200  # a colour cut needs at least this many sure pixels in each class


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
        if self.name in BACKGROUND_CHANNELS:
            if background is None:
                raise ConfigError(f"--mask {self.text}: {self.name} needs a background (--background median or an "
                                  "image)")
            if self.name == "diff":
                return np.abs(rgb.astype(np.int16) - background).max(axis=2).astype(np.float32)
            return chroma_difference(rgb, background)
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


@dataclass(frozen=True)
class Colour(MaskRule):
    """`rgb=WR,WG,WB>CUT`: the arm where WR r + WG g + WB b > CUT. Where the arm covers a share of a pixel, the pixel's
    colour is the arm's and the wall's mixed in that share, linear in r, g, b; so a cut halfway between the two
    classes' mean colours keeps a pixel the arm covers at least half of, as softarm's camera counts one, however
    blurred the edge (a cut on saturation or brightness ratios, not linear in the mix, moves it). `seed`: the Otsu
    rule whose classes `auto` fitted the cut to ("" when the rule was given)."""
    text: str
    weights: tuple[float, float, float]
    cut: float
    seed: str = ""

    def channel(self, rgb: np.ndarray, background: Optional[np.ndarray]) -> np.ndarray:
        return rgb.astype(np.float32) @ np.asarray(self.weights, np.float32)

    def apply(self, values: np.ndarray, threshold: Optional[float]) -> np.ndarray:
        return values > self.cut


@dataclass(frozen=True)
class Auto(MaskRule):
    """`auto`: the Otsu rule that separates the first look's frames best, its mask cleaned; chosen before any frame
    is segmented (`CameraReader.first_look`), so it is never applied itself."""
    text: str = "auto"


def parse_mask(text: str) -> MaskRule:
    """A mask rule from its text (see the classes above); one line naming the syntax otherwise."""
    clean = text.strip().lower()
    if clean == "auto":
        return Auto(text)
    if (m := _THRESHOLD.match(clean)) is not None:
        name, op, value = m.groups()
        return Threshold(text, name, op == ">", None if value == "otsu" else float(value))
    if (m := _HSV.match(clean)) is not None:
        n = [float(x) for x in m.groups()]
        return HsvRange(text, (n[0], n[1]), (n[2], n[3]), (n[4], n[5]))
    if (m := _COLOUR.match(clean)) is not None:
        n = [float(x) for x in m.groups()]
        if not any(n[:3]):
            raise ConfigError(f"--mask {text!r}: the colour weights are all zero; give at least one")
        return Colour(text, (n[0], n[1], n[2]), n[3])
    raise ConfigError(f"--mask {text!r}: give CHANNEL>VALUE or CHANNEL<VALUE with CHANNEL one of "
                      f"{', '.join(CHANNELS)} and VALUE a number or otsu (e.g. s>otsu), hsv=H0-H1,S0-S1,V0-V1, "
                      "rgb=WR,WG,WB>CUT, or auto")


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
    return otsu_split(values)[0]


def otsu_split(values: np.ndarray) -> tuple[float, float]:
    """Otsu's threshold and its separability: the between-class share of the variance at that cut (0: one class,
    1: two spikes), the score `auto` chooses a rule by."""
    top = 360.0 if values.max() > 255 else 255.0
    counts, edges = np.histogram(values, bins=256, range=(0.0, top))
    p = counts / max(counts.sum(), 1)
    centres = (edges[:-1] + edges[1:]) / 2
    w0, m0 = np.cumsum(p), np.cumsum(p * centres)
    between = (m0[-1] * w0 - m0) ** 2 / np.maximum(w0 * (1 - w0), 1e-12)
    best = int(np.argmax(between[:-1]))
    total = float((p * (centres - m0[-1]) ** 2).sum())
    return float(edges[best + 1]), float(between[best] / total) if total > 0 else 0.0


def chroma_difference(rgb: np.ndarray, background: np.ndarray) -> np.ndarray:
    """(H, W) float32 0..255: how far each pixel's chromaticity (r, g, b over their sum) lies from the background's,
    unchanged when the light grows brighter or dimmer, as a shadow or a drifting lamp does."""
    def chromaticity(image: np.ndarray) -> np.ndarray:
        values = image.astype(np.float32)
        return values / np.maximum(values.sum(axis=2, keepdims=True), 1.0)
    return np.minimum(np.abs(chromaticity(rgb) - chromaticity(background)).max(axis=2) * 3 * 255, 255.0)


def choose_rule(samples: list[np.ndarray], background: Optional[np.ndarray]) -> tuple[Threshold, float, float]:
    """(rule, threshold, separability) of the candidate that separates the samples' pixels best; the arm is the
    smaller class (it covers under half of a region of interest), which sets each rule's side of the cut."""
    best: Optional[tuple[Threshold, float, float]] = None
    for name in CANDIDATES + (BACKGROUND_CHANNELS if background is not None else ()):
        probe = Threshold(f"{name}>otsu", name, True, None)
        values = np.concatenate([probe.channel(p, None if background is None else background[:p.shape[0], :p.shape[1]])
                                 .ravel() for p in samples])
        values = values[:: max(1, len(values) // 400_000)]  # a few hundred thousand pixels settle the cut
        threshold, score = otsu_split(values)
        above = (values > threshold).mean() <= 0.5
        rule = Threshold(f"{name}{'>' if above else '<'}otsu", name, above, None)
        if best is None or score > best[2]:
            best = rule, threshold, score
    assert best is not None
    return best


def fit_colour(samples: list[np.ndarray], seed: Threshold, threshold: float) -> Optional[Colour]:
    """The colour cut that best separates the classes `seed` finds in the samples (Fisher's linear discriminant over
    r, g, b of the pixels it is sure of, `SURE`), halfway between the classes' mean colours; None when either class
    has fewer than FIT_PIXELS sure pixels or their colours do not differ."""
    colours = np.concatenate([p.reshape(-1, 3) for p in samples]).astype(np.float64)
    values = np.concatenate([np.asarray(seed.channel(p, None), np.float64).ravel() for p in samples])
    arm = seed.apply(values, threshold)
    if arm.all() or not arm.any():
        return None
    sure = []
    for side in (arm, ~arm):
        median = float(np.median(values[side]))
        sure.append(side & (np.abs(values - threshold) > SURE * abs(median - threshold)))
    if min(int(s.sum()) for s in sure) < FIT_PIXELS:
        return None
    means = [colours[s].mean(axis=0) for s in sure]
    within = sum(np.cov(colours[s].T) * s.sum() for s in sure) / sum(s.sum() for s in sure)
    within += 1e-3 * np.trace(within) / 3 * np.eye(3)  # a flat colour (no spread in a channel) stays solvable
    weights = np.linalg.solve(within, means[0] - means[1])
    if not np.any(weights):
        return None
    weights = np.round(weights / np.abs(weights).max(), 3)
    cut = round(float(weights @ (means[0] + means[1])) / 2, 2)
    text = f"rgb={weights[0]:g},{weights[1]:g},{weights[2]:g}>{cut:g}"
    return Colour(text, (float(weights[0]), float(weights[1]), float(weights[2])), cut, seed.text)


def main_parts(mask: np.ndarray, share: float = 0.25) -> np.ndarray:
    """The largest 4-connected part of a camera-size mask, and every other at least `share` of its size: the arm
    (its tip too, where downsampling cut it off) without specks, reflections and smaller objects apart from it."""
    inside, parts = mask > 0, []
    left = inside.copy()
    while left.any():
        seed = np.zeros_like(inside)
        seed.flat[int(np.flatnonzero(left)[0])] = True
        part = _grow(seed, inside)
        parts.append(part)
        left &= ~part
    if not parts:
        return mask
    largest = max(int(part.sum()) for part in parts)
    return np.logical_or.reduce([part for part in parts if part.sum() >= share * largest]).astype(mask.dtype)


def _grow(seeds: np.ndarray, inside: np.ndarray) -> np.ndarray:
    """Every pixel of `inside` 4-connected to a seed: whole runs along the columns, then along the rows, that hold a
    reached pixel are reached, until nothing changes (a few passes for an arm, not one per pixel of its length)."""
    while True:
        grown = _runs_reached(_runs_reached(seeds, inside), inside, along_rows=True)
        if np.array_equal(grown, seeds):
            return seeds
        seeds = grown


def _runs_reached(reached: np.ndarray, inside: np.ndarray, along_rows: bool = False) -> np.ndarray:
    """`reached` spread over every run of `inside` (along the columns, or the rows) that holds a reached pixel."""
    a, b = (inside.T, reached.T) if not along_rows else (inside, reached)
    flat_inside, flat_reached = a.ravel(), b.ravel()
    starts = flat_inside & ~np.concatenate([[False], flat_inside[:-1]])
    starts[:: a.shape[1]] |= flat_inside[:: a.shape[1]]  # a run never continues across a line's end
    ids = np.cumsum(starts) * flat_inside
    hit = np.zeros(int(ids.max()) + 1, bool)
    hit[ids[flat_reached & flat_inside]] = True
    hit[0] = False
    out = hit[ids].reshape(a.shape)
    return out.T if not along_rows else out


def downsample(mask: np.ndarray, width: int, height: int) -> np.ndarray:
    """(height, width) uint8 0/1: the share of arm pixels over each camera pixel (area average, as a grey level),
    at least half (128 of 255)."""
    from PIL import Image  # loaded when an image is met: importing softarm stays light

    covered = Image.fromarray(mask.astype(np.uint8) * np.uint8(255)).resize((width, height), Image.Resampling.BOX)
    return (np.asarray(covered) >= 128).astype(np.uint8)
