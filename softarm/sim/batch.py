"""The arms of a run as they start: one body, one drive and one start state per seed.

`simulate`, the tests and the benchmarks all start arms through `arm_batch`, so a test's arm is
exactly the arm a real run would record.
"""

from dataclasses import dataclass
from typing import TYPE_CHECKING, Optional, Sequence

import numpy as np

from softarm.arm.body import Body, build_body
from softarm.arm.drive import Drive, drive_for_seed
from softarm.arm.statics import check_step, hanging_equilibrium, initial_state
from softarm.config import Config

if TYPE_CHECKING:  # the disturbances carry their kernel code: Taichi loads when a batch is built, not on import
    from softarm.disturbances import Disturbance


@dataclass(frozen=True)
class ArmBatch:
    body: Body
    seeds: list[int]
    drives: list[Drive]
    positions: np.ndarray   # (arms, N, 2) at t = 0, m
    velocities: np.ndarray  # (arms, N, 2) at t = 0, m/s
    disturbances: list[list["Disturbance"]]  # each arm's, in the order its recording lists them

    @property
    def arms(self) -> int:
        return len(self.seeds)


def arm_batch(config: Config, seeds: Optional[Sequence[int]] = None) -> ArmBatch:
    """The run's arms (seeds run.seed .. run.seed + arms - 1 unless given), their disturbances checked and drawn,
    the step checked for stability with each arm's own."""
    body = build_body(config)
    seeds = list(seeds) if seeds is not None else [config.run.seed + i for i in range(config.run.arms)]
    drives = [drive_for_seed(config.excitation, s) for s in seeds]
    hanging = hanging_equilibrium(body)
    from softarm.disturbances.places import Places
    from softarm.disturbances.resolve import check_world, resolve

    places = Places(body, config.body.columns, hanging, config.world)
    check_world(config, places)
    disturbances = [resolve(config, places, s) for s in seeds]
    for world in {tuple(arm) for arm in disturbances}:  # each arm with its own: arms never touch each other
        check_step(config, body, world)
    starts = [initial_state(hanging, d) for d in drives]
    return ArmBatch(body=body, seeds=seeds, drives=drives, positions=np.stack([p for p, _ in starts]),
                    velocities=np.stack([v for _, v in starts]), disturbances=disturbances)
