"""The numbers a user gives a command or a function besides the config (how many episodes, which seed, how many
seconds, how many environments), each checked by one rule before any work: counts at least one and below what
this machine can hold, times finite, seeds 32-bit. The config's own keys are declared in `softarm.config.keys`.

Each check names the option and says what would be accepted, in one line (a `ConfigError`).
"""

import math
from pathlib import Path
from typing import Optional

import psutil

from softarm.config.keys import MAX_SEED
from softarm.errors import ConfigError

HEADROOM = 0.8  # of the memory available that one request may plan to use


def count(option: str, value: int, most: Optional[int] = None, why: str = "") -> int:
    """A whole number of things, at least 1 and at most `most` (what fits, `why` saying of what)."""
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise ConfigError(f"{option} {value!r}: give a whole number, 1 or more")
    if most is not None and value > most:
        raise ConfigError(f"{option} {value}: at most {most:,} fit{f' ({why})' if why else ''}")
    return value


def seconds(option: str, value: float, longest: Optional[float] = None, why: str = "") -> float:
    """A positive, finite duration, at most `longest` (what fits, `why` saying of what)."""
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
        raise ConfigError(f"{option} {value!r}: give a finite, positive number of seconds")
    if longest is not None and value > longest:
        raise ConfigError(f"{option} {value:g}: at most {longest:.3g} s fit{f' ({why})' if why else ''}")
    return float(value)


def finite(option: str, value: float, bound: float, unit: str = "s") -> float:
    """A finite number within ±bound."""
    if not (isinstance(value, (int, float)) and math.isfinite(value) and abs(value) <= bound):
        raise ConfigError(f"{option} {value!r}: give a finite number within ±{bound:g} {unit}")
    return float(value)


def seed(option: str, value: int, span: int = 1) -> int:
    """A seed, or the first of `span` consecutive ones: all of them 32-bit (0..2^32 - 1)."""
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= MAX_SEED - (span - 1):
        raise ConfigError(f"{option} {value!r}: seeds are 32-bit, give 0..{MAX_SEED - (span - 1)}"
                          + (f" ({span} seeds from it are used)" if span > 1 else ""))
    return value


def fitting(bytes_each: float) -> int:
    """How many items of `bytes_each` fit HEADROOM of the memory available now."""
    return max(0, int(available_memory() * HEADROOM // max(bytes_each, 1)))


def disk_fitting(folder: Path, bytes_each: float) -> int:
    """How many files of `bytes_each` fit HEADROOM of the free disk where `folder` is (or would be made)."""
    import shutil

    folder = Path(folder).resolve()
    existing = next(p for p in (folder, *folder.parents) if p.exists())
    return max(0, int(shutil.disk_usage(existing).free * HEADROOM // max(bytes_each, 1)))


def available_memory() -> int:
    """Available memory, within the cgroup's limit when the process runs in one (a container, a batch job)."""
    free = psutil.virtual_memory().available
    try:
        limit, used = (Path("/sys/fs/cgroup") / name for name in ("memory.max", "memory.current"))
        if limit.read_text().strip() != "max":
            free = min(free, int(limit.read_text()) - int(used.read_text()))
    except (OSError, ValueError):
        pass
    return free
