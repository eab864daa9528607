"""The folds the surprise is judged in out of fold: the corpus's motion groups from its manifest, else each
recording, and what a recording no manifest lists belongs to."""

import json
from types import SimpleNamespace

from softarm.corpus.manifest import motion_group
from softarm.learn.trust_fits import surprise_folds


def test_a_recording_belongs_to_the_group_its_manifest_lists_it_under(tmp_path):
    (tmp_path / "corpus.json").write_text(json.dumps({"groups": {
        "slow": {"recordings": ["slow_arm0.mcap", "slow_arm1.mcap"]}, "fast": {"recordings": ["fast_arm0.mcap"]}}}))
    assert motion_group(tmp_path / "slow_arm1.mcap") == "slow"
    assert motion_group(tmp_path / "fast_arm0.mcap") == "fast"
    assert motion_group(tmp_path / "other.mcap") == ""
    assert motion_group(tmp_path / "elsewhere" / "slow_arm0.mcap") == ""  # no manifest beside it
    (tmp_path / "corpus.json").write_text("not json")
    assert motion_group(tmp_path / "slow_arm0.mcap") == ""


def test_folds_are_the_groups_where_two_or_more_are_named_else_the_recordings():
    def runs(*groups):
        return [SimpleNamespace(name=f"r{i}.mcap", group=g) for i, g in enumerate(groups)]

    assert surprise_folds(runs("slow", "fast", "slow")) == ["slow", "fast", "slow"]
    assert surprise_folds(runs("slow", "slow")) == ["recording 0", "recording 1"]  # one group: no motion new to it
    assert surprise_folds(runs("slow", "")) == ["recording 0", "recording 1"]  # one not listed: groups unknown
