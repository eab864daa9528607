"""Frames as pixels people look at: probabilities as grey bytes, and the camera-vs-imagination difference.

Shared by the Rerun views, the imagination MCAP and the filmstrip, so every picture shows the same
numbers the same way.
"""

import numpy as np

CHUNK = 1024  # frames per step of the array conversions: small temporaries, few page faults

DIFFERENCE_CLASSES = ("neither", "extra in the imagination", "missed by the imagination", "both")
DIFFERENCE_COLOURS = np.array([(0, 0, 0), (40, 110, 255), (230, 40, 40), (255, 255, 255)], np.uint8)


def probability_bytes(frames: np.ndarray) -> np.ndarray:
    """Pixel probabilities in [0, 1] as grayscale bytes 0..255 (round to nearest)."""
    out = np.empty(frames.shape, np.uint8)
    for start in range(0, len(frames), CHUNK):
        chunk = np.clip(frames[start:start + CHUNK], 0.0, 1.0) * 255 + 0.5
        out[start:start + CHUNK] = chunk.astype(np.uint8)
    return out


def difference_codes(truth: np.ndarray, imagined: np.ndarray) -> np.ndarray:
    """(T, H, W) uint8 class per pixel: 0 neither, 1 extra (blue), 2 missed (red), 3 both (white)."""
    out = np.empty(truth.shape, np.uint8)
    for start in range(0, len(truth), CHUNK):
        chunk = slice(start, start + CHUNK)
        out[chunk] = (truth[chunk] > 0).astype(np.uint8) * 2 + (imagined[chunk] >= 0.5)
    return out
