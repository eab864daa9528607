"""One writer process: owns the recordings of some arms of a batch and writes the blocks the simulation shares.

It ignores Ctrl-C and SIGTERM, which reach the whole process group: the simulating parent decides and
then asks it to close (keeping every frame) or to discard. A writer whose parent died closes its
files by itself with complete = "false"; a writer that fails (a full disk) leaves its `.part` files,
whose complete chunks the reader recovers, and says why before it exits.
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
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
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
        _tell(conn, ("failed", f"{e.strerror or e}" + (f": {e.filename}" if e.filename else "")))
    except Exception as e:
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


def _tell(conn: Connection, message: tuple) -> None:
    try:
        conn.send(message)
    except OSError:  # the parent is gone too
        pass
