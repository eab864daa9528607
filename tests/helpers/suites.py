"""A suite folder of one family and one recording, as `softarm suite` lays it out (for the tests of what reads a
suite without writing the whole one)."""

import json
import shutil
from pathlib import Path

from softarm.suite.families import SUITE_VERSION


def mini_suite(folder: Path, recording: Path) -> Path:
    folder.mkdir()
    shutil.copy(recording, folder / "a.mcap")
    (folder / "suite.json").write_text(json.dumps({"suite": SUITE_VERSION, "families": {"paper_amplitude": {
        "probes": "the paper's drive", "levels": {"x": {"overrides": {}, "sensing": {}, "seeds": [1],
                                                        "recordings": ["a.mcap"]}}}}}))
    return folder
