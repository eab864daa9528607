"""`softarm replay` as one call: check outputs, imagine the recording, then write the .rrd, MCAP and PNG asked for.

Light to import: torch loads when `replay()` first runs, rerun and PIL only when a timeline or a
picture is asked for.
"""

import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional, Sequence, Union

from softarm.errors import CheckpointError
from softarm.files import check_outputs, claimed, input_file, made_folders
from softarm.imagine.blind import parse_blind
from softarm.imagine.recording import write_imagination

if TYPE_CHECKING:
    from softarm.imagine.replay_data import Replay

PathLike = Union[str, Path]


@dataclass(frozen=True)
class ReplayOutcome:
    replay: "Replay"
    wall_seconds: float

    @property
    def metrics(self) -> dict[str, Any]:
        return self.replay.metrics

    @property
    def real_time_factor(self) -> float:
        return len(self.replay.times) * self.replay.recording.frame_dt / self.wall_seconds


def replay(checkpoint: PathLike, recording: PathLike, blind: Sequence[str] = (), rrd: Optional[PathLike] = None,
           mcap: Optional[PathLike] = None, png: Optional[PathLike] = None, spawn: bool = False,
           force: bool = False, sensor_noise: Optional[dict[str, Any]] = None,
           png_span: Optional[str] = None, device: str = "auto") -> ReplayOutcome:
    """Imagine every frame of `recording` with `checkpoint` and score it; write the outputs asked for.

    `blind` takes camera blackouts as 'START:END' seconds; `sensor_noise` replaces the imperfections the
    checkpoint was trained with (keys of the [sensing] config section); the networks run on `device` (auto | cpu |
    cuda). Every output is checked before the replay starts, so a refused path costs nothing; each is written
    whole or not at all.
    """
    from softarm.record.reader import read_model

    start = time.perf_counter()
    ranges = parse_blind(blind)  # bad input first: a refused run creates no folder and loads no torch
    span = parse_blind([png_span], "--png-span")[0] if png_span is not None else None
    outputs = [Path(p) for p in (rrd, mcap, png) if p is not None]
    check_outputs(outputs, force, inputs=[checkpoint, recording])
    input_file(checkpoint, "checkpoint", CheckpointError)
    read_model(recording)  # a missing, foreign or damaged recording too (its metadata only)
    from softarm.imagine.replay_data import compute_replay  # torch loads here, not when softarm is imported

    with made_folders(outputs), claimed(outputs):
        result = compute_replay(checkpoint, recording, ranges, nodes=rrd is not None or spawn,
                                sensor_noise=sensor_noise, device=device)
        write_outputs(result, rrd, mcap, png, spawn, span)
    return ReplayOutcome(result, time.perf_counter() - start)


def write_outputs(result: "Replay", rrd: Optional[PathLike], mcap: Optional[PathLike], png: Optional[PathLike],
                  spawn: bool, span: Optional[tuple[float, float]] = None) -> None:
    """The timeline (file and/or viewer), the imagination MCAP and the filmstrip asked for."""
    timeline = rrd is not None or spawn
    if png is not None:  # first: a span without frames is refused before any file is written
        from softarm.view.filmstrip import replay_filmstrip, save_png  # PIL only when a picture is asked for

        picture = replay_filmstrip(result, span=span)
    if timeline or mcap is not None:
        from softarm.view.images import probability_bytes

        imagined_bytes = probability_bytes(result.imagined)  # once, for every writer that shows them
    if timeline:
        from softarm.view.replay_view import log_replay  # rerun is only imported when a timeline is asked for

        log_replay(result, Path(rrd) if rrd is not None else None, spawn=spawn, imagined_bytes=imagined_bytes)
    if mcap is not None:
        write_imagination(result, mcap, imagined_bytes)
    if png is not None:
        save_png(picture, png)
