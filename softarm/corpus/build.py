"""`softarm corpus DIR`: simulate a training corpus, group by group, with a manifest of what each file is.

While a corpus is being written its folder holds `.corpus-incomplete.json`, the list of the recordings it
plans; `corpus.json` replaces it once every group is written. Training refuses a folder with the first
and without the second, and a new corpus (`--force`, or the same command after an interruption) first
removes every recording the folder's old manifest or plan lists, so no recording of another corpus stays.
"""

import json
from pathlib import Path
from typing import Callable, Optional, Union

from softarm.config import load_config
from softarm.corpus.manifest import INCOMPLETE, MANIFEST
from softarm.corpus.presets import DEFAULT_ARMS, PRESETS, SEED_BLOCK, arms_per_group, seeds_of, world_mix
from softarm.errors import ConfigError
from softarm.files import claimed, made_folders, write_json
from softarm.sim.groups import fresh_manifest, planned_paths, simulate_groups

DEFAULT_DURATION = 60.0  # s per arm


def write_corpus(folder: Union[str, Path], preset: str = "general", arms: int = DEFAULT_ARMS,
                 duration: float = DEFAULT_DURATION, force: bool = False, arch: str = "cpu",
                 progress: Optional[Callable[[int, int], None]] = None) -> Optional[Path]:
    """Simulate the preset's groups into `folder` and write `corpus.json`; its path, or None when Ctrl-C (or
    SIGTERM) stopped it (then there is no manifest). `progress(arm_frames_done, arm_frames_in_all)`."""
    if preset not in PRESETS:
        raise ConfigError(f"--preset {preset!r} is not known: use one of {', '.join(PRESETS)}")
    groups = PRESETS[preset]
    if not len(groups) <= arms <= SEED_BLOCK:
        raise ConfigError(f"--arms {arms} is out of range: the {preset} preset's {len(groups)} group(s) need "
                          f"{len(groups)} to {SEED_BLOCK} arms, one or more each")
    counts = arms_per_group(groups, arms)
    runs = [(g.name, load_config(overrides={**g.overrides, **(world_mix(duration) if g.world else {}),
                                            "run.duration": duration, "run.arms": n, "run.seed": seeds_of(k, n)}))
            for k, (g, n) in enumerate(zip(groups, counts))]
    folder = Path(folder)
    manifest = fresh_manifest(folder, MANIFEST, "a corpus", force)  # after the options are checked
    entries: dict[str, dict] = {}

    def note(k: int, paths: list[Path]) -> None:
        group, config = groups[k], runs[k][1]
        entries[group.name] = {"overrides": group.overrides, "recordings": [p.name for p in paths],
                               "seeds": [config.run.seed + i for i in range(config.run.arms)]}

    with made_folders([manifest]), claimed([manifest]):
        clear_old_corpus(folder)
        write_json(folder / INCOMPLETE, {"preset": preset, "recordings": [p.name for p in planned_paths(folder, runs)]})
        if not simulate_groups(folder, runs, arch, note, progress):
            return None
        written = write_json(manifest, {"preset": preset, "arms": sum(counts), "duration": duration, "groups": entries})
        (folder / INCOMPLETE).unlink()
        return written


def clear_old_corpus(folder: Path) -> None:
    """Remove the manifest of an earlier corpus in `folder` and every recording it, or its plan, lists."""
    for listing in (folder / MANIFEST, folder / INCOMPLETE):
        for name in listed_recordings(listing):
            (folder / name).unlink(missing_ok=True)
        listing.unlink(missing_ok=True)


def listed_recordings(listing: Path) -> list[str]:
    """The recording names a manifest or a plan lists (none where it is missing or unreadable); names that
    would leave the folder are ignored."""
    try:
        document = json.loads(listing.read_text())
        names = (document["recordings"] if "recordings" in document
                 else [n for group in document["groups"].values() for n in group["recordings"]])
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return []
    return [n for n in names if isinstance(n, str) and Path(n).name == n and n.endswith(".mcap")]
