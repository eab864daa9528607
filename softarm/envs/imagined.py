"""The imagined body as an observation: a checkpoint's stream model reads every arm's stretch and command as
they come, batched over the arms of a vector env, and adds what it imagines (README, Control).

Added keys: `imagined`, the normalised latent code of the frame it imagines next (K numbers, the autoencoder's
code that its decoder draws), and `confidence`, the error head's (1 / (1 + the predicted mean squared error of
that code)). With `pixels=True` also `imagined_pixels`, the decoded frame's pixel probabilities (costly: one
decoder pass per arm and step). An arm's memory restarts with each of its episodes.
"""

from pathlib import Path
from typing import Any, Callable, Optional, Union

import numpy as np
import torch
from gymnasium import spaces
from gymnasium.vector import AutoresetMode, VectorEnv, VectorWrapper
from gymnasium.vector.utils import batch_space

from softarm.envs.arms import Arms
from softarm.errors import CheckpointError
from softarm.model.prediction import Prediction
from softarm.model.stream import StreamModel

READINGS: dict[str, Callable[[Arms], np.ndarray]] = {
    "stretch": lambda arms: arms.stretch,
    "activation": lambda arms: arms.activation,
    "drive": lambda arms: np.array([[arms.displacement(a)] for a in range(arms.arms)]),
}


class ImaginedBody(VectorWrapper):
    def __init__(self, env: VectorEnv, checkpoint: Union[str, Path], pixels: bool = False):
        super().__init__(env)
        from softarm.model.trained import TrainedModel

        self.imaginer = TrainedModel(checkpoint).imaginer
        self.model, self.pixels = self.imaginer.latent, pixels
        self.arms: Arms = env.unwrapped.arms
        self._check()
        k = self.imaginer.latent_scaler.keep.sum()
        single = dict(env.single_observation_space.spaces)
        single["imagined"] = spaces.Box(-np.inf, np.inf, (int(k),), np.float32)
        single["confidence"] = spaces.Box(0.0, 1.0, (1,), np.float32)
        if pixels:
            camera = self.arms.config.camera
            single["imagined_pixels"] = spaces.Box(0.0, 1.0, (camera.height, camera.width), np.float32)
        self.single_observation_space = spaces.Dict(single)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        rnn = self.model.rnn
        self._lstm = isinstance(rnn, torch.nn.LSTM)
        zero = torch.zeros(rnn.num_layers, self.num_envs, rnn.hidden_size)
        self._state: Any = (zero, zero.clone()) if self._lstm else zero
        self._latent = np.zeros((self.num_envs, int(k)))
        self._log_error = np.zeros((self.num_envs, int(k)))
        self._ended = np.zeros(self.num_envs, bool)

    def reset(self, *, seed: Any = None, options: Optional[dict[str, Any]] = None):
        obs, info = self.env.reset(seed=seed, options=options)
        mask = (options or {}).get("reset_mask")
        rows = np.arange(self.num_envs) if mask is None else np.flatnonzero(np.asarray(mask, bool))
        self._forget(rows)
        self._ended[rows] = False
        return self._imagine(obs, rows), info

    def step(self, actions):
        obs, reward, terminated, truncated, info = self.env.step(actions)
        same_step = self.env.metadata["autoreset_mode"] == AutoresetMode.SAME_STEP
        self._forget(np.flatnonzero((terminated | truncated) if same_step else self._ended))
        self._ended = terminated | truncated
        return self._imagine(obs, np.arange(self.num_envs)), reward, terminated, truncated, info

    def _check(self) -> None:
        if not isinstance(self.model, StreamModel) or self.imaginer.members:
            raise CheckpointError("the imagined-body observation reads one stream model (train.model = \"stream\", "
                                  "train.ensemble = 1)")
        for channel, width in zip(self.imaginer.inputs.channels, self.imaginer.inputs.widths):
            if channel.name not in READINGS or READINGS[channel.name](self.arms).shape[1] != width:
                raise CheckpointError(f"the checkpoint reads {channel.name} ({width} features), which this env does "
                                      f"not give alike: it gives {', '.join(READINGS)}")

    def _forget(self, rows: np.ndarray) -> None:
        """A new episode's arm starts with the model's fresh memory (the stream's start: a zero state)."""
        index = torch.from_numpy(rows)
        for part in self._parts():
            part[:, index] = 0.0

    def _parts(self) -> tuple[torch.Tensor, ...]:
        return self._state if isinstance(self._state, tuple) else (self._state,)

    @torch.inference_mode()
    def _imagine(self, obs: dict[str, np.ndarray], rows: np.ndarray) -> dict[str, np.ndarray]:
        """Advance the given arms' memories by their newest sample; every arm's latest imagination."""
        raw = np.concatenate([READINGS[c.name](self.arms)[rows] for c in self.imaginer.inputs.channels], axis=1)
        sample = torch.from_numpy(self.imaginer.normalised(raw)[:, None])
        index = torch.from_numpy(rows)
        states, after = self.model.rnn(sample, tuple(p[:, index] for p in self._parts()) if self._lstm else
                                       self._state[:, index])
        for part, new in zip(self._parts(), after if self._lstm else (after,)):
            part[:, index] = new
        self._latent[rows] = self.model.head(states[:, 0]).double().numpy()
        self._log_error[rows] = self.model.error(states[:, 0]).double().numpy()
        prediction = Prediction(np.zeros(self.num_envs, int), self._latent, self._log_error)
        out = {**obs, "imagined": self._latent.astype(np.float32),
               "confidence": prediction.confidence.astype(np.float32)[:, None]}
        if self.pixels:
            out["imagined_pixels"] = self.imaginer.decode(self._latent).astype(np.float32)
        return out
