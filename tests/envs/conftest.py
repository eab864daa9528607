import numpy as np
import pytest

from tests.helpers.cli import softarm as run_softarm
from tests.helpers.tiny import tiny_toml


@pytest.fixture(scope="session")
def babble(tmp_path_factory):
    """Two 4 s babbling episodes of Reach, recorded by the env, and a checkpoint `softarm train` learned from the
    first with the stretch and the muscles' activation as inputs."""
    from softarm.config import load_config
    from softarm.envs.babble import babble

    folder = tmp_path_factory.mktemp("babble")
    paths = babble(folder / "episodes", 2, 4.0, config=load_config(overrides={"control.workspace_samples": 16})).paths
    toml = folder / "tiny.toml"
    toml.write_text(tiny_toml() + 'inputs = ["stretch", "activation"]\n')
    trained = run_softarm("train", str(paths[0]), "--config", str(toml), "--out", str(folder / "babble.pt"),
                          cwd=folder, timeout=600)
    return paths, folder / "babble.pt", trained


def random_commands(steps: int, arms: int, seed: int = 0) -> np.ndarray:
    return np.random.default_rng(seed).uniform(0, 1, (steps, arms, 4))
