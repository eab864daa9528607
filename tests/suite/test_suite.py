"""The held-out suite: its families and reserved seeds, the recordings `softarm suite` writes (every arm in
the camera's view), and `softarm evaluate` on it beside the baselines."""

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from softarm.config import load_config
from softarm.record.reader import read_recording
from softarm.sim.simulate import simulate
from softarm.suite.families import (
    CANDIDATES,
    DURATION,
    FAMILIES,
    SEED_BLOCK,
    SUITE_SEED_BASE,
    SUITE_VERSION,
    level_seeds,
)
from softarm.suite.manifest import read_suite
from tests.helpers.cli import assert_one_line_error, softarm
from tests.helpers.shared import made_once


@pytest.fixture(scope="session")
def suite_folder(tmp_path_factory):
    """The whole suite, written by the real command once for every worker (about 25 s here)."""
    def write(folder: Path) -> None:
        result = softarm("suite", str(folder), "-q", cwd=folder, timeout=300)
        assert result.returncode == 0, result.stderr

    return made_once(tmp_path_factory, "suite", write)


def test_at_least_six_families_each_at_two_levels_from_reserved_seeds():
    assert len(FAMILIES) >= 6 and all(len(f.levels) >= 2 for f in FAMILIES)
    blocks = [seed for _, _, seed in level_seeds()]
    assert blocks[0] == SUITE_SEED_BASE and np.all(np.diff(blocks) == SEED_BLOCK)
    assert any(level.sensing for f in FAMILIES for level in f.levels)  # a case with sensor noise


@pytest.mark.slow
def test_the_suite_keeps_every_arm_in_view_and_uses_only_its_seeds(suite_folder):
    suite = read_suite(suite_folder)
    assert suite.version == SUITE_VERSION and suite.families == [f.name for f in FAMILIES]
    manifest = json.loads((suite_folder / "suite.json").read_text())
    for family in FAMILIES:
        for level in family.levels:
            entry = manifest["families"][family.name]["levels"][level.name]
            assert len(entry["recordings"]) == 2 and all(s >= SUITE_SEED_BASE for s in entry["seeds"])
    for case in suite.cases:
        rec = read_recording(case.path, nodes=False)
        assert rec.complete and rec.model["seed"] >= SUITE_SEED_BASE
        frames = rec.frames
        assert not (frames[:, :, 0].any() or frames[:, :, -1].any() or frames[:, -1, :].any()), case.path.name
        assert frames.any(axis=(1, 2)).all()  # the arm is in every frame
    assert sorted(p.name for p in suite_folder.glob("*.mcap")) == sorted(c.path.name for c in suite.cases)


@pytest.mark.slow
def test_a_level_simulated_again_gives_the_same_files_and_a_written_suite_is_refused(suite_folder, tmp_path):
    """The same softarm writes the same bytes: one level re-simulated as `softarm suite` runs it (the whole suite
    again would double this file's time)."""
    family, level, seed = next(entry for entry in level_seeds() if entry[0].name == "multisine_broad")
    stem = f"{family.name}_level{family.levels.index(level)}"
    config = load_config(overrides={**level.overrides, "run.duration": DURATION, "run.seed": seed,
                                    "run.arms": CANDIDATES})
    simulate(config, tmp_path / f"{stem}.mcap")
    entry = json.loads((suite_folder / "suite.json").read_text())["families"][family.name]["levels"][level.name]
    assert len(entry["recordings"]) == 2
    for name in entry["recordings"]:
        assert (tmp_path / name).read_bytes() == (suite_folder / name).read_bytes()
    again = softarm("suite", str(suite_folder), cwd=tmp_path)
    assert_one_line_error(again, "already holds a suite", "--force")


def part_of_suite(suite_folder, folder, families: tuple[str, ...]):
    """The named families of a written suite, one recording per level, as a suite folder of its own."""
    manifest = json.loads((suite_folder / "suite.json").read_text())
    manifest["families"] = {name: manifest["families"][name] for name in families}
    for family in manifest["families"].values():
        for level in family["levels"].values():
            level["recordings"] = level["recordings"][:1]
            shutil.copy(suite_folder / level["recordings"][0], folder)
    (folder / "suite.json").write_text(json.dumps(manifest))
    return folder


@pytest.fixture(scope="module")
def small_suite(suite_folder, tmp_path_factory):
    """Three families (evaluation in seconds)."""
    return part_of_suite(suite_folder, tmp_path_factory.mktemp("small"), ("paper_amplitude", "sensor_noise", "push"))


