"""Recording beside the simulation: writer processes encode and write the MCAP files of a batch.

Encoding and writing cost about as much as the physics, so they run in other processes, one per core
(each owns some arms), while the simulation steps the next block. Blocks travel through two shared
slots, so a slow disk slows the simulation instead of filling memory and nothing is pickled. The parent
never waits on a writer without also watching whether it lives: a writer that dies (killed, out of
memory) or fails (a full disk) is noticed at the parent's next exchange with the writers (every block,
and within a second while it waits on them), the others close their files with every frame, and
`WriterFailed` says which file holds how many frames. Writers that answer nothing for WRITER_DEADLINE
seconds while the parent waits on them (a hung disk) fail the same way, and are not waited for again.
"""

import multiprocessing
import os
import signal
import time
from multiprocessing.connection import Connection, wait
from pathlib import Path
from typing import Callable

import numpy as np

from softarm.errors import RecordingError
from softarm.files import part_path
from softarm.record.slots import BlockShape, Slot
from softarm.record.writer_process import Spec, serve

IN_FLIGHT = 2          # slots: one filled by the simulation while the writers encode the other
GIVE_UP_SECONDS = 30   # a writer that answers nothing for this long while it closes is killed
# s without a word from any writer while the parent waits on them: the run ends with what reached the disk
WRITER_DEADLINE = float(os.environ.get("SOFTARM_WRITER_DEADLINE", 120))


def writer_processes(arms: int) -> int:
    """One writer per core this process may use (its affinity, not the host's core count), at most one per arm."""
    return max(1, min(arms, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1))


class WriterFailed(RecordingError):
    """A writer process died or failed; the files were kept (closed, or as recoverable .part files)."""


