"""Hold's pushes on the simulator: one push slot per arm (the world's Push, docs/model.md, Disturbances),
rewritten at each of the arm's episode starts with the push its task drew, its window moved to the run's clock."""

import numpy as np

from softarm.disturbances import Push
from softarm.envs.tasks import Hold
from softarm.sim.physics import Simulator


def row_nodes(row: int, columns: int) -> tuple[int, ...]:
    return tuple(range(row * columns, (row + 1) * columns))


def placeholders(arms: int, columns: int) -> list[list[Push]]:
    """A slot per arm that never acts ([0, 0)), so that the kernel is compiled with the pushes' code."""
    return [[Push(0.0, 0.0, (0.0, 0.0), row_nodes(0, columns))] for _ in range(arms)]


def place_pushes(sim: Simulator, task: Hold, arms: np.ndarray, now: float, columns: int) -> None:
    """The drawn pushes of the given arms, whose episodes start at run time `now`, into their slots."""
    world = sim.world
    windows, params, nodes = world.windows.to_numpy(), world.params.to_numpy(), world.nodes.to_numpy()
    for a in arms:
        windows[a, 0] = now + task.push_window[a]
        params[a, 0, :2] = task.push_force[a]
        nodes[a, 0] = 0
        nodes[a, 0, list(row_nodes(int(task.push_row[a]), columns))] = 1
    world.windows.from_numpy(windows)
    world.params.from_numpy(params)
    world.nodes.from_numpy(nodes)


def episode_push(task: Hold, arm: int, columns: int) -> Push:
    """The arm's push in its episode's own time, as its recording lists it."""
    start, end = task.push_window[arm]
    return Push(float(start), float(end), tuple(float(f) for f in task.push_force[arm]),
                row_nodes(int(task.push_row[arm]), columns))
