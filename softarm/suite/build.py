"""`softarm suite DIR`: simulate every level of every family from its reserved seeds and write the manifest.

The recordings are regenerated, never stored: the same softarm writes byte-identical files. Each is
checked to keep the arm inside the camera's view (no arm pixel on the left, right or bottom edge),
so a score never mixes imagination with an arm the camera cannot see: each level simulates a few
candidate seeds from its reserved block and keeps the first that stay in view.
"""

from pathlib import Path
from typing import Callable, Optional, Union

from softarm.config import load_config
from softarm.errors import SoftarmError
from softarm.files import claimed, made_folders, write_json
from softarm.sim.groups import fresh_manifest, simulate_groups
from softarm.suite.families import (
    CANDIDATES,
    DURATION,
    FAMILIES,
    GROUPS,
    SEEDS_PER_LEVEL,
    SUITE_SEED_BASE,
    SUITE_VERSION,
    level_seeds,
)
from softarm.suite.manifest import MANIFEST


def write_suite(folder: Union[str, Path], force: bool = False, arch: str = "cpu",
                progress: Optional[Callable[[int, int], None]] = None) -> Optional[Path]:
    """Write the suite's recordings and manifest into `folder`; the manifest's path, or None when Ctrl-C
    (or SIGTERM) stopped it: then the folder holds no manifest, so nothing takes it for a whole suite.

    `progress(arm_frames_done, arm_frames_in_all)` is called as the runs go.
    """
    manifest = fresh_manifest(Path(folder), MANIFEST, "a suite", force)
    levels = level_seeds()
    runs = [(f"{family.name}_level{family.levels.index(level)}",
             load_config(overrides={**level.overrides, "run.duration": DURATION, "run.seed": seed,
                                    "run.arms": CANDIDATES})) for family, level, seed in levels]
    entries: dict[str, dict] = {f.name: {"probes": f.probes, "group": GROUPS[f.name], "levels": {}} for f in FAMILIES}

    def keep(k: int, paths: list[Path]) -> None:
        family, level, seed = levels[k]
        kept = keep_in_view(paths, SEEDS_PER_LEVEL, f"{family.name} {level.name}")
        entries[family.name]["levels"][level.name] = {
            "overrides": level.overrides, "sensing": level.sensing,
            "seeds": [seed + paths.index(p) for p in kept], "recordings": [p.name for p in kept]}

    with made_folders([manifest]), claimed([manifest]):
        manifest.unlink(missing_ok=True)  # an interrupted rewrite must not leave the old manifest claiming the folder
        if not simulate_groups(Path(folder), runs, arch, keep, progress):
            return None
        return write_json(manifest, {"suite": SUITE_VERSION, "seed_base": SUITE_SEED_BASE, "duration": DURATION,
                                     "families": entries})


def keep_in_view(paths: list[Path], count: int, what: str) -> list[Path]:
    """The first `count` recordings whose arm never touches the left, right or bottom edge of the image;
    the others are removed."""
    from softarm.record.reader import read_recording

    kept = []
    for path in paths:
        frames = read_recording(path, nodes=False).frames if len(kept) < count else None
        if frames is not None and not (frames[:, :, 0].any() or frames[:, :, -1].any() or frames[:, -1, :].any()):
            kept.append(path)
        else:
            path.unlink()
    if len(kept) < count:
        raise SoftarmError(f"suite level {what}: only {len(kept)} of {len(paths)} seeds keep the arm in the camera's "
                           f"view; the level's motion is too large")
    return kept
