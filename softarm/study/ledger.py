"""`trials.jsonl`: one line per finished trial, appended as it finishes, so a study resumes where it stopped.

A trial is known by its name and a key: the hash of its overrides and of the scale it ran at (its corpus,
schedule and suite), so a trial whose settings changed, or that ran `--quick`, is not taken for the one
asked now.
"""

import dataclasses
import hashlib
import json
import os
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Optional

from softarm.files import finite_or_null
from softarm.study.plan import Trial, Value
from softarm.study.scale import Scale

LEDGER = "trials.jsonl"


@dataclass(frozen=True)
class TrialRecord:
    study: str
    name: str
    key: str
    group: str
    value: Value
    overrides: dict[str, Any]
    scale: str
    status: str                      # ok | failed | interrupted (never written)
    error: str = ""                  # one line, for failed
    scores: dict[str, Any] = field(default_factory=dict)  # the suite evaluation: families, mean, ...
    wall_seconds: float = 0.0
    host: str = ""
    checkpoint: str = ""
    traceback: Optional[str] = None  # for an error softarm did not foresee


def trial_key(trial: Trial, scale: Scale) -> str:
    """16 hex digits of the SHA-256 of the trial's overrides and everything the scale sets."""
    text = json.dumps({"overrides": trial.overrides, "scale": dataclasses.asdict(scale)}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def append_record(folder: Path, record: TrialRecord) -> None:
    """One JSON line, written by one call and flushed to disk: a crash loses no finished trial."""
    line = json.dumps(finite_or_null(dataclasses.asdict(record)), allow_nan=False) + "\n"
    with open(folder / LEDGER, "a") as f:
        f.write(line)
        f.flush()
        os.fsync(f.fileno())


def read_records(folder: Path) -> list[TrialRecord]:
    """Every record in the folder's ledger, oldest first; a line that does not parse (a crash mid-write) is
    skipped with a warning."""
    path = folder / LEDGER
    if not path.exists():
        return []
    records = []
    for number, line in enumerate(path.read_text().splitlines(), 1):
        try:
            records.append(TrialRecord(**json.loads(line)))
        except (json.JSONDecodeError, TypeError):
            warnings.warn(f"{path}:{number} is not a trial record; it is ignored", stacklevel=2)
    return records


def latest(records: list[TrialRecord]) -> dict[tuple[str, str], TrialRecord]:
    """The last record of each (name, key)."""
    return {(r.name, r.key): r for r in records}