class RecorderProcess:
    """The writers of a batch. `write` blocks only while both slots are still being written."""

    def __init__(self, specs: list[Spec], shape: BlockShape, processes: int = 0):
        context = multiprocessing.get_context("fork")  # no re-import: a writer starts in milliseconds
        self.paths = [Path(path) for path, _, _ in specs]
        self.slots = [Slot(shape) for _ in range(IN_FLIGHT)]
        count = max(1, min(len(specs), processes or writer_processes(len(specs))))
        self._conns: list[Connection] = []
        self._processes: list[multiprocessing.process.BaseProcess] = []
        self._busy: list[set[int]] = [set() for _ in range(IN_FLIGHT)]
        self._finished: set[int] = set()  # writers that closed or discarded their files and exited
        self._stuck = False  # the writers missed WRITER_DEADLINE: nothing more is waited for
        self._next = 0
        try:
            for k in range(count):
                parent_end, child_end = context.Pipe()
                process = context.Process(target=serve, args=(list(range(k, len(specs), count)), specs, self.slots,
                                                              child_end, os.getpid()), daemon=True)
                process.start()
                child_end.close()
                self._conns.append(parent_end)
                self._processes.append(process)
            self._await(lambda k, message: message[0] == "ready", range(count))
        except BaseException:  # a fork failed, Ctrl-C came, or a writer could not open its files: nothing is left
            self.discard()
            raise

    def write(self, images: np.ndarray, readings: np.ndarray, positions: np.ndarray, displacements: np.ndarray) -> None:
        """Share one block of every arm with the writers (copied into the next free slot)."""
        slot = self._next
        self._next = (slot + 1) % IN_FLIGHT
        self._drain(slot)
        n = self.slots[slot].put(images, readings, positions, displacements)
        for k in range(len(self._conns)):
            self._send(k, ("write", slot, n))
        self._busy[slot] = set(range(len(self._conns)))

    def close(self, complete: bool) -> None:
        """Finish every file (complete or not) and wait until they are renamed into place."""
        for slot in range(IN_FLIGHT):
            self._drain(slot)
        for k in range(len(self._conns)):
            self._send(k, ("close", complete))
        self._await(lambda k, message: message[0] == "closed", range(len(self._conns)))
        self._join()

    def discard(self) -> None:
        """Remove every unfinished file (a refused or blown-up run leaves nothing) and end the writers."""
        for k, process in enumerate(self._processes):
            if process.is_alive():
                try:
                    self._conns[k].send(("discard",))
                except OSError:
                    pass
        self._join()
        for path in self.paths:
            part_path(path).unlink(missing_ok=True)

    def keep(self) -> None:
        """After a failure: the living writers close their files with what they hold (complete = "false"); stuck
        ones are ended at once, their files kept as recoverable .part files."""
        if self._stuck:
            self.abandon()
            return
        living = [k for k, process in enumerate(self._processes) if process.is_alive() and k not in self._finished]
        for k in living:
            try:
                self._conns[k].send(("close", False))
            except OSError:
                pass
        for k in living:  # until each says closed (or failed, or goes), past any pending "wrote"
            while self._conns[k].poll(GIVE_UP_SECONDS):
                try:
                    if self._conns[k].recv()[0] in ("closed", "failed"):
                        break
                except (EOFError, OSError):
                    break
        self._join()

    def abandon(self) -> None:
        """End every writer now (a second stop request, or stuck writers): their files stay as they are, whole
        chunks recoverable from the .part files."""
        for process in self._processes:
            if process.is_alive():
                process.kill()
        self._join()

    def _drain(self, slot: int) -> None:
        """Wait until no writer is still reading `slot`."""
        busy = self._busy[slot]
        while busy:
            k, message = self._receive()
            if message[0] == "wrote":
                self._busy[message[1]].discard(k)

    def _await(self, done: Callable[[int, tuple], bool], writers: range) -> None:
        waiting = set(writers)
        while waiting:
            k, message = self._receive()
            if message[0] == "wrote":
                self._busy[message[1]].discard(k)
            elif done(k, message):
                waiting.discard(k)
                if message[0] in ("closed", "discarded"):
                    self._finished.add(k)

    def _receive(self) -> tuple[int, tuple]:
        """The next message of any writer; a failure or a dead writer raises WriterFailed."""
        living = [k for k in range(len(self._processes)) if k not in self._finished]
        sentinels = {self._processes[k].sentinel: k for k in living}
        deadline = time.monotonic() + WRITER_DEADLINE
        while True:
            for k in living:
                conn = self._conns[k]
                if conn.poll():
                    try:
                        message = conn.recv()
                    except (EOFError, OSError):
                        self._fail(k, None)
                    if message[0] == "failed":
                        self._fail(k, message[1])
                    return k, message
            ready = wait([*(self._conns[k] for k in living), *sentinels], timeout=1.0)
            for item in ready:
                if item in sentinels and not self._conns[sentinels[item]].poll():
                    self._fail(sentinels[item], None)
            if not ready and time.monotonic() > deadline:
                self._stuck = True
                raise WriterFailed(f"the writer processes answered nothing for {WRITER_DEADLINE:g} s (a hung disk?)")

    def _send(self, k: int, message: tuple) -> None:
        try:
            self._conns[k].send(message)
        except OSError:  # the writer is gone
            self._fail(k, None)

    def _fail(self, k: int, reason: str | None) -> None:
        process = self._processes[k]
        process.join(timeout=1)
        reason = reason or self._last_word(k)
        if reason is None:
            code = process.exitcode
            reason = (f"killed by {signal.Signals(-code).name}" if code is not None and code < 0
                      else f"exited with code {code}" if code is not None else "stopped answering")
        raise WriterFailed(f"writer process {k + 1} of {len(self._processes)} failed ({reason})")

    def _last_word(self, k: int) -> str | None:
        """The reason a writer that is gone gave before it went, if it gave one."""
        try:
            while self._conns[k].poll():
                message = self._conns[k].recv()
                if message[0] == "failed":
                    return message[1]
        except (EOFError, OSError):
            pass
        return None

    def _join(self) -> None:
        """End the writers (killing one that does not finish in GIVE_UP_SECONDS) and release pipes and slots."""
        for process in self._processes:
            process.join(timeout=GIVE_UP_SECONDS)
            if process.is_alive():
                process.kill()
                process.join()
        for conn in self._conns:
            conn.close()
        for slot in self.slots:
            slot.release()
