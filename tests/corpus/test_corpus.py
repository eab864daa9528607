"""`softarm corpus`: its groups, their seeds (never the suite's), the files and manifest it writes, and
`softarm train DIR` learning from all of them."""

import json

import numpy as np
import pytest

from softarm.arm.drive import HELD_OUT_SEED_BASE, drive_for_seed
from softarm.config import load_config
from softarm.corpus.build import write_corpus
from softarm.corpus.presets import DEFAULT_ARMS, PRESETS, arms_per_group, seeds_of
from softarm.model.checkpoint import load_checkpoint
from softarm.record.reader import read_recording
from tests.helpers.cli import assert_one_line_error, softarm


@pytest.mark.parametrize("arms", [1, 15, 64, 1000])
def test_arms_are_spread_over_every_group(arms):
    counts = arms_per_group(PRESETS["general"], arms)
    assert min(counts) >= 1 and sum(counts) == max(arms, len(counts))


def test_group_seeds_never_overlap_and_stay_below_the_suite():
    groups = PRESETS["general"]
    counts = arms_per_group(groups, 10_000 * len(groups) // 20)
    blocks = [range(seeds_of(k, n), seeds_of(k, n) + n) for k, n in enumerate(counts)]
    seeds = [s for block in blocks for s in block]
    assert len(set(seeds)) == len(seeds) and max(seeds) < HELD_OUT_SEED_BASE


def test_the_general_corpus_plays_the_papers_drive_at_five_rhythms_and_between_them():
    """The five product groups play the paper's drive at their listed rhythm, arm after arm; the last four play it
    at a rhythm of each arm's own, drawn in four bands from 0.65 to 1.45 times the paper's, none of them the same."""
    groups = PRESETS["general"]
    paper = np.array(load_config().excitation.frequencies)
    drawn = []
    for k, (group, arms) in enumerate(zip(groups, arms_per_group(groups, DEFAULT_ARMS))):
        excitation = load_config(overrides=group.overrides).excitation
        if excitation.kind != "product_of_sines":
            continue
        ratios = np.array([drive_for_seed(excitation, seed).frequencies
                           for seed in range(seeds_of(k, arms), seeds_of(k, arms) + arms)]) / paper
        assert np.ptp(ratios, axis=1).max() < 1e-3  # every arm plays the paper's three frequencies scaled alike
        if excitation.rhythm_jitter == 0:
            assert np.ptp(ratios) < 1e-3
        else:
            low, high = (float(x) for x in group.name.removeprefix("product_x").split("-"))
            assert np.all((ratios[:, 0] >= low - 1e-9) & (ratios[:, 0] <= high + 1e-9))
            drawn.extend(ratios[:, 0])
    assert len(drawn) == 16 and len(set(np.round(drawn, 6))) == 16
    assert 0.65 <= min(drawn) and max(drawn) <= 1.45 and np.ptp(drawn) > 0.6


@pytest.mark.slow
def test_a_general_corpus_holds_every_group_with_its_motion(tmp_path):
    manifest = write_corpus(tmp_path, arms=len(PRESETS["general"]), duration=0.2)
    document = json.loads(manifest.read_text())
    assert list(document["groups"]) == [g.name for g in PRESETS["general"]]
    seeds = []
    for group in PRESETS["general"]:
        entry = document["groups"][group.name]
        rec = read_recording(tmp_path / entry["recordings"][0], nodes=False)
        assert rec.model["excitation"]["kind"] == group.overrides.get("excitation.kind", "product_of_sines")
        seeds.extend(entry["seeds"])
    assert len(set(seeds)) == len(seeds) and max(seeds) < HELD_OUT_SEED_BASE
    assert sorted(p.name for p in tmp_path.glob("*.mcap")) == sorted(
        name for entry in document["groups"].values() for name in entry["recordings"])


@pytest.mark.slow
def test_train_learns_from_a_corpus_folder(tmp_path):
    result = softarm("corpus", "runs", "--preset", "paper", "--arms", "2", "--duration", "4", "-q", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    again = softarm("corpus", "runs", "--preset", "paper", "--arms", "2", cwd=tmp_path)
    assert_one_line_error(again, "already holds a corpus", "--force")
    trained = softarm("train", "runs", "--epochs-ae", "1", "--epochs-lstm", "1", "-q", cwd=tmp_path, timeout=300)
    assert trained.returncode == 0, trained.stderr
    state = load_checkpoint(tmp_path / "recordings" / "runs.pt")
    assert [r["name"] for r in state["recordings"]] == ["paper_arm0.mcap", "paper_arm1.mcap"]


@pytest.mark.slow
def test_unknown_presets_and_empty_folders_are_refused_in_one_line(tmp_path):
    assert_one_line_error(softarm("corpus", "c", "--preset", "everything", cwd=tmp_path), "--preset", "general")
    (tmp_path / "empty").mkdir()
    assert_one_line_error(softarm("train", "empty", cwd=tmp_path), "empty", "holds no recordings")
