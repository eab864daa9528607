"""One writer process: owns the recordings of some arms of a batch and writes the blocks the simulation shares.

It ignores Ctrl-C, SIGTERM and SIGHUP, which reach the whole process group: the simulating parent decides and
then asks it to close (keeping every frame) or to discard. A writer whose parent died closes its
files by itself with complete = "false" (it polls for its parent every second: the pipe cannot say, since
writers forked later hold its other end too); a writer that fails (a full disk) closes what it still can
and leaves the rest as `.part` files, whose complete chunks the reader recovers, and says why.
"""

import os
import signal
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Any

from softarm.record.slots import Slot
from softarm.record.writer import RecordingWriter

Spec = tuple[Path, dict[str, Any], float]  # path, model metadata, frame step
POLL_SECONDS = 1.0                          # how often an idle writer checks that its parent lives


def serve(arms: list[int], specs: list[Spec], slots: list[Slot], conn: Connection, parent: int) -> None:
    """The writer's loop: ("write", slot, n) | ("close", complete) | ("discard",) from the parent, answered
    ("ready",), ("wrote", slot), ("closed",), ("discarded",) or ("failed", reason)."""
    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):  # the parent decides, even when a terminal closes
        signal.signal(sig, signal.SIG_IGN)
    writers: dict[int, RecordingWriter] = {}
    try:
        for arm in arms:
            writers[arm] = RecordingWriter(*specs[arm])
        conn.send(("ready",))
        while True:
            message = _next_message(conn, parent)
            if message is None:  # the parent is gone: keep what was recorded
                _close(writers, complete=False)
                return
            if message[0] == "write":
                _, slot, n = message
                for arm, writer in writers.items():
                    writer.write(*slots[slot].arm(arm, n))
                conn.send(("wrote", slot))
            elif message[0] == "close":
                _close(writers, message[1])
                conn.send(("closed",))
                return
            else:
                for writer in writers.values():
                    writer.discard()
                conn.send(("discarded",))
                return
    except OSError as e:  # no space, an I/O error: the .part files keep every complete chunk
        _close_what_can_be(writers)
        _tell(conn, ("failed", f"{e.strerror or e}" + (f": {e.filename}" if e.filename else "")))
    except Exception as e:
        _close_what_can_be(writers)
        _tell(conn, ("failed", f"{type(e).__name__}: {e}"))


def _next_message(conn: Connection, parent: int) -> Any:
    while not conn.poll(POLL_SECONDS):
        if os.getppid() != parent:
            return None
    try:
        return conn.recv()
    except EOFError:
        return None


def _close(writers: dict[int, RecordingWriter], complete: bool) -> None:
    for writer in writers.values():
        writer.close(complete)


def _close_what_can_be(writers: dict[int, RecordingWriter]) -> None:
    """After a failure, close every file that still can be (complete = "false"); the others stay .part."""
    for writer in writers.values():
        if writer.broken:  # its file may end in half a record: it stays .part
            continue
        try:
            writer.close(False)
        except Exception:  # this one cannot be finished (the disk is full): its .part keeps its chunks
            pass


def _tell(conn: Connection, message: tuple) -> None:
    try:
        conn.send(message)
    except OSError:  # the parent is gone too
        pass
