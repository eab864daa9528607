"""Writes one arm's run as a softarm-recording/3 MCAP file (docs/recording.md).

The file grows as `<name>.mcap.part` and is renamed when it is closed, so a path without `.part`
is always a whole file: closed normally (`complete = "true"`), or cut off with every frame recorded so
far (`complete = "false"`). A blown-up run discards its `.part`; a failed write leaves it for the reader.
"""

from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional, Sequence

import numpy as np
import orjson

from softarm import __version__
from softarm.arm.body import Body
from softarm.arm.camera import world_to_pixel
from softarm.arm.drive import Drive
from softarm.config import Config
from softarm.record.format import (
    ACTIVATION,
    ACTIVATION_SCHEMA,
    CONTACT_SCHEMA,
    DISTURBANCE,
    EXCITATION,
    FORMAT,
    IMAGE,
    JSON_SCHEMAS,
    META_MODEL,
    META_RUN,
    NODES,
    POSITION_DECIMALS,
    STRETCH,
    sensor_schema,
)
from softarm.record.frames import FRAME_TOPICS, encode_frames
from softarm.record.mcap_file import McapFile
from softarm.sensors import declared

if TYPE_CHECKING:
    from softarm.disturbances import Disturbance


def model_metadata(config: Config, body: Body, drive: Drive, seed: int, positions: np.ndarray, velocities: np.ndarray,
                   disturbances: Sequence["Disturbance"] = ()) -> dict[str, Any]:
    """Everything another program needs to re-simulate this arm without softarm (docs/model.md, docs/recording.md)."""
    return ArmMetadata(config, body)(drive, seed, positions, velocities, disturbances)


class ArmMetadata:
    """The model metadata of the arms of one config and body: what they share (the body, the camera, the config)
    is built once, not once an arm (a 256-arm batch spent 0.32 s of its start there)."""

    def __init__(self, config: Config, body: Body):
        self.body = {"nodes": body.rest.tolist(), "masses": body.masses.tolist(), "springs": body.springs.tolist(),
                     "rest_lengths": body.rest_lengths.tolist(), "stiffness": body.stiffness.tolist(),
                     "damping": body.damping.tolist(), "driven": body.driven.tolist(), "gravity": body.gravity.tolist()}
        self.sensing = {"sensors": body.sensors.tolist(), **{name: p.tolist() for name, p in body.placed.items()},
                        "outline": body.outline.tolist(),
                        "camera": {"width": config.camera.width, "height": config.camera.height,
                                   "world_to_pixel": world_to_pixel(config.camera).tolist()},
                        "frame_dt": config.integration.frame_dt, "substeps": config.integration.substeps,
                        "integrator": config.integration.integrator}
        self.versions = {"softarm_version": __version__, "config": config.to_dict()}

    def __call__(self, drive: Drive, seed: int, positions: np.ndarray, velocities: np.ndarray,
                 disturbances: Sequence["Disturbance"] = ()) -> dict[str, Any]:
        """One arm's, its keys in the order every recording has them."""
        return {**self.body, "excitation": drive.parameters(), **self.sensing,
                "initial": {"positions": positions.tolist(), "velocities": velocities.tolist()}, "seed": seed,
                "disturbances": [d.metadata() for d in disturbances], **self.versions}


