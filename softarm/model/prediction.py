"""A latent model's answers for some frames, and what it knows of its own trust in each (NumPy only: importing it
loads no network)."""

from dataclasses import dataclass, fields, replace
from typing import Optional, Sequence

import numpy as np

PICTURE_BATCH = 1024  # frames `picture_of` takes at once: float64 temporaries of 36 MB each at 84 x 52 pixels


@dataclass(frozen=True)
class Prediction:
    """The latent answers for some frames of one recording (or several, one after another)."""
    targets: np.ndarray     # (M,) frame indices, or (M, 2) (recording, frame) pairs
    latents: np.ndarray     # (M, K) normalised kept latent features (an ensemble's: its members' mean)
    log_error: np.ndarray   # (M, K) the error head's estimate of each feature's log squared error (members' mean)
    spread: Optional[np.ndarray] = None    # (M, K) an ensemble's variance across its members; None for one model
    surprise: Optional[np.ndarray] = None  # (M,) the surprise of the sample each frame is imagined from
    residual: Optional[np.ndarray] = None  # (M,) its felt residual before the vigour divides it (`model.surprise`)
    ridge_gap: Optional[np.ndarray] = None  # (M,) mean squared gap to the ridge baseline's latent from the same window
    picture: Optional[np.ndarray] = None    # (M, 2) the decoded frame's doubt and area (`picture_of`)

    @property
    def confidence(self) -> np.ndarray:
        """(M,) in (0, 1]: the error head's, 1 / (1 + the predicted mean squared error of the normalised latent);
        0.5 means the model expects to be as far off as a guess of the mean frame's code. A checkpoint's chosen
        confidence is `softarm.trust.confidence`'s."""
        return 1.0 / (1.0 + np.exp(self.log_error).mean(axis=1))

    def take(self, keep: np.ndarray) -> "Prediction":
        return Prediction(*(None if a is None else a[keep] for a in self.arrays()))

    def arrays(self) -> tuple[Optional[np.ndarray], ...]:
        return tuple(getattr(self, f.name) for f in fields(self))

    def with_surprise(self, surprise: np.ndarray, residual: np.ndarray) -> "Prediction":
        return replace(self, surprise=surprise, residual=residual)

    def with_ridge_gap(self, ridge: np.ndarray) -> "Prediction":
        """With the gap between each latent and the ridge baseline's answer `ridge` (M, K) for the same frames."""
        return replace(self, ridge_gap=((self.latents - ridge) ** 2).mean(axis=1))

    def with_picture(self, probabilities: np.ndarray) -> "Prediction":
        """With what the decoder's pixel probabilities (M, H, W) of these latents say (`picture_of`)."""
        return replace(self, picture=picture_of(probabilities))

    @staticmethod
    def join(parts: Sequence["Prediction"]) -> "Prediction":
        return Prediction(*(None if any(a is None for a in arrays) else np.concatenate(arrays)
                            for arrays in zip(*(p.arrays() for p in parts))))


def picture_of(probabilities: np.ndarray) -> np.ndarray:
    """(M, 2) of pixel probabilities (M, H, W): the decoder's doubt, its pixels' binary entropy summed (nats), and
    the arm's area, the probabilities summed (pixels). A latent between the codes the decoder learned draws
    pixels it cannot decide; the same misplaced pixels cost a small arm more IoU."""
    out = np.empty((len(probabilities), 2))
    for start in range(0, len(probabilities), PICTURE_BATCH):
        frames = slice(start, start + PICTURE_BATCH)
        p = np.clip(probabilities[frames].astype(np.float64), 1e-12, 1.0 - 1e-12)
        out[frames, 0] = -(p * np.log(p) + (1.0 - p) * np.log1p(-p)).sum(axis=(1, 2))
        out[frames, 1] = p.sum(axis=(1, 2))
    return out


def joined_members(answers: Sequence[Prediction]) -> Prediction:
    """An ensemble's answer: the members' mean latent, their mean predicted squared error, and the variance
    between them; one member's answer as it is."""
    if len(answers) == 1:
        return answers[0]
    latents = np.stack([a.latents for a in answers])
    log_error = np.log(np.mean([np.exp(a.log_error) for a in answers], axis=0))
    return Prediction(answers[0].targets, latents.mean(axis=0), log_error, latents.var(axis=0))
