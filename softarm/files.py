"""Output files: checked before any work, written whole or not at all, told apart by fingerprint.

Every writer in softarm (recordings, checkpoints, metrics, .rrd timelines, PNGs) writes to
`<name>.part` and renames it on success, so a path without `.part` is always a whole file.
"""

import hashlib
import json
import math
import os
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Iterator, Union

from softarm.errors import OutputError


def check_outputs(paths: list[Path], force: bool) -> None:
    """Refuse before any work: two outputs on one path, an existing file (unless force), a parent that is a
    file or is read-only."""
    paths = [Path(p) for p in paths]
    if len(set(paths)) != len(paths):
        raise OutputError(f"the outputs {', '.join(map(str, paths))} must name different files")
    for path in paths:
        if path.is_dir():
            raise OutputError(f"output {path} is a folder; give a file name")
        if path.exists() and not force:
            raise OutputError(f"output {path} already exists; pass --force to overwrite it")
        parent = next((p for p in [path.parent, *path.parent.parents] if p.exists()), Path("."))
        if not parent.is_dir():
            raise OutputError(f"cannot write {path}: {parent} is a file, not a folder")
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
        except OSError as e:
            raise OutputError(f"cannot create the folder of {path}: {e.strerror}") from None
        probe = part_path(path)
        try:
            probe.touch()
            probe.unlink()
        except OSError as e:
            raise OutputError(f"cannot write {path}: {e.strerror}") from None


def part_path(path: Union[str, Path]) -> Path:
    """Where `path` grows until it is whole: `<name>.part` beside it."""
    path = Path(path)
    return path.with_name(path.name + ".part")


def publish(path: Union[str, Path]) -> Path:
    """Give the finished `<name>.part` its final name, atomically (a reader never sees half a file)."""
    os.replace(part_path(path), path)
    return Path(path)


@contextmanager
def atomic_path(path: Union[str, Path]) -> Iterator[Path]:
    """Write to the yielded `<path>.part`; it becomes `path` only when the block succeeds, else it is removed."""
    part = part_path(path)
    try:
        yield part
    except BaseException:
        part.unlink(missing_ok=True)
        raise
    publish(path)


def write_json(path: Union[str, Path], document: Any) -> Path:
    """Indented JSON written whole; NaN becomes null, since strict JSON readers reject NaN."""
    with atomic_path(path) as part:
        part.write_text(json.dumps(finite_or_null(document), indent=1, allow_nan=False))
    return Path(path)


def finite_or_null(value: Any) -> Any:
    """NaN and infinities as null: JSON has no numbers for them."""
    if isinstance(value, dict):
        return {k: finite_or_null(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [finite_or_null(v) for v in value]
    return None if isinstance(value, float) and not math.isfinite(value) else value


def fingerprint(path: Union[str, Path]) -> str:
    """First 16 hex digits of the file's SHA-256: enough to tell recordings apart, short enough to read."""
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()[:16]
