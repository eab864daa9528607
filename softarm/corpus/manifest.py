"""Reading a corpus folder: `corpus.json` says which recordings make the corpus; a folder whose corpus is still
being written (or was stopped) holds `.corpus-incomplete.json` instead and is refused, so a training never
takes part of a corpus for the whole of it."""

import json
from pathlib import Path

from softarm.errors import RecordingError

MIN_CORPUS = 4  # recordings; more make a corpus: it keeps some out for validation, and reads the drive too
MANIFEST = "corpus.json"
INCOMPLETE = ".corpus-incomplete.json"


def folder_recordings(folder: Path) -> tuple[list[Path], list[Path]]:
    """The recordings a folder stands for, sorted by name, and its own files that training reads besides them
    (the manifest): a corpus's listed recordings, or in a folder that is no corpus every recording in it."""
    folder = Path(folder)
    manifest = folder / MANIFEST
    if manifest.is_file():
        return sorted(folder / name for name in _listed(manifest)), [manifest]
    if (folder / INCOMPLETE).exists():
        raise RecordingError(f"{folder} holds an incomplete corpus (it was stopped before {MANIFEST} was written): "
                             f"finish it with `softarm corpus {folder}` and the same options, then train again")
    return sorted(p for p in folder.glob("*.mcap") if p.is_file()), []


def _listed(manifest: Path) -> list[str]:
    """Every recording name the manifest lists, each one present beside it."""
    again = f"write it again with `softarm corpus {manifest.parent} --force`"
    try:
        groups = json.loads(manifest.read_text())["groups"]
        names = [name for group in groups.values() for name in group["recordings"]]
    except (OSError, UnicodeDecodeError, ValueError, KeyError, TypeError, AttributeError):
        raise RecordingError(f"{manifest} is not a corpus manifest: {again}") from None
    if not names or not all(isinstance(n, str) and n and Path(n).name == n for n in names):
        raise RecordingError(f"{manifest} lists no recordings or a name that is not a file of its folder: {again}")
    missing = [n for n in names if not (manifest.parent / n).is_file()]
    if missing:
        raise RecordingError(f"{manifest.parent} lacks {len(missing)} of its corpus's recordings "
                             f"(first: {missing[0]}): {again}")
    return names


def motion_group(recording: Path) -> str:
    """The corpus group a recording was made in (the manifest beside it lists it under that group's name), or ""
    where no manifest lists it: the folds the surprise is judged in out of group."""
    manifest = Path(recording).parent / MANIFEST
    try:
        groups = json.loads(manifest.read_text())["groups"]
        return next((name for name, group in groups.items() if Path(recording).name in group["recordings"]), "")
    except (OSError, UnicodeDecodeError, ValueError, KeyError, TypeError, AttributeError):
        return ""

