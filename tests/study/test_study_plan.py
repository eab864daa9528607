"""Studies as data: the built-in grids, the sensor placements they compute from the body, and the checks
that refuse a user's study file in one line naming the bad key, before anything runs."""

import pytest

from softarm.config import load_config
from softarm.errors import ConfigError
from softarm.study.builtin import BUILTIN, SENSOR_COUNTS, load_study
from softarm.study.placements import MAX_SPAN, PLACEMENTS, sensor_pairs
from tests.helpers.cli import assert_one_line_error, softarm

GOOD = '''name = "mine"
variable = "latent features"
quick = ["small"]

[[trials]]
name = "small"
value = 4
overrides = { "train.latent" = 4 }

[[trials]]
name = "large"
[trials.overrides.train]
latent = 32
'''


def test_four_edge_sensors_are_the_default_sensors():
    config = load_config()
    assert sensor_pairs("edges", 4, config) == [list(p) for p in config.sensors.pairs]


@pytest.mark.parametrize("placement", PLACEMENTS)
def test_every_placement_stretches_distinct_pairs_down_the_arm(placement):
    config = load_config()
    columns, nodes = config.body.columns, config.body.rows * config.body.columns
    for count in SENSOR_COUNTS:
        pairs = sensor_pairs(placement, count, config)
        assert len(pairs) == count and len({tuple(p) for p in pairs}) == count
        for upper, lower in pairs:
            assert columns <= upper < lower < nodes            # below the driven row, inside the body
            assert upper // columns < lower // columns          # along the arm, never across one row
            if placement == "random":
                assert lower // columns - upper // columns <= MAX_SPAN
    assert sensor_pairs(placement, 8, config) == sensor_pairs(placement, 8, config)  # seeded


def test_edges_keep_to_the_outer_columns_and_spread_reaches_the_middle_one():
    config = load_config()
    column = lambda pairs: {node % config.body.columns for pair in pairs for node in pair}  # noqa: E731
    assert column(sensor_pairs("edges", 16, config)) == {0, 2}
    assert column(sensor_pairs("spread", 16, config)) == {0, 1, 2}


@pytest.mark.parametrize("name", BUILTIN)
def test_every_built_in_trial_is_a_valid_config_with_its_own_name(name):
    study = load_study(name)
    names = [t.name for t in study.trials]
    assert len(set(names)) == len(names) and study.quick_trials() and set(study.quick) <= set(names)
    for trial in study.trials:
        load_config(overrides=trial.overrides)


def test_a_study_file_reads_dotted_and_nested_overrides(tmp_path):
    (tmp_path / "mine.toml").write_text(GOOD)
    study = load_study(tmp_path / "mine.toml")
    assert [(t.name, t.value, t.overrides) for t in study.trials] == [
        ("small", 4, {"train.latent": 4}), ("large", "large", {"train.latent": 32})]
    assert [t.name for t in study.quick_trials()] == ["small"]


@pytest.mark.parametrize("edit, words", [
    (("variable =", "varable ="), ["unknown key 'varable'", "known keys"]),
    (('value = 4', 'value = 4\nseting = 1'), ["unknown key 'trials[0].seting'"]),
    (('"train.latent" = 4', '"train.latnet" = 4'), ["trial small", "train.latnet", "did you mean"]),
    (('"train.latent" = 4', '"train.latent" = 0'), ["trial small", "train.latent", "out of range"]),
    (('name = "large"', 'name = "small"'), ["two trials are named 'small'"]),
    (('quick = ["small"]', 'quick = ["tiny"]'), ["'quick' names 'tiny'"]),
    (('name = "large"', 'name = "a/b"'), ["trials[1].name 'a/b'"]),
    (('value = 4', 'value = [4]'), ["trials[0].value"]),
    (("[[trials]]", "[[trial]]"), ["unknown key 'trial'"]),
    ((" = 4 }", " = 4"), ["not valid TOML"]),
])
def test_a_bad_study_file_is_refused_in_one_line_naming_the_key(tmp_path, edit, words):
    (tmp_path / "bad.toml").write_text(GOOD.replace(*edit, 1))
    with pytest.raises(ConfigError) as caught:
        load_study(tmp_path / "bad.toml")
    message = str(caught.value)
    assert "\n" not in message and all(word in message for word in words), message


@pytest.mark.slow
def test_the_cli_refuses_a_bad_study_before_any_work(tmp_path):
    (tmp_path / "bad.toml").write_text(GOOD.replace("variable =", "varable =", 1))
    assert_one_line_error(softarm("study", "bad.toml", "--out", "s", cwd=tmp_path), "unknown key 'varable'")
    assert_one_line_error(softarm("study", "sensor", "--out", "s", cwd=tmp_path), "sensors, noise, history, latent")
    assert not (tmp_path / "s").exists()
