"""Reading a suite folder: its manifest says which recordings make each family and level, and which
sensor imperfections each level is read with."""

import json
from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple, Union

from softarm.errors import RecordingError
from softarm.suite.families import SUITE_VERSION

MANIFEST = "suite.json"


class SuiteCase(NamedTuple):
    family: str
    level: str
    path: Path
    sensing: dict[str, float]   # imperfections this level is read with


@dataclass(frozen=True)
class Suite:
    version: str
    probes: dict[str, str]   # family -> what it probes
    cases: list[SuiteCase]
    groups: dict[str, str]   # family -> "motion" (the drive's kinds) or "world" (disturbances)

    @property
    def families(self) -> list[str]:
        return list(self.probes)


def read_suite(folder: Union[str, Path]) -> Suite:
    """The suite written by `softarm suite` into `folder`; every recording it names must be there."""
    folder = Path(folder)
    path = folder / MANIFEST
    if not path.is_file():
        raise RecordingError(f"{folder} holds no suite ({MANIFEST} missing): write one with softarm suite {folder}")
    try:
        document = json.loads(path.read_text())
        version, families = document["suite"], document["families"]
        if version != SUITE_VERSION:
            raise RecordingError(f"{folder} holds {version}, but this softarm evaluates {SUITE_VERSION}: "
                                 f"write it again with softarm suite {folder} --force")
        cases = [SuiteCase(family, level, folder / name, dict(entry["sensing"]))
                 for family, body in families.items() for level, entry in body["levels"].items()
                 for name in entry["recordings"]]
        probes = {family: str(body["probes"]) for family, body in families.items()}
        groups = {family: str(body.get("group", "motion")) for family, body in families.items()}
    except (json.JSONDecodeError, KeyError, TypeError, AttributeError, ValueError):
        raise RecordingError(f"{path} is not a suite manifest: "
                             f"write it again with softarm suite {folder} --force") from None
    empty = sorted(set(probes) - {c.family for c in cases})
    if empty:
        raise RecordingError(f"{path}: family {empty[0]} has no recordings: "
                             f"write it again with softarm suite {folder} --force")
    missing = [c.path.name for c in cases if not c.path.is_file()]
    if missing:
        raise RecordingError(f"{folder} lacks {len(missing)} of the suite's recordings (first: {missing[0]}): "
                             f"write it again with softarm suite {folder} --force")
    return Suite(version, probes, cases, groups)
