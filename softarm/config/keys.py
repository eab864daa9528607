"""Every config key's unit and allowed range, declared once: `check_ranges` refuses values by these rules and the
documentation's config reference prints them, so the two cannot disagree.

The meaning of each key lives in `default.toml`'s comments (what `softarm config` prints); the value in its
assignment. Keys of the array tables (`[[disturbances]]`, `[[world.random]]`, `[[muscles.groups]]`) are named
`table[].key`; their checks need the body and live with the body (`softarm.disturbances.resolve`,
`softarm.arm.muscles`).
"""

from dataclasses import dataclass
from typing import Any, Callable, Iterable, Optional

from softarm.errors import ConfigError

MAX_SEED = 2**32 - 1
INTEGRATORS = ("symplectic_euler",)
EXCITATION_KINDS = ("product_of_sines", "sum_of_sines")
PRECISIONS = ("auto", "fp32", "bf16")  # train.precision: softarm.learn.precision
DEVICES = ("auto", "cpu", "cuda")      # train.device: softarm.model.device


@dataclass(frozen=True)
class Rule:
    """An allowed range: `text` is what a refusal and the reference say ("must be > 0"), `ok` tests a value."""
    text: str
    ok: Callable[[Any], bool]


@dataclass(frozen=True)
class Key:
    """One config key: its SI unit ("" for counts, names and flags), its range (None: any value of its type) and,
    for the keys of array tables that `default.toml` leaves empty, their meaning."""
    unit: str = ""
    rule: Optional[Rule] = None
    meaning: str = ""


def above(bound: float, why: str = "") -> Rule:
    return Rule(f"must be > {bound:g}{why}", lambda v: v > bound)


def at_least(bound: float, why: str = "") -> Rule:
    return Rule(f"must be >= {bound:g}{why}", lambda v: v >= bound)


def between(low: float, high: float, *, open_high: bool = True, open_low: bool = False, why: str = "") -> Rule:
    brackets = ("(" if open_low else "[") + f"{low:g}, {high:g}" + (")" if open_high else "]")
    return Rule(f"must be in {brackets}{why}",
                lambda v: (low < v if open_low else low <= v) and (v < high if open_high else v <= high))


def one_of(values: Iterable[str]) -> Rule:
    values = tuple(values)
    return Rule(f"must be one of {list(values)}", lambda v: v in values)


def seed() -> Rule:
    return Rule(f"must be in 0..{MAX_SEED} (seeds are 32-bit)", lambda v: 0 <= v <= MAX_SEED)


def require(key: str, value: Any, where: Optional[str] = None) -> None:
    """Refuse `value` of `key` (named `where` in the message, e.g. an array table's `muscles.groups[2].rows`) when
    it breaks the key's declared rule (an optional key left out, None, has nothing to break)."""
    rule = KEYS[key].rule
    if rule is not None and value is not None and not rule.ok(value):
        shown = [list(v) if isinstance(v, tuple) else v for v in value] if isinstance(value, tuple) else value
        raise ConfigError(f"config key '{where or key}' = {shown!r} is out of range: {rule.text}")


POSITIVE = above(0)
NON_NEGATIVE = at_least(0)
ONE_OR_MORE = at_least(1)

