"""The GPU's kernel (`layout="gathered"`: one thread per arm, arms innermost, forces gathered per node from two
state buffers) run on the CPU backend against the CPU's kernel (lanes) and the NumPy reference: the default run,
every kind of disturbance, muscles under command, a blow-up, and a state placed between blocks."""

import numpy as np
import pytest

from softarm.arm.body import build_body
from softarm.arm.drive import drive_for_seed
from softarm.arm.muscles import build_muscles
from softarm.arm.reference import simulate_reference
from softarm.arm.statics import hanging_equilibrium
from softarm.config import load_config
from softarm.errors import SimulationError
from softarm.sim.batch import arm_batch
from softarm.sim.gathered import incident_springs
from softarm.sim.physics import Simulator
from tests.sim.test_disturbances import ONE_OF_EACH

EQUAL = 0.0  # m: the two kernels do the same operations in the same order, so they agree to the bit


def positions(config, arms: int, frames: int, layout: str, muscles=None, commands=None) -> np.ndarray:
    batch = arm_batch(config, seeds=range(arms))
    sim = Simulator.from_config(config, batch, block_frames=50, muscles=muscles, layout=layout)
    assert sim.layout == layout
    out = []
    for block in range(frames // 50):
        if commands is not None:
            sim.command(commands[block])
        sim.step_block(50)
        out.append(sim.history[:, :50].copy())
    sim.close()
    return np.concatenate(out, axis=1)


def test_each_nodes_springs_are_listed_in_the_springs_order_with_their_sign():
    starts, entries = incident_springs(np.array([[0, 1], [1, 2], [0, 2]]), 3)
    assert starts.tolist() == [0, 2, 4, 6]
    assert entries.tolist() == [1, 3, -1, 2, -2, -3]  # node 0: first end of 0 and 2; node 2: second end of 1, 2


@pytest.mark.slow
def test_the_default_run_steps_the_same_in_both_layouts_and_as_the_numpy_reference():
    config = load_config(overrides={"run.duration": 10.0})
    lanes, gathered = (positions(config, 4, 1000, layout) for layout in ("lanes", "gathered"))
    assert np.abs(gathered - lanes).max() <= EQUAL
    batch = arm_batch(config, seeds=[2])
    i = config.integration
    reference = simulate_reference(batch.body, batch.drives[0], batch.positions[0], batch.velocities[0], i.frame_dt,
                                   i.substeps, 200)
    assert np.abs(gathered[2, :200] - reference).max() < 1e-9


@pytest.mark.slow
def test_every_kind_of_disturbance_steps_the_same_in_both_layouts():
    """All four kinds in one run (each acting over its own interval, contact from the start): one kernel compiled
    per layout instead of four."""
    config = load_config(overrides={"disturbances": list(ONE_OF_EACH.values()), "excitation.amplitude": 0.006})
    lanes, gathered = (positions(config, 2, 200, layout) for layout in ("lanes", "gathered"))
    assert np.abs(gathered - lanes).max() <= EQUAL


@pytest.mark.slow
def test_commanded_muscles_step_the_same_in_both_layouts():
    config = load_config(overrides={"excitation.amplitude": 0.0})
    muscles = build_muscles(config, arm_batch(config).body)
    commands = np.random.default_rng(5).uniform(0, 1, (4, 3, muscles.count))
    lanes, gathered = (positions(config, 3, 200, layout, muscles, commands) for layout in ("lanes", "gathered"))
    assert np.abs(gathered[:, -1] - gathered[:, 0]).max() > 1e-3  # the muscles move the arms
    assert np.abs(gathered - lanes).max() <= EQUAL


@pytest.mark.slow
def test_a_blow_up_is_found_at_the_same_frame_and_node():
    config = load_config(overrides={"integration.substeps": 2})
    body = build_body(config)  # not arm_batch: its stability check refuses 2 substeps before any blow-up
    x, i = hanging_equilibrium(body), config.integration
    messages = []
    for layout in ("lanes", "gathered"):
        drives = [drive_for_seed(config.excitation, seed) for seed in (0, 1)]
        sim = Simulator(body, drives, i.frame_dt, i.substeps, i.blowup_distance, x, np.zeros_like(x), 50, (), None,
                        layout)
        with pytest.raises(SimulationError) as caught:
            sim.advance(300)
        messages.append(str(caught.value))
        sim.close()
    assert messages[0] == messages[1] and "blew up" in messages[0]


@pytest.mark.slow
def test_a_state_placed_between_blocks_is_where_the_next_block_starts():
    config = load_config()
    runs = []
    for layout in ("lanes", "gathered"):
        batch = arm_batch(config, seeds=range(3))
        sim = Simulator.from_config(config, batch, block_frames=25, layout=layout)
        sim.step_block(25)
        sim.place(np.array([1]), batch.positions[1], batch.velocities[1])
        sim.step_block(25)
        runs.append(np.concatenate([sim.history[:, :25].copy(), sim.state()[0][:, None]], axis=1))
        sim.close()
    assert np.abs(runs[1] - runs[0]).max() <= EQUAL
