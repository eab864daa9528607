"""`softarm corpus DIR`: simulate a training corpus, group by group, with a manifest of what each file is."""

from pathlib import Path
from typing import Callable, Optional, Union

from softarm.config import load_config
from softarm.errors import ConfigError, OutputError
from softarm.files import check_outputs, write_json
from softarm.interrupt import stop_on_signal
from softarm.corpus.presets import PRESETS, SEED_BLOCK, arms_per_group, seeds_of

MANIFEST = "corpus.json"
DEFAULT_ARMS = 64
DEFAULT_DURATION = 60.0  # s per arm


def write_corpus(folder: Union[str, Path], preset: str = "general", arms: int = DEFAULT_ARMS,
                 duration: float = DEFAULT_DURATION, force: bool = False, arch: str = "cpu",
                 progress: Optional[Callable[[int, int], None]] = None) -> Optional[Path]:
    """Simulate the preset's groups into `folder` and write `corpus.json`; its path, or None when Ctrl-C (or
    SIGTERM) stopped it (then there is no manifest). `progress(arm_frames_done, arm_frames_in_all)`."""
    from softarm.sim.run import simulate

    if preset not in PRESETS:
        raise ConfigError(f"--preset {preset!r} is not known: use one of {', '.join(PRESETS)}")
    if not 1 <= arms <= SEED_BLOCK:
        raise ConfigError(f"--arms {arms} is out of range: a corpus holds 1 to {SEED_BLOCK} arms")
    folder = Path(folder)
    manifest = folder / MANIFEST
    if manifest.exists() and not force:
        raise OutputError(f"{folder} already holds a corpus ({manifest}); pass --force to write it again")
    check_outputs([manifest], force=True)
    manifest.unlink(missing_ok=True)
    groups, counts = PRESETS[preset], arms_per_group(PRESETS[preset], arms)
    configs = [load_config(overrides={**g.overrides, "run.duration": duration, "run.arms": n,
                                      "run.seed": seeds_of(k, n)}) for k, (g, n) in enumerate(zip(groups, counts))]
    total, done, entries = sum(c.n_frames * c.run.arms for c in configs), 0, {}
    with stop_on_signal() as caught:
        for group, config in zip(groups, configs):
            result = simulate(config, folder / f"{group.name}.mcap", force=True, arch=arch,
                              progress=lambda frames: progress(done + frames * config.run.arms, total) if progress else None)
            if caught or not result.complete:
                return None
            done += config.n_frames * config.run.arms
            entries[group.name] = {"overrides": group.overrides, "seeds": [config.run.seed + i for i in range(config.run.arms)],
                                   "recordings": [p.name for p in result.paths]}
    return write_json(manifest, {"preset": preset, "arms": sum(counts), "duration": duration, "groups": entries})
