"""The data every trial shares, built once under the study's folder before any trial starts: the training
corpus (DIR/corpus) and the held-out suite (DIR/suite); a folder already whole is kept.

A scale that scores on the first recording of each suite level gets DIR/suite-quick: that recording of
each level, hard-linked from DIR/suite, under a manifest that names only them.
"""

import json
import os
import shutil
from pathlib import Path
from typing import Callable, Optional

from softarm.corpus.build import write_corpus
from softarm.corpus.manifest import MANIFEST as CORPUS_MANIFEST
from softarm.corpus.presets import PRESETS, arms_per_group
from softarm.errors import OutputError, RecordingError
from softarm.files import write_json
from softarm.study.scale import Scale
from softarm.suite.build import write_suite
from softarm.suite.manifest import MANIFEST as SUITE_MANIFEST
from softarm.suite.manifest import read_suite

StageProgress = Callable[[str, int, int], None]  # (stage, done, total)


def prepare(folder: Path, scale: Scale, force: bool, progress: StageProgress) -> Optional[tuple[Path, Path]]:
    """(corpus folder, suite folder to score on), built where missing; None when Ctrl-C stopped a build.

    A corpus of another size than the scale's is refused, or with `force` written again.
    """
    corpus, suite = folder / "corpus", folder / "suite"
    if not corpus_fits(corpus, scale):
        if (corpus / CORPUS_MANIFEST).exists() and not force:
            raise OutputError(f"{corpus} holds another corpus than a {scale.name} study's ({scale.preset}, "
                              f"{scale.arms} arms x {scale.duration:g} s); pass --force to write it again")
        if write_corpus(corpus, scale.preset, scale.arms, scale.duration, force=True,
                        progress=lambda done, total: progress("corpus", done, total)) is None:
            return None
    try:
        read_suite(suite)
    except RecordingError:  # none yet, or half of one: the same softarm writes the same suite again
        if write_suite(suite, force=True, progress=lambda done, total: progress("suite", done, total)) is None:
            return None
    return corpus, first_recordings(suite, folder / "suite-quick") if scale.first_recording_only else suite


def corpus_fits(corpus: Path, scale: Scale) -> bool:
    """The folder holds a whole corpus of the scale's preset, arms and duration."""
    try:
        manifest = json.loads((corpus / CORPUS_MANIFEST).read_text())
    except (OSError, json.JSONDecodeError):
        return False
    names = [name for group in manifest.get("groups", {}).values() for name in group.get("recordings", [])]
    return (manifest.get("preset") == scale.preset and manifest.get("duration") == scale.duration
            and manifest.get("arms") == sum(arms_per_group(PRESETS[scale.preset], scale.arms))
            and all((corpus / name).is_file() for name in names))


def first_recordings(suite: Path, folder: Path) -> Path:
    """`folder` as a suite of the first recording (and seed) of every level of `suite`; its path."""
    manifest = json.loads((suite / SUITE_MANIFEST).read_text())
    folder.mkdir(exist_ok=True)
    for family in manifest["families"].values():
        for level in family["levels"].values():
            level["recordings"], level["seeds"] = level["recordings"][:1], level["seeds"][:1]
            _link(suite / level["recordings"][0], folder / level["recordings"][0])
    write_json(folder / SUITE_MANIFEST, manifest)
    return folder


def _link(source: Path, target: Path) -> None:
    target.unlink(missing_ok=True)
    try:
        os.link(source, target)
    except OSError:  # another file system, or one without hard links
        shutil.copyfile(source, target)
