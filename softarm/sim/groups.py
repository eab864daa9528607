"""Many runs into one folder, one config after another, with a manifest written only when all finished.

The suite and the corpora are built this way: a folder with a manifest is whole; Ctrl-C or SIGTERM
stops the current run cleanly, and no manifest claims the folder. The folder is held by one run at a
time (its manifest's lock), and the manifest of an earlier run is removed before any new file is made.
"""

from pathlib import Path
from typing import Callable, Optional, Sequence

from softarm.config import Config
from softarm.errors import OutputError
from softarm.files import check_outputs
from softarm.interrupt import stop_on_signal


def fresh_manifest(folder: Path, name: str, what: str, force: bool) -> Path:
    """The manifest's path, refused if the folder already holds one (unless force)."""
    manifest = Path(folder) / name
    if manifest.exists() and not force:
        raise OutputError(f"{folder} already holds {what} ({manifest}); pass --force to write it again")
    check_outputs([manifest], force=True)
    return manifest


def planned_paths(folder: Path, runs: Sequence[tuple[str, Config]]) -> list[Path]:
    """Every file `simulate_groups` writes for these runs."""
    from softarm.sim.simulate import output_paths

    return [p for stem, config in runs for p in output_paths(config, Path(folder) / f"{stem}.mcap")]


def simulate_groups(folder: Path, runs: Sequence[tuple[str, Config]], arch: str,
                    after: Callable[[int, list[Path]], None],
                    progress: Optional[Callable[[int, int], None]] = None) -> bool:
    """Simulate each (file stem, config) into `folder`, calling `after(index, paths)` when one finishes;
    False when a signal stopped them. `progress(arm_frames_done, arm_frames_in_all)`."""
    from softarm.sim.simulate import simulate

    total, done = sum(c.n_frames * c.run.arms for _, c in runs), 0
    with stop_on_signal() as caught:
        for k, (stem, config) in enumerate(runs):
            arms = config.run.arms
            result = simulate(config, Path(folder) / f"{stem}.mcap", force=True, arch=arch,
                              progress=(lambda frames: progress(done + frames * arms, total)) if progress else None)
            if caught or not result.complete:
                return False
            done += config.n_frames * arms
            after(k, result.paths)
    return True
