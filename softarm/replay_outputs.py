"""`softarm replay` as one call: check outputs, replay, then write the .rrd, MCAP and PNG asked for."""

import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Optional, Sequence, Union

from softarm.errors import OutputError
from softarm.filmstrip import save_png
from softarm.imagination_recording import write_imagination
from softarm.outputs import check_outputs
from softarm.replay import Replay, filmstrip_of, parse_blind, replay

PathLike = Union[str, Path]


@dataclass(frozen=True)
class ReplayOutcome:
    replay: Replay
    wall_seconds: float

    @property
    def metrics(self) -> dict[str, Any]:
        return self.replay.metrics

    @property
    def real_time_factor(self) -> float:
        return len(self.replay.times) * self.replay.recording.frame_dt / self.wall_seconds


def write_replay(checkpoint: PathLike, recording: PathLike, blind: Sequence[str] = (), rrd: Optional[PathLike] = None,
                 mcap: Optional[PathLike] = None, png: Optional[PathLike] = None, spawn: bool = False,
                 force: bool = False) -> ReplayOutcome:
    """Every output is checked before the replay starts, so a refused path costs nothing; each is written whole."""
    start = time.perf_counter()
    outputs = [Path(p) for p in (rrd, mcap, png) if p is not None]
    if len(set(outputs)) != len(outputs):
        raise OutputError("--rrd, --mcap and --png must name different files")
    check_outputs(outputs, force)
    timeline = rrd is not None or spawn
    result = replay(checkpoint, recording, parse_blind(blind), nodes=timeline)
    if timeline:
        from softarm.viz import log_replay  # rerun is only imported when a timeline is asked for
        log_replay(result, Path(rrd) if rrd is not None else None, spawn=spawn)
    if mcap is not None:
        write_imagination(result, mcap)
    if png is not None:
        save_png(filmstrip_of(result), png)
    return ReplayOutcome(result, time.perf_counter() - start)
