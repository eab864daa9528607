"""Output files: checked against each other and against every input before any work, claimed by one run at a
time, written whole or not at all, told apart by fingerprint.

Every writer in softarm (recordings, checkpoints, metrics, .rrd timelines, PNGs) writes to `<name>.part`
and renames it on success, so a path without `.part` is always a whole file. A run holds each of its
outputs with a lock (`.<name>.lock` beside it, an flock the kernel drops when the process ends, however it
ends): a second run on the same output is refused with one line instead of racing the first. `--force`
replaces an old output, never an input.
"""

import errno
import fcntl
import hashlib
import json
import math
import os
from contextlib import ExitStack, contextmanager
from pathlib import Path
from typing import Any, Iterator, Sequence, Union

from softarm.errors import OutputError

PathLike = Union[str, Path]


def check_outputs(outputs: Sequence[PathLike], force: bool, inputs: Sequence[PathLike] = ()) -> None:
    """Refuse before any work, creating nothing: two outputs on one file, an output that is one of the inputs
    (the same path once resolved, or a hard link to it), an existing output (unless force), an output that is
    a folder, or one whose folder cannot be made or written. The files an output brings with it, its `.part`
    and its lock, obey the same rule: neither may be an input, and an existing `.part` (an earlier run's
    unfinished file, which may hold frames worth keeping) is replaced only with force. Each name is resolved
    once and looked up, so a batch of 256 outputs costs 256 lookups, not 32 640 pairwise comparisons."""
    sources: dict[Any, Path] = {}
    for source in map(Path, inputs):
        sources.update(dict.fromkeys(identities(source), source))
    earlier: dict[Any, Path] = {}
    for path in map(Path, outputs):
        keys = identities(path)
        other = next((earlier[k] for k in keys if k in earlier), None)
        if other is not None:
            raise OutputError(f"the outputs {other} and {path} are one file: give each its own name")
        for companion, what in ((path, "output"), (part_path(path), "unfinished file"), (lock_path(path), "lock")):
            source = next((sources[k] for k in identities(companion) if k in sources), None)
            if source is not None:
                named = f"output {path}" if companion == path else f"output {path} writes its {what} {companion}, which"
                raise OutputError(f"{named} is the input {source}: write the output elsewhere "
                                  f"(--force replaces an old output, never an input)")
        earlier.update(dict.fromkeys(keys, path))
        if path.is_dir():
            raise OutputError(f"output {path} is a folder; give a file name")
        if path.exists() and not force:
            raise OutputError(f"output {path} already exists; pass --force to overwrite it")
        if part_path(path).exists() and not force:
            raise OutputError(f"{part_path(path)} holds an earlier run's unfinished {path.name} (it may keep frames "
                              f"worth saving): move it away, or pass --force to replace it")
        check_writable_folder(path)


def input_file(path: PathLike, kind: str, error: type[Exception]) -> Path:
    """`path` as an input that must be a file (a `kind`, named in the message): a missing one or a folder is
    refused by `error` in one line, before any heavy work loads."""
    path = Path(path)
    if not path.is_file():
        raise error(f"{kind} {path} not found" if not path.exists() else
                    f"{path} is a folder, not a {kind}" if path.is_dir() else f"{path} is not a file")
    return path


def check_writable_folder(path: Path) -> None:
    """The folder of `path` exists and can be written, or can be made where the nearest existing one is."""
    parent = next((p for p in [path.parent, *path.parent.parents] if p.exists()), Path("."))
    if not parent.is_dir():
        raise OutputError(f"cannot write {path}: {parent} is a file, not a folder")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise OutputError(f"cannot write {path}: {parent} is not writable")


def identities(path: Path) -> list[Any]:
    """What two names of one file share: the path once resolved, and where the file exists its device and
    inode (a hard link)."""
    keys: list[Any] = [path.resolve()]
    try:
        status = os.stat(path)
    except OSError:  # it does not exist (yet)
        return keys
    return [*keys, (status.st_dev, status.st_ino)]


@contextmanager
def made_folders(paths: Sequence[PathLike]) -> Iterator[None]:
    """Make the missing folders of `paths` for the block; if it fails, remove those it made that stayed empty."""
    made: list[Path] = []
    try:
        for path in map(Path, paths):
            missing = [p for p in [path.parent, *path.parent.parents] if not p.exists()]
            for folder in reversed(missing):
                folder.mkdir(exist_ok=True)
                made.append(folder)
        yield
    except BaseException:
        for folder in reversed(made):
            try:
                folder.rmdir()
            except OSError:  # not empty (something else wrote there) or gone: leave it
                pass
        raise


@contextmanager
def claimed(paths: Sequence[PathLike]) -> Iterator[None]:
    """Hold every output of a run (their folders must exist); a second run on any of them is refused, the first
    output it holds named (the run's main one, listed first)."""
    with ExitStack() as stack:
        for path in dict.fromkeys(Path(p).resolve() for p in paths):
            stack.enter_context(_lock(path))
        yield


def lock_path(path: PathLike) -> Path:
    path = Path(path)
    return path.with_name(f".{path.name}.lock")


@contextmanager
def _lock(path: Path) -> Iterator[None]:
    lock = lock_path(path)
    while True:
        fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as e:
            owner = os.read(fd, 32).decode(errors="replace").strip()
            os.close(fd)
            if e.errno not in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
                raise
            raise OutputError(f"{path} is being written by another softarm run (pid {owner or 'unknown'}); "
                              f"wait for it to end, or write elsewhere") from None
        try:
            same = os.stat(lock).st_ino == os.fstat(fd).st_ino  # the holder before us may have removed it
        except FileNotFoundError:
            same = False
        if same:
            break
        os.close(fd)
    try:
        os.ftruncate(fd, 0)
        os.write(fd, f"{os.getpid()}\n".encode())
        yield
    finally:
        try:
            os.unlink(lock)  # while still held: a run that opened it before sees another inode and retries
        except FileNotFoundError:
            pass
        os.close(fd)


def part_path(path: PathLike) -> Path:
    """Where `path` grows until it is whole: `<name>.part` beside it."""
    path = Path(path)
    return path.with_name(path.name + ".part")


def publish(path: PathLike) -> Path:
    """Give the finished `<name>.part` its final name, atomically (a reader never sees half a file)."""
    os.replace(part_path(path), path)
    return Path(path)


@contextmanager
def atomic_path(path: PathLike) -> Iterator[Path]:
    """Write to the yielded `<path>.part`; it becomes `path` only when the block succeeds, else it is removed."""
    part = part_path(path)
    part.parent.mkdir(parents=True, exist_ok=True)
    try:
        yield part
    except BaseException:
        part.unlink(missing_ok=True)
        raise
    publish(path)


def write_json(path: PathLike, document: Any) -> Path:
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


def fingerprint(path: PathLike) -> str:
    """First 16 hex digits of the file's SHA-256 (of a folder, such as a ROS 2 bag: of its files' names and bytes
    in name order): enough to tell inputs apart, short enough to read."""
    digest = hashlib.sha256()
    path = Path(path)
    for file in sorted(p for p in path.rglob("*") if p.is_file()) if path.is_dir() else [path]:
        if path.is_dir():
            digest.update(str(file.relative_to(path)).encode() + b"\0")
        with open(file, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                digest.update(block)
    return digest.hexdigest()[:16]
