"""What a corpus holds: groups of arms, each one motion family with its own seeds.

`paper` is the paper's drive at as many time offsets as arms. `general` spreads the arms over every kind
of motion the arm can live through: the paper's product at five rhythms and amplitudes and, arm by arm,
at every rhythm from 0.65 to 1.45 times the paper's,
band-limited multisines from quasi-static to both first modes (1.48 and 3.99 Hz), and single sines
in five bands whose amplitudes keep the swing inside the camera's view (small at resonance); and over
all of them the world (`world_mix`): about half of the arms are poked, loaded, damaged or meet an
obstacle. The ranges cover the suite's levels without being them, and every seed stays below the suite's.
"""

from dataclasses import dataclass
from typing import Any

from softarm.arm.drive import HELD_OUT_SEED_BASE

SEED_BLOCK = 10_000   # seeds per group: group g uses g * SEED_BLOCK + arm
DEFAULT_ARMS = 80     # `softarm corpus`'s arms; GENERAL counts its groups' arms at this size
SUM = "excitation.sum_of_sines."


@dataclass(frozen=True)
class Group:
    name: str
    overrides: dict[str, Any]
    share: float   # of the corpus's arms
    world: bool = False  # its arms draw the disturbances of `world_mix`


def world_mix(duration: float) -> dict[str, Any]:
    """[[world.random]] specs every arm of a `world` group draws from its seed: pokes (30 % of the arms), a tip
    load (15 %), a damaged segment (15 %), an obstacle beside the swing (15 %), independently; about 43 % draw
    none. Times scale with the recordings' duration."""
    later = [0.1 * duration, 0.75 * duration]
    def spec(kind: str, share: float, **keys: Any) -> dict[str, Any]:
        return {"kind": kind, "share": share, "count": [1, 1], "start": later, **keys}
    return {"world.random": [
        spec("push", 0.3, count=[1, 6], start=[0.02 * duration, 0.97 * duration], duration=[0.05, 0.2],
             force=[0.01, 0.08], rows=[6, 18]),
        spec("payload", 0.15, mass=[0.003, 0.02], rows=[16, 18]),
        spec("stiffness", 0.15, factor=[0.25, 0.7], rows=[2, 15], span=2),
        spec("obstacle", 0.15, start=[0.0, 0.0], radius=[0.008, 0.025], gap=[0.002, 0.01], rows=[6, 18])]}


def _multisine(band: list[float], rms: float, components: int = 8) -> dict[str, Any]:
    return {"excitation.kind": "sum_of_sines", SUM + "band": band, SUM + "rms": rms, SUM + "components": components,
            "excitation.amplitude_jitter": 0.3}


def _sine(band: list[float], rms: float) -> dict[str, Any]:
    return {**_multisine(band, rms, 1), "excitation.amplitude_jitter": 0.5}


def _product(scale: float, amplitude: float, rhythms: float = 0.0) -> dict[str, Any]:
    """The paper's drive at `scale` times its rhythm; with `rhythms` > 0 each arm plays it at a rhythm of its own,
    drawn within that fraction of `scale`."""
    return {"excitation.frequencies": [round(f * scale, 4) for f in (2.11, 3.73, 4.33)],
            "excitation.amplitude": amplitude, "excitation.amplitude_jitter": 0.3, "excitation.rhythm_jitter": rhythms}


GENERAL = (  # (group, its motion, its arms in a corpus of DEFAULT_ARMS)
    ("product_x0.7", _product(0.7, 0.004), 4),
    ("product_x0.85", _product(0.85, 0.004), 3),
    ("product_x1", _product(1.0, 0.003), 5),
    ("product_x1.2", _product(1.2, 0.004), 3),
    ("product_x1.4", _product(1.4, 0.004), 3),
    ("multisine_0.1-1Hz", _multisine([0.1, 1.0], 0.003), 6),
    ("multisine_0.5-2Hz", _multisine([0.5, 2.0], 0.0012), 6),
    ("multisine_1-3Hz", _multisine([1.0, 3.0], 0.0015), 6),
    ("multisine_2-6Hz", _multisine([2.0, 6.0], 0.002, 12), 5),
    ("multisine_0.1-6Hz", _multisine([0.1, 6.0], 0.0015, 16), 8),
    ("sine_0.1-0.8Hz", _sine([0.1, 0.8], 0.008), 3),
    ("sine_0.8-1.3Hz", _sine([0.8, 1.3], 0.002), 3),
    ("sine_1.3-1.7Hz", _sine([1.3, 1.7], 0.0003), 3),
    ("sine_1.7-3Hz", _sine([1.7, 3.0], 0.0015), 3),
    ("sine_3-6Hz", _sine([3.0, 6.0], 0.0025), 3),
    # Last, so that every group above keeps its seeds: the drive between the five rhythms above, where a forward
    # model fitted on those alone erred 14-50 times as much as on them (docs/results/trust.md, where the surprise
    # falls short). Four bands, not one group: the surprise judges each motion group by a forward model fitted
    # without it, and one group holding every rhythm between would be judged by the five rhythms alone.
    *((f"product_x{low:g}-{low + 0.2:g}", _product(low + 0.1, 0.003, 0.1 / (low + 0.1)), 4)
      for low in (0.65, 0.85, 1.05, 1.25)),
)

PRESETS: dict[str, tuple[Group, ...]] = {
    "paper": (Group("paper", {}, 1.0),),
    "general": tuple(Group(name, motion, arms / DEFAULT_ARMS, world=True) for name, motion, arms in GENERAL),
}


def arms_per_group(groups: tuple[Group, ...], arms: int) -> list[int]:
    """Arms of each group: the shares of `arms`, every group at least one, the total exactly `arms` or the
    number of groups, whichever is larger."""
    counts = [max(1, int(round(g.share * arms))) for g in groups]
    while sum(counts) > max(arms, len(groups)):
        counts[counts.index(max(counts))] -= 1
    while sum(counts) < arms:
        counts[counts.index(min(counts))] += 1
    return counts


def seeds_of(group_index: int, arms: int) -> int:
    """The first seed of a group (the paper preset starts at 0: its first arm is the paper's run)."""
    first = group_index * SEED_BLOCK
    if first + arms > HELD_OUT_SEED_BASE or arms > SEED_BLOCK:
        raise ValueError(f"group {group_index} with {arms} arms leaves the corpus's seed range")
    return first