class RecordingWriter:
    """One open recording. Use `close(complete)` to finish it or `discard()` to remove it."""

    def __init__(self, path: Path, model: dict[str, Any], frame_dt: float):
        self.path = Path(path)
        self.frame_dt = frame_dt
        self.frames = 0
        self.broken = False
        disturbances = model.get("disturbances", [])
        self._obstacles = [(i, np.array(d["centre"], float), float(d["radius"]))
                           for i, d in enumerate(disturbances) if d.get("kind") == "obstacle"]
        self._free = np.setdiff1d(np.arange(len(model["nodes"])), model["driven"]) if self._obstacles else None
        self._sensors = [(kind, np.asarray(model[kind.name], np.int64), np.asarray(model["nodes"], np.float64))
                         for kind in declared(model)]
        schemas = {**JSON_SCHEMAS, **(ACTIVATION_SCHEMA if "muscles" in model else {}),
                   **(CONTACT_SCHEMA if self._obstacles else {}), **{k: v for kind, _, _ in self._sensors
                                                                     for k, v in sensor_schema(kind).items()}}
        self._mcap = McapFile(self.path, (IMAGE,), schemas)
        self._mcap.writer.add_metadata(META_MODEL, {"format": FORMAT, "model": orjson.dumps(model).decode()})
        self._windows = [(d["start"], np.inf if d["end"] is None else d["end"]) for d in disturbances]

    def write(self, images: np.ndarray, stretch: np.ndarray, positions: np.ndarray, displacement: np.ndarray,
              muscles: Optional[tuple[np.ndarray, np.ndarray]] = None) -> None:
        """Append a block of frames: images (B, H, W) of 0/1, stretch (B, P), positions (B, N, 2), displacement (B,),
        and for a commanded arm, its muscles' (commands, activations), each (B, G).

        A write that fails (a full disk) marks the writer broken: its file may end in half a record, so it
        must stay `.part` (the reader recovers every complete chunk) and never be closed.
        """
        self.broken = True
        self._write(images, stretch, positions, displacement, muscles)
        self.broken = False

    def _write(self, images: np.ndarray, stretch: np.ndarray, positions: np.ndarray, displacement: np.ndarray,
               muscles: Optional[tuple[np.ndarray, np.ndarray]]) -> None:
        n = len(images)
        stamps = np.round(np.arange(self.frames, self.frames + n) * self.frame_dt * 1e9).astype(np.int64)
        stretch, positions, displacement = (np.ascontiguousarray(a, np.float64)
                                            for a in (stretch, positions, displacement))
        active = self._active(n)
        touching = self._touching(positions, active) if self._obstacles else None
        encoded = None if muscles is not None or self._sensors else encode_frames(
            stamps, tuple(self._mcap.channels[topic] for topic in FRAME_TOPICS),
            self._mcap.image_encoder(*images.shape[1:]), images, stretch, positions, displacement, active, touching)
        if encoded is not None:
            self._mcap.add_records(stamps, FRAME_TOPICS, *encoded)
        else:
            self._mcap.add_frames(stamps.tolist(), self._messages(stamps.tolist(), images, stretch, positions,
                                                                  displacement, active, touching, muscles))
        self.frames += n

    def _messages(self, stamps: list[int], images: np.ndarray, stretch: np.ndarray, positions: np.ndarray,
                  displacement: np.ndarray, active: list[list[int]], touching: Optional[list[list[int]]],
                  muscles: Optional[tuple[np.ndarray, np.ndarray]]) -> dict[str, list[bytes]]:
        """The Python encoder: each topic's messages of the block (the reference the C encoder matches)."""
        seconds = [ns / 1e9 for ns in stamps]
        positions = np.round(positions, POSITION_DECIMALS)  # a fresh C-contiguous array, as orjson needs
        dumps, numpy = orjson.dumps, orjson.OPT_SERIALIZE_NUMPY
        messages = {
            IMAGE: self._mcap.images(np.multiply(images, 255, dtype=np.uint8), stamps),
            STRETCH: [dumps({"t": t, "stretch": s}, option=numpy) for t, s in zip(seconds, stretch)],
            NODES: [dumps({"t": t, "positions": p}, option=numpy) for t, p in zip(seconds, positions)],
            EXCITATION: [dumps({"t": t, "displacement": float(d)}) for t, d in zip(seconds, displacement)],
            DISTURBANCE: [dumps({"t": t, "active": a}) for t, a in zip(seconds, active)] if touching is None else
                         [dumps({"t": t, "active": a, "touching": c}) for t, a, c in zip(seconds, active, touching)]}
        for kind, placements, rest in self._sensors:  # the other sensor kinds, read from the simulated positions
            readings = np.ascontiguousarray(kind.ideal(positions, rest, placements), np.float64)
            messages[kind.topic] = [dumps({"t": t, kind.field: r}, option=numpy) for t, r in zip(seconds, readings)]
        if muscles is not None:
            command, activation = (np.ascontiguousarray(m, np.float64) for m in muscles)
            messages[ACTIVATION] = [dumps({"t": t, "command": u, "activation": a}, option=numpy)
                                    for t, u, a in zip(seconds, command, activation)]
        return messages

    def _active(self, n: int) -> list[list[int]]:
        """The disturbances active at each of the next n frames: start <= k frame_dt < end."""
        times = np.arange(self.frames, self.frames + n) * self.frame_dt
        if not self._windows:
            return [[] for _ in range(n)]
        start, end = np.array(self._windows).T
        on = (start[None] <= times[:, None]) & (times[:, None] < end[None])
        return [np.flatnonzero(row).tolist() for row in on]

    def _touching(self, positions: np.ndarray, active: list[list[int]]) -> list[list[int]]:
        """The active obstacles that some free node is inside at each frame of the block (|x - centre| < radius,
        from the simulated positions): the label of contact."""
        inside = {i: [bool(k) for k in (np.sqrt(((positions[:, self._free] - centre) ** 2).sum(axis=2))
                                        < radius).any(axis=1)]
                  for i, centre, radius in self._obstacles}
        return [[i for i in row if i in inside and inside[i][k]] for k, row in enumerate(active)]

    def close(self, complete: bool) -> Path:
        """Write the run record, the summary and the index, then move the file to its final name."""
        return self._mcap.close({META_RUN: {"complete": "true" if complete else "false", "frames": str(self.frames)}})

    def discard(self) -> None:
        """Drop the unfinished file: a failed run leaves nothing behind."""
        self._mcap.discard()
