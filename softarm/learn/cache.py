"""The frame cache of a corpus training: the frames of every recording in files beside the checkpoint,
memory-mapped, so resident memory does not grow with the corpus.

Its folder is `.<checkpoint stem>-frames-<pid>-<random>`: removed when the run ends, however it ends short of
SIGKILL; the next run with the same checkpoint name removes the caches of runs that are no longer alive.
"""

import os
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator, Optional


def prefix(checkpoint: Path) -> str:
    return f".{checkpoint.stem}-frames-"


@contextmanager
def frame_cache(checkpoint: Path, wanted: bool) -> Iterator[Optional[Path]]:
    """A fresh cache folder beside `checkpoint` for the block (None when not `wanted`), stale ones swept."""
    sweep_stale(checkpoint)
    if not wanted:
        yield None
        return
    with tempfile.TemporaryDirectory(prefix=f"{prefix(checkpoint)}{os.getpid()}-", dir=checkpoint.parent) as cache:
        yield Path(cache)


def sweep_stale(checkpoint: Path) -> list[Path]:
    """Remove the caches beside `checkpoint` whose run is gone (its pid is not alive); the ones removed."""
    swept = []
    for folder in checkpoint.parent.glob(f"{prefix(checkpoint)}*"):
        pid = folder.name[len(prefix(checkpoint)):].partition("-")[0]
        if folder.is_dir() and pid.isdigit() and not alive(int(pid)):
            shutil.rmtree(folder, ignore_errors=True)
            swept.append(folder)
    return swept


def alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # alive, someone else's
        return True
    return True
