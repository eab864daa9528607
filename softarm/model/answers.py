"""The four answers every imagined frame is judged by, decoded and scored in one place: the model's, a ridge
map from the same input window to the same latent, the mean training frame, and the AE ceiling (the true
frame's own code decoded: the best any latent predictor can do).

Training's metrics and the suite's evaluation both score through `score_answers`, under the same keys.
"""

import numpy as np

from softarm.model.baselines import Baselines, ridge_predict
from softarm.model.imaginer import Imaginer
from softarm.model.metrics import frame_scores

ANSWERS = ("model", "ridge", "mean_frame", "ae_ceiling")


def score_answers(imaginer: Imaginer, baselines: Baselines, truth: np.ndarray, predicted: np.ndarray,
                  windows: np.ndarray, true_latents: np.ndarray, pixels_per_metre: float) -> dict[str, dict[str, np.ndarray]]:
    """Per-frame scores (`metrics.frame_scores`) of each answer for the frames `truth` (M, H, W): the model's
    normalised latents `predicted` (M, K), the ridge map of the normalised input `windows` (M, history, F),
    the mean frame and the decoded `true_latents` (M, K, normalised)."""
    probabilities = {"model": imaginer.decode(predicted),
                     "ridge": imaginer.decode(ridge_predict(baselines.ridge, windows)),
                     "mean_frame": np.broadcast_to(baselines.mean_frame, truth.shape),
                     "ae_ceiling": imaginer.decode(true_latents)}
    return {name: frame_scores(probabilities[name], truth, pixels_per_metre) for name in ANSWERS}
