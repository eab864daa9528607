"""`softarm corpus DIR`: simulate a training corpus, group by group, with a manifest of what each file is."""

from pathlib import Path
from typing import Callable, Optional, Union

from softarm.config import load_config
from softarm.corpus.presets import PRESETS, SEED_BLOCK, arms_per_group, seeds_of
from softarm.errors import ConfigError
from softarm.files import write_json
from softarm.sim.groups import fresh_manifest, simulate_groups

MANIFEST = "corpus.json"
DEFAULT_ARMS = 64
DEFAULT_DURATION = 60.0  # s per arm


def write_corpus(folder: Union[str, Path], preset: str = "general", arms: int = DEFAULT_ARMS,
                 duration: float = DEFAULT_DURATION, force: bool = False, arch: str = "cpu",
                 progress: Optional[Callable[[int, int], None]] = None) -> Optional[Path]:
    """Simulate the preset's groups into `folder` and write `corpus.json`; its path, or None when Ctrl-C (or
    SIGTERM) stopped it (then there is no manifest). `progress(arm_frames_done, arm_frames_in_all)`."""
    if preset not in PRESETS:
        raise ConfigError(f"--preset {preset!r} is not known: use one of {', '.join(PRESETS)}")
    if not 1 <= arms <= SEED_BLOCK:
        raise ConfigError(f"--arms {arms} is out of range: a corpus holds 1 to {SEED_BLOCK} arms")
    groups, counts = PRESETS[preset], arms_per_group(PRESETS[preset], arms)
    runs = [(g.name, load_config(overrides={**g.overrides, "run.duration": duration, "run.arms": n,
                                            "run.seed": seeds_of(k, n)})) for k, (g, n) in enumerate(zip(groups, counts))]
    manifest = fresh_manifest(Path(folder), MANIFEST, "a corpus", force)  # after the options are checked
    entries: dict[str, dict] = {}

    def note(k: int, paths: list[Path]) -> None:
        group, config = groups[k], runs[k][1]
        entries[group.name] = {"overrides": group.overrides, "recordings": [p.name for p in paths],
                               "seeds": [config.run.seed + i for i in range(config.run.arms)]}

    if not simulate_groups(Path(folder), runs, arch, note, progress):
        return None
    return write_json(manifest, {"preset": preset, "arms": sum(counts), "duration": duration, "groups": entries})
