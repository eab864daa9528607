"""Config loading: defaults reproduce the paper, files and overrides merge, bad values name their key."""

import pytest

from softarm.config import DEFAULT_CONFIG_TEXT, config_from_dict, load_config
from softarm.errors import ConfigError


def test_defaults_are_the_papers_constants():
    c = load_config()
    assert (c.body.rows * c.body.columns, c.body.node_mass) == (57, 0.01)
    assert (c.springs.stiffness, c.springs.damping) == (1000.0, 0.9)
    assert c.excitation.frequencies == (2.11, 3.73, 4.33)
    assert (c.camera.height, c.camera.width, c.integration.frame_dt, c.n_frames) == (84, 52, 0.01, 10000)
    assert len(c.sensors.pairs) == 4


def test_a_file_changes_only_the_keys_it_names(tmp_path):
    (tmp_path / "c.toml").write_text("[springs]\nstiffness = 500\n[run]\nseed = 4\n")
    c = load_config(tmp_path / "c.toml", {"run.duration": 5.0, "run.arms": None})
    assert (c.springs.stiffness, c.springs.damping, c.run.seed, c.run.duration, c.run.arms) == (500.0, 0.9, 4, 5.0, 1)


def test_config_round_trips_through_its_dict():
    c = load_config(overrides={"camera.outline": [0, 54, 56, 2]})
    assert config_from_dict(c.to_dict()) == c
    assert "outline" not in load_config().to_dict()["camera"]  # unset optional keys are not written


def test_every_default_key_is_documented_in_the_default_file():
    def check(table: str, values: dict) -> None:
        assert f"[{table}]" in DEFAULT_CONFIG_TEXT, table
        for key, value in values.items():
            if isinstance(value, dict):
                check(f"{table}.{key}", value)
            else:
                written = f"\n{key} = " in DEFAULT_CONFIG_TEXT or f"[[{table}.{key}]]" in DEFAULT_CONFIG_TEXT
                assert written, f"{table}.{key}"

    for section, values in load_config().to_dict().items():
        if isinstance(values, dict):
            check(section, values)
        else:  # a top-level list of tables ([[disturbances]])
            assert f"\n{section} = " in DEFAULT_CONFIG_TEXT, section


@pytest.mark.parametrize("overrides, words", [
    ({"body.gravity": [0.0]}, ["body.gravity", "2 values"]),
    ({"run.arms": 1.5}, ["run.arms", "integer"]),
    ({"run.arms": True}, ["run.arms", "integer"]),
    ({"excitation.amplitude_jitter": 1.0}, ["excitation.amplitude_jitter", "[0, 1)"]),
    ({"excitation.rhythm_jitter": -0.1}, ["excitation.rhythm_jitter", "[0, 1)"]),
    ({"sensors.pairs": [[4, 4]]}, ["sensors.pairs[0]", "two different nodes"]),
    ({"excitation.frequencies": []}, ["excitation.frequencies", "at least one"]),
    ({"body.length": float("nan")}, ["body.length", "finite"]),
    ({"excitation.kind": "square"}, ["excitation.kind", "product_of_sines", "sum_of_sines"]),
    ({"excitation.direction": [1.0, 1.0]}, ["excitation.direction", "unit vector"]),
    ({"excitation.direction": [0.0, 0.0]}, ["excitation.direction", "unit vector"]),
    ({"excitation.sum_of_sines.band": [2.0, 2.0]}, ["excitation.sum_of_sines.band", "f_min < f_max"]),
    ({"excitation.sum_of_sines.band": [-1.0, 2.0]}, ["excitation.sum_of_sines.band", "0 < f_min"]),
    ({"excitation.sum_of_sines.band": [1.0]}, ["excitation.sum_of_sines.band"]),
    ({"excitation.sum_of_sines.rms": -0.001}, ["excitation.sum_of_sines.rms", ">= 0"]),
    ({"excitation.sum_of_sines.components": 0}, ["excitation.sum_of_sines.components", ">= 1"]),
    ({"excitation.sum_of_sines.amplitudes": [0.001], "excitation.sum_of_sines.frequencies": [1.0, 2.0],
      "excitation.sum_of_sines.phases": [0.0]}, ["excitation.sum_of_sines.amplitudes", "one value per component"]),
    ({"excitation.sum_of_sines.amplitudes": [0.001], "excitation.sum_of_sines.frequencies": [0.0],
      "excitation.sum_of_sines.phases": [0.0]}, ["excitation.sum_of_sines.frequencies", "> 0"]),
    ({"sensing.noise": -1e-6}, ["sensing.noise", ">= 0"]),
    ({"sensing.dropout_sensor": -2}, ["sensing.dropout_sensor"]),
    ({"sensing.pairs": [[1, 2]], "sensing.dropout_sensor": 1}, ["sensing.dropout_sensor", "0..0"]),
])
def test_bad_values_name_the_key_and_what_is_allowed(overrides, words):
    with pytest.raises(ConfigError) as info:
        load_config(overrides=overrides)
    for word in words:
        assert word in str(info.value)


def test_softarm_config_prints_a_file_that_loads_as_the_defaults(tmp_path):
    from tests.helpers.cli import softarm

    result = softarm("config", cwd=tmp_path)
    assert result.returncode == 0
    (tmp_path / "c.toml").write_text(result.stdout)
    assert load_config(tmp_path / "c.toml") == load_config()
