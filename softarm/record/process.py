"""Recording beside the simulation: a child process encodes and writes the MCAP files of a batch.

Encoding (protobuf, JSON) and writing take about as long as the physics of a default run, so doing
them in the simulating process would make recording the slowest stage. The child owns one
`RecordingWriter` per arm and takes whole blocks through a bounded queue (at most two blocks in
flight, so a slow disk slows the simulation instead of filling memory). It ignores Ctrl-C: the
parent decides, then asks it to close (keeping what was recorded) or to discard; a child whose
parent died discards its files by itself.
"""

import multiprocessing
import os
import queue
import signal
from pathlib import Path
from typing import Any

import numpy as np

from softarm.errors import OutputError
from softarm.files import part_path
from softarm.record.writer import RecordingWriter

IN_FLIGHT = 2


def _serve(specs: list[tuple[Path, dict[str, Any], float]], inbox: Any, outbox: Any, parent: int) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C reaches the whole process group; the parent decides
    writers: list[RecordingWriter] = []
    try:
        for path, model, frame_dt in specs:
            writers.append(RecordingWriter(path, model, frame_dt))
        outbox.put(("ready", None))
        while True:
            try:
                message = inbox.get(timeout=1.0)
            except queue.Empty:
                if os.getppid() != parent:  # the parent died without a word: leave nothing half written
                    message = ("discard",)
                else:
                    continue
            if message[0] == "write":
                images, readings, positions, displacements = message[1:]
                for arm, writer in enumerate(writers):
                    writer.write(images[arm], readings[arm], positions[arm], displacements[arm])
            elif message[0] == "close":
                for writer in writers:
                    writer.close(message[1])
                outbox.put(("closed", None))
                return
            else:
                for writer in writers:
                    writer.discard()
                outbox.put(("discarded", None))
                return
    except Exception as e:  # tell the parent in one line, leave no partial file
        for writer in writers:
            writer.discard()
        outbox.put(("error", f"{type(e).__name__}: {e}"))


class RecorderProcess:
    """The writers of a batch, in a child process. `write` blocks only when two blocks are already queued."""

    def __init__(self, specs: list[tuple[Path, dict[str, Any], float]]):
        context = multiprocessing.get_context("fork")  # no re-import: the child starts in milliseconds
        self._parts = [part_path(path) for path, _, _ in specs]
        self._inbox = context.Queue(maxsize=IN_FLIGHT)
        self._outbox = context.Queue()
        self._process = context.Process(target=_serve, args=(specs, self._inbox, self._outbox, os.getpid()),
                                        daemon=True)
        self._process.start()
        self._expect("ready")

    def write(self, images: np.ndarray, readings: np.ndarray, positions: np.ndarray, displacements: np.ndarray) -> None:
        """Queue one block of every arm. The arrays are copied now: the caller reuses its buffers."""
        self._put(("write", images.copy(), readings.copy(), positions.copy(), displacements.copy()))

    def close(self, complete: bool) -> None:
        """Finish every file (complete or not) and wait until they are renamed into place."""
        self._put(("close", complete))
        self._expect("closed")

    def discard(self) -> None:
        """Remove every unfinished file and wait until they are gone (ending the child if it hangs)."""
        try:
            if self._process.is_alive():
                self._put(("discard",))
                self._process.join(timeout=30)
        except OutputError:
            pass
        finally:
            if self._process.is_alive():
                self._process.kill()
                self._process.join()
            for part in self._parts:
                part.unlink(missing_ok=True)

    def _put(self, message: tuple) -> None:
        while True:
            try:
                self._inbox.put(message, timeout=0.5)
                return
            except queue.Full:
                self._raise_if_failed()

    def _raise_if_failed(self) -> None:
        try:
            kind, detail = self._outbox.get_nowait()
        except queue.Empty:
            if not self._process.is_alive():
                self._raise_dead()
            return
        if kind == "error":
            raise OutputError(f"recording failed: {detail}")

    def _raise_dead(self) -> None:
        """The child is gone: report its last word if it left one."""
        try:
            kind, detail = self._outbox.get(timeout=0.5)
        except queue.Empty:
            raise OutputError("the recording process stopped unexpectedly") from None
        raise OutputError(f"recording failed: {detail}" if kind == "error" else "the recording process stopped early")

    def _expect(self, kind: str) -> None:
        while True:
            try:
                got, detail = self._outbox.get(timeout=0.5)
            except queue.Empty:
                if not self._process.is_alive():
                    self._raise_dead()
                continue
            if got == "error":
                self._process.join(timeout=30)
                raise OutputError(f"recording failed: {detail}")
            if got == kind:
                if kind != "ready":  # closed: the child has finished its work
                    self._process.join(timeout=30)
                return
