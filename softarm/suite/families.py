"""The suite's families: what motion each probes, at which levels, from which reserved seeds.

A family is one question about the body image (does it hold beyond the paper's amplitude, its
frequencies, band-limited noise, a pure sine below or at the arm's resonance, noisy sensors, pokes, a
load, damage, contact?); a level is one setting of it. Everything here is part of the suite's version:
change a family, bump it.
Seeds from SUITE_SEED_BASE on belong to the suite; training refuses recordings made from them.
"""

from dataclasses import dataclass, field
from typing import Any

from softarm.arm.drive import HELD_OUT_SEED_BASE

SUITE_VERSION = "softarm-suite/2"
SUITE_SEED_BASE = HELD_OUT_SEED_BASE  # seeds >= this are the suite's: training refuses their recordings
DURATION = 20.0               # s per recording
SEEDS_PER_LEVEL = 2
CANDIDATES = 4                # the first seeds of a level's block, simulated;
                              # the first SEEDS_PER_LEVEL in view are kept
SEED_BLOCK = 10               # reserved seeds per level
SUM = "excitation.sum_of_sines."


@dataclass(frozen=True)
class Level:
    name: str
    overrides: dict[str, Any]                                 # config keys of the motion
    sensing: dict[str, float] = field(default_factory=dict)   # imperfections read at evaluation


@dataclass(frozen=True)
class Family:
    name: str
    probes: str
    levels: tuple[Level, ...]


def multisine(band: list[float], rms: float, components: int = 8) -> dict[str, Any]:
    return {"excitation.kind": "sum_of_sines", SUM + "band": band, SUM + "rms": rms, SUM + "components": components}


def sine(frequency: float, amplitude: float) -> dict[str, Any]:
    return {"excitation.kind": "sum_of_sines", SUM + "amplitudes": [amplitude], SUM + "frequencies": [frequency],
            SUM + "phases": [0.0]}


MOTION = (
    Family("paper_amplitude", "the paper's drive at its default amplitude and a smaller one: "
                              "memorised shapes or the body?",
           (Level("A=4mm (default)", {}), Level("A=2.5mm", {"excitation.amplitude": 0.0025}))),
    Family("paper_frequency", "the paper's three-sine product with every frequency scaled: other rhythms, same kind",
           (Level("f x0.8", {"excitation.frequencies": [1.688, 2.984, 3.464]}),
            Level("f x1.25", {"excitation.frequencies": [2.6375, 4.6625, 5.4125]}))),
    Family("multisine_low", "band-limited noise below the first mode (0.2-1 Hz): slow, quasi-static bending",
           (Level("rms 1.5mm", multisine([0.2, 1.0], 0.0015)), Level("rms 3mm", multisine([0.2, 1.0], 0.003)))),
    Family("multisine_mid", "band-limited noise around the first mode (1-3 Hz, resonance 1.48 Hz): "
                            "large dynamic swings",
           (Level("rms 1mm", multisine([1.0, 3.0], 0.001)), Level("rms 2mm", multisine([1.0, 3.0], 0.002)))),
    Family("multisine_broad", "broad-band noise over both first modes (0.2-6 Hz): the richest motion",
           (Level("rms 1mm", multisine([0.2, 6.0], 0.001, 16)), Level("rms 2mm", multisine([0.2, 6.0], 0.002, 16)))),
    Family("sine_slow", "one slow sine far below resonance: the arm follows its top almost rigidly",
           (Level("0.3Hz 20mm", sine(0.3, 0.02)), Level("0.6Hz 10mm", sine(0.6, 0.01)))),
    Family("sine_fast", "one sine at the first (1.5 Hz) and the second (4 Hz) mode: resonant shapes",
           (Level("1.5Hz 0.5mm", sine(1.5, 0.0005)), Level("4Hz 4mm", sine(4.0, 0.004)))),
    Family("sensor_noise", "the paper's motion read through imperfect sensors: noise, drift and quantisation",
           (Level("noise 20um", {}, {"noise": 2e-5}), Level("noise 100um", {}, {"noise": 1e-4}),
            Level("noise 20um + drift 20um/sqrt(s) + 10um steps", {},
                  {"noise": 2e-5, "drift": 2e-5, "quantisation": 1e-5}))),
)


def world(kind: str, **keys: Any) -> dict[str, Any]:
    """The overrides of a level whose every arm draws one [[world.random]] spec (one disturbance unless `count`
    says more), over the paper's drive."""
    spec = {"kind": kind, "share": 1.0, "count": [1, 1], "start": [5.0, 12.0], "rows": [18, 18], **keys}
    return {"world.random": [spec]}


WORLD = (
    Family("push", "pokes of random force, place and time: "
                   "the world touches the arm, and nothing in the command says so",
           (Level("light pokes (10-30 mN a node)", world("push", count=[3, 5], start=[2.0, 18.0], duration=[0.05, 0.15],
                                                        force=[0.01, 0.03], rows=[9, 18])),
            Level("firm pokes (30-80 mN a node)", world("push", count=[3, 5], start=[2.0, 18.0], duration=[0.05, 0.15],
                                                       force=[0.03, 0.08], rows=[9, 18])))),
    Family("payload", "a load on the tip row from a moment at 5-12 s on: a grasped object, heavier and slower",
           (Level("5 g a tip node", world("payload", mass=[0.005, 0.005])),
            Level("15 g a tip node", world("payload", mass=[0.015, 0.015])))),
    Family("damage", "a two-row segment of springs softened from a moment at 5-12 s on: damage the body must feel",
           (Level("k x0.5", world("stiffness", factor=[0.5, 0.5], rows=[4, 14], span=2)),
            Level("k x0.3", world("stiffness", factor=[0.3, 0.3], rows=[4, 14], span=2)))),
    Family("contact", "the swing meets a fixed disc from the start: contact stops and bends it",
           (Level("beside the tip", world("obstacle", start=[0.0, 0.0], rows=[15, 18], radius=[0.01, 0.02],
                                          gap=[0.003, 0.008])),
            Level("beside the middle", world("obstacle", start=[0.0, 0.0], rows=[8, 12], radius=[0.01, 0.02],
                                             gap=[0.002, 0.005])))),
)
FAMILIES = MOTION + WORLD  # softarm-suite/2: the motions of /1, then the world
GROUPS = {**{f.name: "motion" for f in MOTION}, **{f.name: "world" for f in WORLD}}


def level_seeds() -> list[tuple[Family, Level, int]]:
    """Every (family, level, first seed of its block) of the suite, in this order.

    Each level owns a block of SEED_BLOCK seeds from SUITE_SEED_BASE on; its recordings are, of the block's
    first CANDIDATES seeds, the first SEEDS_PER_LEVEL whose arm stays in the camera's view.
    """
    out, seed = [], SUITE_SEED_BASE
    for family in FAMILIES:
        for level in family.levels:
            out.append((family, level, seed))
            seed += SEED_BLOCK
    return out
