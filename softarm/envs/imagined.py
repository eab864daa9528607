"""The imagined body as an observation: a checkpoint's stream model reads every arm's stretch and command as
they come, batched over the arms of a vector env, and adds what it imagines (README, Control).

Added keys: `imagined`, the normalised latent code of the frame it imagines next (K numbers, the autoencoder's
code that its decoder draws), and `confidence`, the error head's (1 / (1 + the predicted mean squared error of
that code)). With `pixels=True` also `imagined_pixels`, the decoded frame's pixel probabilities (costly: one
decoder pass per arm and step). An arm's memory restarts with each of its episodes.

On a device env (softarm.envs.device_vector) the model runs on the env's device, its memory and answers stay
there, and the observations are tensors; on the NumPy env, on the CPU, and they are arrays.
"""

from pathlib import Path
from typing import Any, Callable, Optional, Union

import numpy as np
import torch
from gymnasium import spaces
from gymnasium.vector import AutoresetMode, VectorEnv, VectorWrapper
from gymnasium.vector.utils import batch_space

from softarm.errors import CheckpointError
from softarm.model.stream import StreamModel

READINGS: dict[str, Callable[[Any], Any]] = {  # each arm's reading now, (arms, width): arrays or tensors
    "stretch": lambda arms: arms.stretch,
    "activation": lambda arms: arms.activation,
    "drive": lambda arms: arms.displacements(),
}


class ImaginedBody(VectorWrapper):
    def __init__(self, env: VectorEnv, checkpoint: Union[str, Path], pixels: bool = False):
        super().__init__(env)
        from softarm.imagine.trained import TrainedModel

        self.imaginer = TrainedModel(checkpoint).imaginer
        self.model, self.pixels = self.imaginer.latent, pixels
        self.arms = env.unwrapped.arms  # Arms or DeviceArms: the same readings, as arrays or tensors
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
        self.tensors = isinstance(self.arms.steps, torch.Tensor)  # a device env: tensors in, tensors out
        self.device = self.arms.device if self.tensors else torch.device("cpu")
        self.model.to(self.device)
        width = sum(self.imaginer.inputs.widths)
        offset = self.imaginer.inputs.normalise(np.zeros((1, width)))
        scale = self.imaginer.inputs.normalise(np.eye(width)) - offset  # normalising is affine: raw @ scale + offset
        self._scale, self._offset = (torch.as_tensor(a, device=self.device) for a in (scale, offset))
        rnn = self.model.rnn
        self._lstm = isinstance(rnn, torch.nn.LSTM)
        zero = torch.zeros(rnn.num_layers, self.num_envs, rnn.hidden_size, device=self.device)
        self._state: Any = (zero, zero.clone()) if self._lstm else zero
        self._latent = torch.zeros((self.num_envs, int(k)), device=self.device)
        self._log_error = torch.zeros((self.num_envs, int(k)), device=self.device)
        self._ended = torch.zeros(self.num_envs, dtype=torch.bool, device=self.device)

    def reset(self, *, seed: Any = None, options: Optional[dict[str, Any]] = None):
        obs, info = self.env.reset(seed=seed, options=options)
        mask = (options or {}).get("reset_mask")
        rows = (torch.ones(self.num_envs, dtype=torch.bool, device=self.device) if mask is None else
                torch.as_tensor(mask, device=self.device))
        self._forget(rows)
        self._ended[rows] = False
        return self._imagine(obs, rows), info

    def step(self, actions):
        obs, reward, terminated, truncated, info = self.env.step(actions)
        ended = torch.as_tensor(terminated | truncated, device=self.device)
        same_step = self.env.metadata["autoreset_mode"] == AutoresetMode.SAME_STEP
        self._forget(ended if same_step else self._ended)
        self._ended = ended
        return self._imagine(obs, None), reward, terminated, truncated, info

    def _check(self) -> None:
        if not isinstance(self.model, StreamModel) or self.imaginer.members:
            raise CheckpointError("the imagined-body observation reads one stream model (train.model = \"stream\", "
                                  "train.ensemble = 1)")
        for channel, width in zip(self.imaginer.inputs.channels, self.imaginer.inputs.widths):
            if channel.name not in READINGS or tuple(READINGS[channel.name](self.arms).shape)[1] != width:
                raise CheckpointError(f"the checkpoint reads {channel.name} ({width} features), which this env does "
                                      f"not give alike: it gives {', '.join(READINGS)}")

    def _forget(self, rows: torch.Tensor) -> None:
        """A new episode's arm starts with the model's fresh memory (the stream's start: a zero state)."""
        for part in self._parts():
            part[:, rows] = 0.0

    def _parts(self) -> tuple[torch.Tensor, ...]:
        return self._state if isinstance(self._state, tuple) else (self._state,)

    @torch.inference_mode()
    def _imagine(self, obs: dict[str, Any], rows: Optional[torch.Tensor]) -> dict[str, Any]:
        """Advance the memories of the arms of the mask `rows` (None: every arm) by their newest sample, as one
        batched call on the device; every arm's latest imagination."""
        raw = torch.cat([torch.as_tensor(READINGS[c.name](self.arms), device=self.device)
                         for c in self.imaginer.inputs.channels], dim=1)
        sample = (raw.double() @ self._scale + self._offset).float()[rows if rows is not None else slice(None), None]
        before = tuple(p[:, rows] if rows is not None else p for p in self._parts())
        states, after = self.model.rnn(sample, before if self._lstm else before[0])
        for part, new in zip(self._parts(), after if self._lstm else (after,)):
            if rows is None:
                part.copy_(new)
            else:
                part[:, rows] = new
        latent, log_error = self.model.head(states[:, 0]).float(), self.model.error(states[:, 0]).float()
        if rows is None:
            self._latent, self._log_error = latent, log_error
        else:
            self._latent[rows], self._log_error[rows] = latent, log_error
        confidence = 1.0 / (1.0 + self._log_error.exp().mean(dim=1, keepdim=True))  # Prediction.confidence
        out = {"imagined": self._latent.clone(), "confidence": confidence}
        if self.pixels:
            out["imagined_pixels"] = torch.as_tensor(
                self.imaginer.decode(self._latent.double().cpu().numpy()).astype(np.float32), device=self.device)
        if not self.tensors:
            out = {key: value.cpu().numpy() for key, value in out.items()}
        return {**obs, **out}
