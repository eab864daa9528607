"""Output paths are checked before any work starts, so a refused run costs nothing and leaves nothing."""

from contextlib import contextmanager
from pathlib import Path
from typing import Iterator

from softarm.errors import OutputError


def check_outputs(paths: list[Path], force: bool) -> None:
    """Refuse before any work: an existing file (unless force), a parent that is a file or is read-only."""
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
        probe = path.with_name(path.name + ".part")
        try:
            probe.touch()
            probe.unlink()
        except OSError as e:
            raise OutputError(f"cannot write {path}: {e.strerror}") from None


@contextmanager
def atomic_path(path: Path) -> Iterator[Path]:
    """Write to the yielded `<path>.part`; it becomes `path` only when the block succeeds, else it is removed."""
    path = Path(path)
    part = path.with_name(path.name + ".part")
    try:
        yield part
    except BaseException:
        part.unlink(missing_ok=True)
        raise
    part.replace(path)
