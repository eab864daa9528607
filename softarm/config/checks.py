"""Ranges every simulation and training needs to be meaningful, with messages that name the key."""

import math
from typing import Any

from softarm.config.schema import Config, ExcitationConfig, SensingConfig, TrainConfig
from softarm.errors import ConfigError
from softarm.model.registry import TRUST

INTEGRATORS = ("symplectic_euler",)
EXCITATION_KINDS = ("product_of_sines", "sum_of_sines")
PRECISIONS = ("auto", "fp32", "bf16")  # train.precision: softarm.learn.precision
MAX_SEED = 2**32 - 1


def _require(ok: bool, key: str, value: Any, allowed: str) -> None:
    if not ok:
        raise ConfigError(f"config key '{key}' = {value!r} is out of range: {allowed}")


def check_ranges(c: Config) -> None:
    """Values every simulation needs to be meaningful; node indices are checked against the body."""
    b, e, cam, i, r = c.body, c.excitation, c.camera, c.integration, c.run
    _require(b.rows >= 2, "body.rows", b.rows, "must be at least 2 (one driven row and one free row)")
    _require(b.columns >= 2, "body.columns", b.columns, "must be at least 2")
    for key in ("length", "base_width", "tip_width", "node_mass"):
        value = getattr(b, key)
        _require(value > 0, f"body.{key}", value, "must be > 0")
    _require(c.springs.stiffness > 0, "springs.stiffness", c.springs.stiffness, "must be > 0")
    _require(c.springs.damping >= 0, "springs.damping", c.springs.damping, "must be >= 0")
    _check_excitation(e)
    _require(e.offset_range >= 0, "excitation.offset_range", e.offset_range, "must be >= 0")
    _require(0 <= e.amplitude_jitter < 1, "excitation.amplitude_jitter", e.amplitude_jitter, "must be in [0, 1)")
    _require(len(c.sensors.pairs) >= 1, "sensors.pairs", [], "must list at least one [a, b] node pair")
    for k, (a, bb) in enumerate(c.sensors.pairs):
        _require(a != bb, f"sensors.pairs[{k}]", [a, bb], "a sensor must join two different nodes")
    _check_sensing(c.sensing)
    _require(cam.width >= 1, "camera.width", cam.width, "must be >= 1")
    _require(cam.height >= 1, "camera.height", cam.height, "must be >= 1")
    _require(cam.pixels_per_metre > 0, "camera.pixels_per_metre", cam.pixels_per_metre, "must be > 0")
    _require(i.frame_dt > 0, "integration.frame_dt", i.frame_dt, "must be > 0 (the frame rate is 1 / frame_dt)")
    _require(i.substeps >= 1, "integration.substeps", i.substeps, "must be >= 1")
    _require(i.integrator in INTEGRATORS, "integration.integrator", i.integrator, f"must be one of {list(INTEGRATORS)}")
    _require(i.blowup_distance > 0, "integration.blowup_distance", i.blowup_distance, "must be > 0")
    _require(r.duration > 0, "run.duration", r.duration, "must be > 0")
    _require(c.n_frames >= 1, "run.duration", r.duration, f"must cover at least one frame of {i.frame_dt} s")
    _require(r.arms >= 1, "run.arms", r.arms, "must be >= 1")
    _require(0 <= r.seed <= MAX_SEED - (r.arms - 1), "run.seed", r.seed,
             f"must be in 0..{MAX_SEED - (r.arms - 1)} (seeds are 32-bit; arm i of run.arms = {r.arms} uses run.seed + i)")
    _check_control(c)
    _check_train(c.train)


def _check_control(c: Config) -> None:
    k = c.control
    for key in ("episode", "tolerance", "hold", "track_period", "reward_scale"):
        _require(getattr(k, key) > 0, f"control.{key}", getattr(k, key), "must be > 0")
    _require(k.hold < k.episode, "control.hold", k.hold, f"must be shorter than control.episode = {k.episode} s")
    _require(k.shake_amplitude >= 0, "control.shake_amplitude", k.shake_amplitude, "must be >= 0 (m)")
    _require(k.workspace_samples >= 1, "control.workspace_samples", k.workspace_samples, "must be >= 1")
    _require(0 <= k.push_force[0] <= k.push_force[1], "control.push_force", list(k.push_force),
             "must be [min, max] with 0 <= min <= max (N per node; [0, 0]: no push)")
    _require(0 < k.push_duration[0] <= k.push_duration[1], "control.push_duration", list(k.push_duration),
             "must be [min, max] with 0 < min <= max (s)")


