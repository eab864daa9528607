"""The README's picture of the control tasks: each task's colour view (`render_mode="rgb_array"`) at a few moments
of one episode, driven by a scripted command (the static command of the nearest workspace place, ramped over
one second; Hold: the passive arm).

    python docs/scripts/control_tasks.py docs/images/control_tasks.png
"""

import sys

import gymnasium
import numpy as np
from PIL import Image

import softarm.envs
from softarm.envs.workspace import STREAM

MOMENTS = (0, 50, 100, 200, 300)  # steps (10 ms each)


def frames(task: str) -> list[np.ndarray]:
    env = gymnasium.make(softarm.envs.IDS[task], render_mode="rgb_array")
    arms = env.unwrapped.arms
    commands = np.random.default_rng(STREAM).uniform(0, 1, (len(arms.task.places), arms.muscles.count))
    env.reset(seed=4)
    out = []
    for step in range(max(MOMENTS) + 1):
        if step in MOMENTS:
            out.append(env.render())
        nearest = np.argmin(np.linalg.norm(arms.task.places - arms.target[0], axis=1))
        command = commands[nearest] * min(1.0, step / 100) if task != "hold" else np.zeros(arms.muscles.count)
        env.step(command)
    env.close()
    return out


def main(out: str) -> None:
    rows = [np.concatenate(frames(task), axis=1) for task in ("reach", "track", "hold")]
    Image.fromarray(np.concatenate(rows, axis=0)).save(out)


if __name__ == "__main__":
    main(sys.argv[1])
