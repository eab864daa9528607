import os

if "PYTEST_XDIST_WORKER_COUNT" in os.environ:  # `pytest -n N`: the cores shared among the workers (and every command
    # they start), before torch reads it; OpenMP threads of two trainings on two cores would oversubscribe them
    _cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
    os.environ.setdefault("OMP_NUM_THREADS", str(max(1, _cores // int(os.environ["PYTEST_XDIST_WORKER_COUNT"]))))

import pytest

from softarm.config import load_config
from softarm.sim.runtime import init_taichi
from tests.helpers.tiny import TINY


@pytest.fixture(scope="session", autouse=True)
def library_logs_in_the_tests_folder(tmp_path_factory):
    """Stable-Baselines3 makes a log folder for every training, in the system's temporary folder unless told
    (`SB3_LOGDIR`): the tests' trainings and the example runs they start (which inherit it) make theirs here."""
    os.environ["SB3_LOGDIR"] = str(tmp_path_factory.mktemp("sb3_logs"))


@pytest.fixture(scope="session", autouse=True)
def taichi_on_cpu():
    """Taichi starts once per test process, on the CPU with float64, as the CLI would start it."""
    init_taichi("cpu")


@pytest.fixture(scope="session")
def recordings(tmp_path_factory):
    """Two 4 s recordings (seeds 0 and 1) and a 1 s one with 3 sensors."""
    from softarm.sim.simulate import simulate

    folder = tmp_path_factory.mktemp("rec")
    for seed in (0, 1):
        simulate(load_config(overrides={"run.duration": 4.0, "run.seed": seed}), folder / f"s{seed}.mcap")
    simulate(load_config(overrides={"run.duration": 1.0, "sensors.pairs": [[3, 27], [5, 29], [27, 54]]}),
             folder / "three_sensors.mcap")
    return folder


@pytest.fixture(scope="session")
def tiny_checkpoint(recordings, tmp_path_factory):
    """A few seconds of training on the 4 s seed-0 recording, its live view saved beside it as tiny.rrd."""
    from softarm.learn.training import train

    folder = tmp_path_factory.mktemp("ckpt")
    return train([recordings / "s0.mcap"], load_config(overrides=TINY), folder / "tiny.pt", rrd=folder / "tiny.rrd")


@pytest.fixture(scope="session")
def tiny_window_checkpoint(recordings, tmp_path_factory):
    """The same few seconds of training for the paper's window model (the default is the stream model)."""
    from softarm.learn.training import train

    folder = tmp_path_factory.mktemp("ckpt_window")
    return train([recordings / "s0.mcap"], load_config(overrides={**TINY, "train.model": "window"}),
                 folder / "tiny_window.pt")


@pytest.fixture(scope="session")
def tiny_tcn_checkpoint(recordings, tmp_path_factory):
    """The same few seconds of training for the causal convolution network."""
    from softarm.learn.training import train

    folder = tmp_path_factory.mktemp("ckpt_tcn")
    return train([recordings / "s0.mcap"], load_config(overrides={**TINY, "train.model": "tcn"}),
                 folder / "tiny_tcn.pt")