def _check_train(t: TrainConfig) -> None:
    _require(0 < t.train_fraction < 1, "train.train_fraction", t.train_fraction, "must be in (0, 1)")
    _require(0 < t.test_fraction and t.train_fraction + t.test_fraction < 1, "train.test_fraction",
             t.test_fraction, "must be > 0 and leave room for the imagination segment")
    _require(0 <= t.validation_recordings < 1, "train.validation_recordings", t.validation_recordings,
             "must be in [0, 1)")
    for key in ("latent", "history", "sequence", "streams", "epochs_ae", "epochs_lstm", "batch_ae", "batch_lstm",
                "lstm_hidden"):
        _require(getattr(t, key) >= 1, f"train.{key}", getattr(t, key), "must be >= 1")
    for key in ("max_steps_ae", "max_steps_lstm"):
        _require(getattr(t, key) >= 0, f"train.{key}", getattr(t, key), "must be >= 0 (0: no cap)")
    for key in ("lr_ae", "lr_lstm"):
        _require(getattr(t, key) > 0, f"train.{key}", getattr(t, key), "must be > 0")
    _require(0 <= t.min_feature_std < 1, "train.min_feature_std", t.min_feature_std, "must be in [0, 1)")
    _require(0 <= t.seed <= MAX_SEED, "train.seed", t.seed, f"must be in 0..{MAX_SEED} (seeds are 32-bit)")
    _require(t.node_target >= 0, "train.node_target", t.node_target, "must be >= 0 (0: no node target)")
    _require(t.precision in PRECISIONS, "train.precision", t.precision, f"must be one of {list(PRECISIONS)}")
    _require(1 <= t.ensemble <= 16, "train.ensemble", t.ensemble, "must be in 1..16 (1: one model)")
    _require(t.confidence in TRUST, "train.confidence", t.confidence, f"must be one of {list(TRUST)}")  # the registry's
    _require(t.confidence != "ensemble" or t.ensemble > 1, "train.confidence", t.confidence,
             "needs train.ensemble > 1 (members to disagree)")
    _require(t.false_alarms_per_minute > 0, "train.false_alarms_per_minute", t.false_alarms_per_minute, "must be > 0")


def _check_sensing(s: SensingConfig) -> None:
    for key in ("noise", "bias", "drift", "quantisation", "dropout_time"):
        _require(getattr(s, key) >= 0, f"sensing.{key}", getattr(s, key), "must be >= 0")
    _require(0 <= s.seed <= MAX_SEED, "sensing.seed", s.seed, f"must be in 0..{MAX_SEED} (seeds are 32-bit)")
    _require(s.dropout_sensor >= -1, "sensing.dropout_sensor", s.dropout_sensor, "must be a sensor index, or -1 for none")
    if s.pairs:
        _require(s.dropout_sensor < len(s.pairs), "sensing.dropout_sensor", s.dropout_sensor,
                 f"must be -1 or an index into sensing.pairs (0..{len(s.pairs) - 1})")
    for k, (a, b) in enumerate(s.pairs):
        _require(a != b, f"sensing.pairs[{k}]", [a, b], "a sensor must join two different nodes")


def _check_excitation(e: ExcitationConfig) -> None:
    _require(e.kind in EXCITATION_KINDS, "excitation.kind", e.kind, f"must be one of {list(EXCITATION_KINDS)}")
    norm = math.hypot(*e.direction)
    _require(abs(norm - 1) < 1e-9, "excitation.direction", list(e.direction),
             f"must be a unit vector (its length is {norm:.6g}), e.g. [1.0, 0.0] sideways or [0.0, 1.0] up")
    _require(e.amplitude >= 0, "excitation.amplitude", e.amplitude, "must be >= 0")
    _require(len(e.frequencies) >= 1, "excitation.frequencies", list(e.frequencies), "must list at least one frequency")
    s = e.sum_of_sines
    key = "excitation.sum_of_sines"
    _require(len(s.band) == 2 and 0 < s.band[0] < s.band[1], f"{key}.band", list(s.band),
             "must be [f_min, f_max] with 0 < f_min < f_max (Hz)")
    _require(s.components >= 1, f"{key}.components", s.components, "must be >= 1")
    _require(s.rms >= 0, f"{key}.rms", s.rms, "must be >= 0 (m)")
    lengths = {len(s.amplitudes), len(s.frequencies), len(s.phases)}
    _require(len(lengths) == 1, f"{key}.amplitudes", list(s.amplitudes),
             "amplitudes, frequencies and phases must list one value per component (or all be empty)")
    _require(all(f > 0 for f in s.frequencies), f"{key}.frequencies", list(s.frequencies), "must all be > 0 (Hz)")
    _require(all(a >= 0 for a in s.amplitudes), f"{key}.amplitudes", list(s.amplitudes), "must all be >= 0 (m)")
