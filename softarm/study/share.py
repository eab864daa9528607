"""A trial's CPU share: torch uses as many threads as the trial has cores, and the process is pinned to
that many cores of this machine that no other trial holds, so trials side by side never share a core.

Ray counts CPUs but does not say which cores a task may use; a trial claims free cores with a lock
file per core (released when it ends, or dies), so studies side by side on one machine also stay apart.
"""

import fcntl
import os
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import IO, Iterator, Optional

LOCKS = Path(tempfile.gettempdir()) / "softarm-cores"


@contextmanager
def cpu_share(cores: int) -> Iterator[list[int]]:
    """Within the block, torch runs `cores` threads and the process runs on the cores yielded (all of its
    cores, unpinned, when fewer than `cores` are free)."""
    import torch

    allowed = sorted(os.sched_getaffinity(0))
    threads = torch.get_num_threads()
    held = _claim(allowed, cores)
    torch.set_num_threads(cores)
    if held:
        os.sched_setaffinity(0, held)
    try:
        yield sorted(held) or allowed
    finally:
        os.sched_setaffinity(0, allowed)
        torch.set_num_threads(threads)
        for lock in held.values():
            lock.close()


def _claim(allowed: list[int], cores: int) -> dict[int, IO[str]]:
    """Locks on `cores` of the allowed cores that no other process holds; none if there are not enough."""
    held: dict[int, IO[str]] = {}
    for core in allowed:
        lock = _lock(LOCKS / f"{core}.lock")
        if lock is not None:
            held[core] = lock
        if len(held) == cores:
            return held
    for lock in held.values():
        lock.close()
    return {}


def _lock(path: Path) -> Optional[IO[str]]:
    """The open, exclusively locked file; None when another process holds it (or it cannot be made)."""
    try:
        path.parent.mkdir(exist_ok=True)
        lock = open(path, "a")
    except OSError:
        return None
    try:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        lock.close()
        return None
    return lock