KEYS: dict[str, Key] = {
    "disturbances": Key(meaning="The world acting on the body: a list of [[disturbances]] tables."),
    "disturbances[].kind": Key(meaning="push, payload, stiffness, obstacle or drag (docs/model.md, Disturbances)."),
    "disturbances[].start": Key("s", meaning="Run time from which it acts."),
    "disturbances[].end": Key("s", meaning="Run time at which it stops acting; leave it out for the end of the run."),
    "disturbances[].force": Key("N", meaning="push: [Fx, Fy] on each of its nodes."),
    "disturbances[].nodes": Key(meaning="push, payload: the node indices it acts on."),
    "disturbances[].mass": Key("kg", meaning="payload: mass added to each of its nodes (inertia and weight)."),
    "disturbances[].factor": Key(meaning="stiffness: multiplier of each of its springs' stiffness (< 1: damage)."),
    "disturbances[].springs": Key(meaning="stiffness: the spring indices of the model (docs/model.md, Body)."),
    "disturbances[].centre": Key("m", meaning="obstacle: [x, y] of the disc's centre."),
    "disturbances[].radius": Key("m", meaning="obstacle: the disc's radius."),
    "disturbances[].stiffness": Key("N/m",
                                    meaning="obstacle: its contact stiffness (default: world.contact_stiffness)."),
    "disturbances[].damping": Key("N s/m", meaning="obstacle: its contact damping (default: world.contact_damping)."),
    "disturbances[].velocity": Key("m/s", meaning="drag: [ux, uy] of the water's current (default [0, 0]: still)."),
    "disturbances[].coefficient": Key("N s/m", meaning="drag: c of the linear (Stokes) drag on every free node."),
    "disturbances[].quadratic": Key("N s^2/m^2", meaning="drag: c2 of the quadratic (form) drag (default 0)."),
    "body.rows": Key(rule=Rule("must be at least 2 (one driven row and one free row)", lambda v: v >= 2)),
    "body.columns": Key(rule=Rule("must be at least 2", lambda v: v >= 2)),
    "body.length": Key("m", POSITIVE),
    "body.base_width": Key("m", POSITIVE),
    "body.tip_width": Key("m", POSITIVE),
    "body.node_mass": Key("kg", POSITIVE),
    "body.gravity": Key("m/s²"),
    "body.driven": Key(),
    "springs.stiffness": Key("N/m", POSITIVE),
    "springs.damping": Key("N s/m", NON_NEGATIVE),
    "excitation.kind": Key(rule=one_of(EXCITATION_KINDS)),
    "excitation.direction": Key(rule=Rule("must be a unit vector, e.g. [1.0, 0.0] sideways or [0.0, 1.0] up",
                                          lambda v: abs((v[0] ** 2 + v[1] ** 2) ** 0.5 - 1) < 1e-9)),
    "excitation.amplitude": Key("m", NON_NEGATIVE),
    "excitation.frequencies": Key("Hz", Rule("must list at least one frequency", lambda v: len(v) >= 1)),
    "excitation.time_offset": Key("s"),
    "excitation.offset_range": Key("s", NON_NEGATIVE),
    "excitation.amplitude_jitter": Key(rule=between(0, 1)),
    "excitation.rhythm_jitter": Key(rule=between(0, 1)),
    "excitation.sum_of_sines.amplitudes": Key("m", Rule("must all be >= 0 (m)", lambda v: all(a >= 0 for a in v))),
    "excitation.sum_of_sines.frequencies": Key("Hz", Rule("must all be > 0 (Hz)", lambda v: all(f > 0 for f in v))),
    "excitation.sum_of_sines.phases": Key("rad"),
    "excitation.sum_of_sines.band": Key("Hz", Rule("must be [f_min, f_max] with 0 < f_min < f_max (Hz)",
                                                   lambda v: len(v) == 2 and 0 < v[0] < v[1])),
    "excitation.sum_of_sines.components": Key(rule=ONE_OR_MORE),
    "excitation.sum_of_sines.rms": Key("m", at_least(0, " (m)")),
    "sensors.pairs": Key(rule=Rule("must list at least one [a, b] node pair", lambda v: len(v) >= 1)),
    "sensing.pairs": Key(),
    "sensing.noise": Key("m", NON_NEGATIVE),
    "sensing.bias": Key("m", NON_NEGATIVE),
    "sensing.drift": Key("m/√s", NON_NEGATIVE),
    "sensing.quantisation": Key("m", NON_NEGATIVE),
    "sensing.dropout_sensor": Key(rule=Rule("must be a sensor index, or -1 for none", lambda v: v >= -1)),
    "sensing.dropout_time": Key("s", NON_NEGATIVE),
    "sensing.seed": Key(rule=seed()),
    "sensors.bend": Key(),
    "sensing.bend": Key(),
    "sensing.bend_noise": Key("rad", NON_NEGATIVE),
    "camera.width": Key("px", ONE_OR_MORE),
    "camera.height": Key("px", ONE_OR_MORE),
    "camera.pixels_per_metre": Key("px/m", POSITIVE),
    "camera.origin": Key("px"),
    "camera.outline": Key(),
    "integration.frame_dt": Key("s", above(0, " (the frame rate is 1 / frame_dt)")),
    "integration.substeps": Key(rule=ONE_OR_MORE),
    "integration.integrator": Key(rule=one_of(INTEGRATORS)),
    "integration.blowup_distance": Key("m", POSITIVE),
    "run.duration": Key("s", POSITIVE),
    "run.arms": Key(rule=ONE_OR_MORE),
    "run.seed": Key(rule=Rule(f"must be in 0..{MAX_SEED} - (run.arms - 1): arm i uses run.seed + i",
                              lambda v: v >= 0)),
    "world.contact_stiffness": Key("N/m", NON_NEGATIVE),
    "world.contact_damping": Key("N s/m", NON_NEGATIVE),
    "world.random": Key(meaning="Random disturbances every arm draws from its seed: a list of [[world.random]] "
                                "tables."),
    "world.random[].kind": Key(meaning="push, payload, stiffness, obstacle or drag."),
    "world.random[].share": Key(meaning="Share of the arms that draw any of this kind, 0..1."),
    "world.random[].count": Key(meaning="[min, max] disturbances of this kind an arm draws."),
    "world.random[].start": Key("s", meaning="[min, max] of their start times."),
    "world.random[].rows": Key(meaning="push, payload, stiffness, obstacle: [first, last] body rows they reach."),
    "world.random[].duration": Key("s", meaning="[min, max] of how long each acts; leave it out for lasting ones."),
    "world.random[].force": Key("N", meaning="push: [min, max] force per node, in a random direction, on one row."),
    "world.random[].mass": Key("kg", meaning="payload: [min, max] mass per node of one row."),
    "world.random[].factor": Key(meaning="stiffness: [min, max] multiplier of the springs' stiffness."),
    "world.random[].span": Key(meaning="stiffness: how many rows of springs, from a random row."),
    "world.random[].radius": Key("m", meaning="obstacle: [min, max] of the disc's radius."),
    "world.random[].gap": Key("m", meaning="obstacle: [min, max] gap from the arm's resting edge at a row, on a "
                                           "random side."),
    "world.random[].speed": Key("m/s", meaning="drag: [min, max] speed of the current, in a random direction."),
    "world.random[].coefficient": Key("N s/m", meaning="drag: [min, max] of the linear drag coefficient c."),
    "world.random[].quadratic": Key("N s^2/m^2", meaning="drag: [min, max] of the quadratic coefficient c2 "
                                                         "(default 0)."),
    "muscles.time_constant": Key("s", above(0, " s")),
    "muscles.groups": Key(meaning="The muscle groups: a list of [[muscles.groups]] tables."),
    "muscles.groups[].name": Key(),
    "muscles.groups[].side": Key(),
    "muscles.groups[].rows": Key(),
    "muscles.groups[].springs": Key(meaning="The group's springs as spring indices of the model (docs/model.md, "
                                            "Body), instead of side and rows."),
    "muscles.groups[].max_contraction": Key(rule=between(
        0, 1, open_low=True, why=" (the share of the rest length a full activation takes off)")),
    "control.episode": Key("s", POSITIVE),
    "control.tolerance": Key("m", POSITIVE),
    "control.hold": Key("s", POSITIVE),
    "control.track_period": Key("s", POSITIVE),
    "control.shake_amplitude": Key("m", at_least(0, " (m)")),
    "control.reward_scale": Key("m", POSITIVE),
    "control.workspace_samples": Key(rule=ONE_OR_MORE),
    "control.push_force": Key("N", Rule("must be [min, max] with 0 <= min <= max (N per node; [0, 0]: no push)",
                                        lambda v: 0 <= v[0] <= v[1])),
    "control.push_duration": Key("s", Rule("must be [min, max] with 0 < min <= max (s)", lambda v: 0 < v[0] <= v[1])),
    "train.train_fraction": Key(rule=between(0, 1, open_low=True)),
    "train.test_fraction": Key(rule=Rule("must be > 0 and leave room for the imagination segment", lambda v: v > 0)),
    "train.latent": Key(rule=ONE_OR_MORE),
    "train.history": Key("samples", ONE_OR_MORE),
    "train.include_current": Key(),
    "train.inputs": Key(),
    "train.model": Key(),
    "train.sequence": Key("samples", ONE_OR_MORE),
    "train.streams": Key(rule=ONE_OR_MORE),
    "train.validation_recordings": Key(rule=between(0, 1)),
    "train.epochs_ae": Key(rule=ONE_OR_MORE),
    "train.epochs_lstm": Key(rule=ONE_OR_MORE),
    "train.max_steps_ae": Key(rule=at_least(0, " (0: no cap)")),
    "train.max_steps_lstm": Key(rule=at_least(0, " (0: no cap)")),
    "train.batch_ae": Key("frames", ONE_OR_MORE),
    "train.batch_lstm": Key(rule=ONE_OR_MORE),
    "train.lr_ae": Key(rule=POSITIVE),
    "train.lr_lstm": Key(rule=POSITIVE),
    "train.lstm_hidden": Key(rule=ONE_OR_MORE),
    "train.min_feature_std": Key(rule=between(0, 1)),
    "train.seed": Key(rule=seed()),
    "train.precision": Key(rule=one_of(PRECISIONS)),
    "train.device": Key(rule=one_of(DEVICES)),
    "train.node_target": Key(rule=at_least(0, " (0: no node target)")),
    "train.ensemble": Key(rule=Rule("must be in 1..16 (1: one model)", lambda v: 1 <= v <= 16)),
    "train.confidence": Key(),  # one of the trust registry's kinds: checked in `checks`
    "train.false_alarms_per_minute": Key("1/min", POSITIVE),
}
