"""Every loader, fed damaged files: truncations, bit flips, overwritten, inserted and deleted bytes, random bytes,
and valid JSON or a checkpoint of the wrong shape. Each must read the file or refuse it with a softarm error in
one line, never raise anything else and never hang. The cases are drawn by Hypothesis, derandomised (CI sees
the same ones); every loader must meet both outcomes, so the cases reach past its first check."""

from pathlib import Path
from typing import Any, Callable

import pytest
import torch
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from softarm.config import DEFAULT_CONFIG_TEXT, load_config
from softarm.corpus.manifest import folder_recordings
from softarm.imagine.trained import TrainedModel
from softarm.record.reader import read_model, read_recording
from softarm.study.plan import read_study
from softarm.suite.families import SUITE_VERSION
from softarm.suite.manifest import read_suite
from tests.helpers.fuzz import damaged, json_bytes, refused_or_read, reshaped

pytestmark = pytest.mark.slow  # each test runs the CLI, trains or compiles kernels: seconds


def fuzz(examples: int, case: Callable[[Any], bool]) -> None:
    """Run `case(data)` on `examples` drawn cases; it returns whether the loader read the file. Both outcomes must
    occur."""
    outcomes: list[bool] = []

    @settings(max_examples=examples, deadline=None, derandomize=True, database=None,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
    @given(data=st.data())
    def run(data: Any) -> None:
        outcomes.append(case(data))

    run()
    assert len(outcomes) >= examples * 0.9 and any(outcomes) and not all(outcomes), \
        f"{sum(outcomes)} read, {len(outcomes) - sum(outcomes)} refused"


@pytest.fixture(scope="module")
def short_recording(tmp_path_factory) -> Path:
    from softarm.sim.simulate import simulate

    path = tmp_path_factory.mktemp("fuzz") / "short.mcap"
    simulate(load_config(overrides={"run.duration": 0.3}), path)
    return path


def test_damaged_recordings_are_read_or_refused(short_recording, tmp_path):
    original, path = short_recording.read_bytes(), tmp_path / "damaged.mcap"

    def case(data: Any) -> bool:
        path.write_bytes(data.draw(damaged(original)))
        refused_or_read(lambda: read_model(path))
        return refused_or_read(lambda: read_recording(path, nodes=data.draw(st.booleans())))

    fuzz(1000, case)


def test_damaged_checkpoints_are_read_or_refused(tiny_checkpoint, tmp_path):
    original, path = tiny_checkpoint.checkpoint.read_bytes(), tmp_path / "damaged.pt"

    def case(data: Any) -> bool:
        path.write_bytes(data.draw(damaged(original)))
        return refused_or_read(lambda: TrainedModel(path))

    fuzz(200, case)


WRONG_VALUES = st.one_of(st.none(), st.integers(-3, 10**6), st.text(max_size=5), st.lists(st.integers(), max_size=3),
                         st.builds(torch.zeros, st.lists(st.integers(0, 3), max_size=3)))


def test_checkpoints_of_the_wrong_shape_are_read_or_refused(tiny_checkpoint, tmp_path):
    path = tmp_path / "reshaped.pt"

    def case(data: Any) -> bool:
        state = torch.load(tiny_checkpoint.checkpoint, weights_only=True)
        where = state
        for _ in range(data.draw(st.integers(0, 2))):  # into a nested table, now and then
            tables = sorted(k for k, v in where.items() if isinstance(v, dict) and v)
            if tables:
                where = where[data.draw(st.sampled_from(tables))]
        key = data.draw(st.sampled_from(sorted(where)))
        if data.draw(st.booleans()):
            del where[key]
        else:
            where[key] = data.draw(WRONG_VALUES)
        torch.save(state, path)
        return refused_or_read(lambda: TrainedModel(path))

    fuzz(200, case)


SUITE = {"suite": SUITE_VERSION, "families": {"paper": {"probes": "p", "levels": {
    "x": {"overrides": {}, "sensing": {}, "seeds": [1], "recordings": ["a.mcap"]}}}}}
CORPUS = {"preset": "paper", "arms": 1, "duration": 0.3,
          "groups": {"paper": {"overrides": {}, "recordings": ["a.mcap"], "seeds": [0]}}}


@pytest.mark.parametrize("manifest, name, load", [(SUITE, "suite.json", read_suite),
                                                  (CORPUS, "corpus.json", folder_recordings)])
def test_damaged_folder_manifests_are_read_or_refused(short_recording, tmp_path, manifest, name, load):
    (tmp_path / "a.mcap").write_bytes(short_recording.read_bytes())

    def case(data: Any) -> bool:
        (tmp_path / name).write_bytes(data.draw(st.one_of(damaged(json_bytes(manifest)),
                                                          st.builds(json_bytes, reshaped(manifest)))))
        return refused_or_read(lambda: load(tmp_path))

    fuzz(600, case)


STUDY = b"""name = "s"
variable = "latent features"
quick = ["a"]
[[trials]]
name = "a"
value = 4
group = "g"
overrides = { "train.latent" = 4 }
[[trials]]
name = "b"
value = 8
overrides = { train = { latent = 8, model = "gru" } }
"""


@pytest.mark.parametrize("original, load", [(STUDY, read_study), (DEFAULT_CONFIG_TEXT.encode(), load_config)],
                         ids=["study file", "config"])
def test_damaged_toml_files_are_read_or_refused(tmp_path, original, load):
    path = tmp_path / "file.toml"

    def case(data: Any) -> bool:
        path.write_bytes(data.draw(damaged(original)))
        return refused_or_read(lambda: load(path))

    fuzz(600, case)
