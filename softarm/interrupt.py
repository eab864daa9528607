"""Ctrl-C as a request: long jobs check a flag at safe points instead of dying mid-write."""

import signal
from contextlib import contextmanager
from typing import Iterator

_open: list[list[int]] = []  # the flags of the stop_on_signal blocks in force, innermost last


@contextmanager
def stop_on_signal() -> Iterator[list[int]]:
    """Turn Ctrl-C (and SIGTERM) into a flag the loop checks between blocks, so no frame is half written.

    Blocks nest (a suite's levels each run a simulation): a signal caught by an inner block is passed
    on to the enclosing one when the inner block ends, so a request that came as the inner job finished
    still stops the outer one.
    """
    caught: list[int] = []
    handlers = {}

    def handle(signum: int, _frame: object) -> None:
        caught.append(signum)

    for sig in (signal.SIGINT, signal.SIGTERM):
        try:
            handlers[sig] = signal.signal(sig, handle)
        except ValueError:  # not the main thread: leave signals alone
            pass
    _open.append(caught)
    try:
        yield caught
    finally:
        _open.pop()
        for sig, old in handlers.items():
            signal.signal(sig, old)
        if caught and _open:
            _open[-1].extend(caught)
