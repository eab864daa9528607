"""The answers every imagined frame is judged by, decoded and scored in one place: the model's, a ridge map
from the same input window to the same latent, the mean training frame, the AE ceiling (the true frame's own
code decoded: the best any latent predictor can do) and, where the checkpoint has it, the privileged ridge
from 2 s of inputs to the node positions, drawn through the recording's camera (`ridge_nodes`).

Training's metrics and the suite's evaluation both score through `score_answers`, under the same keys.
"""

from typing import Any

import numpy as np

from softarm.config import config_from_dict, load_config
from softarm.config.load import merge
from softarm.imagine.imaginer import Imaginer
from softarm.model import node_ridge
from softarm.model.baselines import Baselines, ridge_predict
from softarm.model.metrics import frame_scores

ANSWERS = ("model", "ridge", "mean_frame", "ae_ceiling")
PRIVILEGED = "ridge_nodes"


def score_answers(imaginer: Imaginer, baselines: Baselines, truth: np.ndarray, answer: np.ndarray,
                  windows: np.ndarray, true_latents: np.ndarray,
                  pixels_per_metre: float) -> dict[str, dict[str, np.ndarray]]:
    """Per-frame scores (`metrics.frame_scores`) of each answer for the frames `truth` (M, H, W): the model's
    pixel probabilities `answer` (M, H, W; decoded by the caller, who may need them again), the ridge map of the
    normalised input `windows` (M, history, F), the mean frame and the decoded `true_latents` (M, K, normalised)."""
    probabilities = {"model": answer,
                     "ridge": imaginer.decode(ridge_predict(baselines.ridge, windows)),
                     "mean_frame": np.broadcast_to(baselines.mean_frame, truth.shape),
                     "ae_ceiling": imaginer.decode(true_latents)}
    return {name: frame_scores(probabilities[name], truth, pixels_per_metre) for name in ANSWERS}


def score_node_ridge(imaginer: Imaginer, baselines: Baselines, raw: np.ndarray, targets: np.ndarray,
                     truth: np.ndarray, model: dict[str, Any], pixels_per_metre: float) -> dict[str, np.ndarray]:
    """Per-frame scores of the privileged node ridge for the frames `targets` of a raw input series (T, F),
    drawn with the camera and outline of the recording's model document."""
    positions = node_ridge.predict(baselines.nodes, imaginer.inputs.normalise(raw), targets, imaginer.latent.lead)
    camera = config_from_dict(merge(load_config().to_dict(), model.get("config", {}))).camera
    frames = node_ridge.draw(positions, camera, np.asarray(model["outline"], int))
    return frame_scores(frames.astype(np.float32), truth, pixels_per_metre)
