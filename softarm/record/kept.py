"""What a cut-off batch left on disk, in one line: which files were closed with how many frames, and
which stayed `.part` with how many frames the reader recovers from them."""

from pathlib import Path

from softarm.files import part_path
from softarm.record.reader import count_frames


def describe_kept(paths: list[Path]) -> str:
    """e.g. "kept 2 closed files (900 frames each: b_arm0.mcap, b_arm2.mcap) and 2 .part files ..."."""
    closed = [(p, count_frames(p)) for p in paths if p.exists()]
    parts = [(part_path(p), count_frames(part_path(p))) for p in paths if not p.exists() and part_path(p).exists()]
    pieces = [_group(f"closed file{'s' if len(closed) > 1 else ''}, complete = false", closed),
              _group(".part file" + ("s" if len(parts) > 1 else "") + " that the reader recovers", parts)]
    pieces = [p for p in pieces if p]
    return "kept " + " and ".join(pieces) if pieces else "no frame reached the disk"


def _group(label: str, files: list[tuple[Path, int]]) -> str:
    if not files:
        return ""
    counts = sorted({n for _, n in files})
    frames = f"{counts[0]} frames" if len(counts) == 1 else f"{counts[0]}-{counts[-1]} frames"
    names = ", ".join(str(p) for p, _ in files[:2]) + (", ..." if len(files) > 2 else "")
    return f"{len(files)} {label} ({frames}{' each' if len(files) > 1 and len(counts) == 1 else ''}: {names})"