@pytest.mark.slow
def test_evaluate_writes_every_family_with_its_baselines_and_skill(small_suite, tiny_checkpoint, tmp_path):
    result = softarm("evaluate", str(tiny_checkpoint.checkpoint), str(small_suite), "--json", "e.json",
                     "--png", "e.png", "--trust-png", "t.png", cwd=tmp_path, timeout=300)
    assert result.returncode == 0, result.stderr
    assert "paper_amplitude" in result.stdout and "sensor_noise" in result.stdout
    document = json.loads((tmp_path / "e.json").read_text())
    assert (document["suite"] == SUITE_VERSION
            and set(document["families"]) == {"paper_amplitude", "sensor_noise", "push"})
    for row in document["families"].values():
        assert row["frames"] in (2 * 1994, 3 * 1994)  # per level, every frame after the first 6-sample window
        assert set(row["baselines"]) == {"mean_frame", "ridge", "ae_ceiling", "ridge_nodes"}
        floor, ceiling = row["baselines"]["mean_frame"]["iou"], row["baselines"]["ae_ceiling"]["iou"]
        assert row["skill"] == pytest.approx((row["iou"] - floor) / (ceiling - floor))
        for scores in (row, *row["baselines"].values()):
            assert 0 <= scores["iou"] <= 1 and scores["bce"] > 0 and scores["tip_error_mm"] >= 0
        assert 0 <= row["tip_error_median_mm"] <= 3 * row["tip_error_mm"]
    report = document["confidence"]
    assert report["default"] == "calibrated" and list(report["methods"]) == ["error_head", "calibrated"]  # no ensemble
    trust = report["methods"]["error_head"]
    assert trust["frames"] == sum(row["frames"] for row in document["families"].values())
    assert -1 <= trust["spearman"] <= 1 and 0 <= trust["least_trusted_iou"] <= 1 and "least trusted" in result.stdout
    assert len(trust["sparsification"]) == len(trust["oracle"]) == 100 and trust["ause"] >= 0
    assert set(trust["reference"]) == {"spearman", "auroc", "ause", "least_trusted_iou", "rest_iou"}
    felt = document["surprise"]["families"]
    assert list(felt) == ["push"] and 0 <= felt["push"]["auroc"] <= 1 and felt["push"]["disturbances"] >= 6
    assert 0 <= felt["push"]["detected_suite"] <= 1 and "surprise" in result.stdout
    for png in ("e.png", "t.png"):
        assert (tmp_path / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.slow
def test_sensor_noise_reaches_the_stretch_answers_and_nothing_else(suite_folder, tiny_checkpoint, tmp_path):
    from softarm.suite.scoring import evaluate_suite

    calm = part_of_suite(suite_folder, tmp_path, ("paper_amplitude",))  # one family: two evaluations in seconds
    clean = evaluate_suite(tiny_checkpoint.checkpoint, calm)["families"]["paper_amplitude"]
    noisy = evaluate_suite(tiny_checkpoint.checkpoint, calm,
                           sensor_noise={"noise": 1e-2})["families"]["paper_amplitude"]
    assert noisy["baselines"]["ridge"]["iou"] < clean["baselines"]["ridge"]["iou"] - 0.05  # 10 mm of noise hurts
    assert noisy["iou"] != clean["iou"]
    for camera_side in ("mean_frame", "ae_ceiling"):
        assert noisy["baselines"][camera_side] == clean["baselines"][camera_side]


def test_evaluate_refuses_a_folder_without_a_suite(tiny_checkpoint, tmp_path):
    result = softarm("evaluate", str(tiny_checkpoint.checkpoint), str(tmp_path), "--json", "e.json", cwd=tmp_path)
    assert_one_line_error(result, "holds no suite", "softarm suite")
    assert not (tmp_path / "e.json").exists()


@pytest.mark.slow
def test_training_refuses_a_recording_of_the_suite(suite_folder, tmp_path):
    held_out = read_suite(suite_folder).cases[0].path
    result = softarm("train", str(held_out), "--out", "x.pt", cwd=tmp_path)
    assert_one_line_error(result, held_out.name, "held-out")
    assert not (tmp_path / "x.pt").exists()


@pytest.mark.slow
def test_ctrl_c_stops_the_suite_without_a_manifest(tmp_path):
    import signal
    import subprocess
    import time

    from tests.helpers.cli import SOFTARM

    proc = subprocess.Popen([SOFTARM, "suite", str(tmp_path), "-q"], cwd=tmp_path, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 120
    while not list(tmp_path.glob("*.mcap")) and time.time() < deadline:  # the first level's files have closed
        time.sleep(0.05)
    proc.send_signal(signal.SIGINT)
    _, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 130, stderr
    assert "interrupted" in stderr and not (tmp_path / "suite.json").exists()
