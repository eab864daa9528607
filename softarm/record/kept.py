"""What a cut-off batch left on disk, in one line: which files were closed with how many frames, and
which stayed `.part` with how many frames the reader recovers from them."""

from pathlib import Path

from mcap.reader import make_reader

from softarm.errors import RecordingError
from softarm.files import part_path
from softarm.record.format import META_RUN
from softarm.record.reader import count_frames


def describe_kept(paths: list[Path]) -> str:
    """e.g. "kept 2 closed files (900 frames each, complete = false: b_arm0.mcap, ...) and 2 .part files ..."."""
    closed, parts = [], []
    for path in paths:
        if part_path(path).exists():  # this run's file, cut off (an older file at `path` is not this run's)
            parts.append((part_path(path), recoverable(part_path(path)), ""))
        elif path.exists():
            closed.append((path, *closed_run(path)))
    pieces = [_group("closed file", closed), _group(".part file that the reader recovers", parts)]
    pieces = [p for p in pieces if p]
    return "kept " + " and ".join(pieces) if pieces else "no frame reached the disk"


def recoverable(path: Path) -> int:
    try:
        return count_frames(path)
    except RecordingError:  # cut before its metadata, or empty: nothing to recover
        return 0


def closed_run(path: Path) -> tuple[int, str]:
    """Frames and completeness from the closing `softarm.run` record, read through the file's summary."""
    with open(path, "rb") as f:
        run = next((dict(m.metadata) for m in make_reader(f).iter_metadata() if m.name == META_RUN), {})
    return int(run.get("frames", 0)), f"complete = {run.get('complete', 'false')}"


def _group(label: str, files: list[tuple[Path, int, str]]) -> str:
    if not files:
        return ""
    counts = sorted({n for _, n, _ in files})
    frames = f"{counts[0]} frames" if len(counts) == 1 else f"{counts[0]}-{counts[-1]} frames"
    flags = sorted({flag for _, _, flag in files if flag})
    detail = ", ".join([frames + (" each" if len(files) > 1 and len(counts) == 1 else ""), *flags])
    names = ", ".join(str(p) for p, _, _ in files[:2]) + (", ..." if len(files) > 2 else "")
    return f"{len(files)} {label}{'s' if len(files) > 1 else ''} ({detail}: {names})"
