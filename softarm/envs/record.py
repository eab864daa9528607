"""Episodes of a single env written as softarm recordings (docs/recording.md): the camera, the ideal stretch of
the model's sensors, the nodes, the top's drive, and the muscles' commands and activations on `/arm/activation`,
with everything needed to re-simulate the episode in the metadata. `softarm train` learns the body from them
(`train.inputs = ["stretch", "activation"]` reads the command beside the feeling) and `softarm replay` shows one.

    env = RecordEpisodes(gymnasium.make("softarm/Reach-v0"), "recordings/babble")
"""

import dataclasses
from pathlib import Path
from typing import Any, Optional, Union

import gymnasium
import numpy as np

from softarm.arm.sensors import stretch
from softarm.envs.arms import Arms
from softarm.envs.pushes import episode_push
from softarm.errors import OutputError, SoftarmError
from softarm.files import check_outputs
from softarm.record.writer import RecordingWriter, model_metadata


class RecordEpisodes(gymnasium.Wrapper):
    """Writes every episode to `folder/episode_0000.mcap`, `episode_0001.mcap`, ...; an episode cut off by a reset
    or `close` before it ended is kept with `complete = "false"`. Existing files are never replaced."""

    def __init__(self, env: gymnasium.Env, folder: Union[str, Path], prefix: str = "episode"):
        super().__init__(env)
        self.folder, self.prefix, self.episodes = Path(folder), prefix, 0
        self.written: list[Path] = []
        if self.folder.is_dir() and any(self.folder.glob(f"{prefix}_*.mcap")):
            raise OutputError(f"{self.folder} holds {prefix}_*.mcap episodes already: record into an empty folder "
                              "(episodes are never replaced)")
        self.folder.mkdir(parents=True, exist_ok=True)
        self._frames: Optional[dict[str, list]] = None

    @property
    def arms(self) -> Arms:
        return self.env.unwrapped.arms

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict[str, Any]] = None):
        self._finish(complete=False)
        obs, info = self.env.reset(seed=seed, options=options)
        self._frames = {key: [] for key in ("images", "stretch", "positions", "displacement", "command", "activation")}
        self._start = (self.arms.x[0].copy(), self.arms.v[0].copy())
        self._keep()
        return obs, info

    def step(self, action):
        obs, reward, terminated, truncated, info = self.env.step(action)
        if self._frames is not None:
            self._frames["command"].append(self.arms.commands[0].copy())  # held from the frame before to this one
            self._keep()
            if terminated or truncated:
                self._finish(complete=True)
        return obs, reward, terminated, truncated, info

    def close(self) -> None:
        self._finish(complete=False)
        super().close()

    def _keep(self) -> None:
        a, f = self.arms, self._frames
        f["images"].append(a.frames()[0])
        f["stretch"].append(stretch(a.x[0], a.body.rest, a.body.sensors))
        f["positions"].append(a.x[0].copy())
        f["displacement"].append(a.displacement(0))
        f["activation"].append(a.activation[0].copy())

    def _finish(self, complete: bool) -> None:
        """Write the episode so far: each frame's command is the one held from it to the next (the last frame's,
        the one held into it)."""
        if self._frames is None:
            return
        f, self._frames = self._frames, None
        commands = f["command"] + ([f["command"][-1]] if f["command"] else [np.zeros(self.arms.muscles.count)])
        path = self.folder / f"{self.prefix}_{self.episodes:04d}.mcap"
        check_outputs([path], force=False)
        writer = RecordingWriter(path, self._model(), self.arms.dt)
        try:
            writer.write(np.stack(f["images"]), np.stack(f["stretch"]), np.stack(f["positions"]),
                         np.array(f["displacement"]), (np.stack(commands), np.stack(f["activation"])))
        except OSError as e:
            writer.discard()
            raise SoftarmError(f"cannot write {path}: {e}") from None
        self.written.append(writer.close(complete))
        self.episodes += 1

    def _model(self) -> dict[str, Any]:
        a = self.arms
        drive = dataclasses.replace(a.drives[0], time_offset=float(a.t0[0]))
        pushes = [episode_push(a.task, 0, a.config.body.columns)] if a.task.pushed else []
        model = model_metadata(a.config, a.body, drive, int(self.env.unwrapped.np_random_seed), *self._start, pushes)
        muscles = a.muscles
        model["muscles"] = {"names": list(muscles.names), "time_constant": muscles.time_constant,
                            "max_contraction": muscles.max_contraction.tolist(),
                            "springs": [np.flatnonzero(muscles.group == g).tolist() for g in range(muscles.count)]}
        model["task"] = {"name": a.task.name, "target": a.target[0].tolist()}
        return model
