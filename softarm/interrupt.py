"""Ctrl-C as a request: long jobs check a flag at safe points instead of dying mid-write."""

import signal
from contextlib import contextmanager
from typing import Iterator


@contextmanager
def stop_on_signal() -> Iterator[list[int]]:
    """Turn Ctrl-C (and SIGTERM) into a flag the loop checks between blocks, so no frame is half written."""
    caught: list[int] = []
    handlers = {}

    def handle(signum: int, _frame: object) -> None:
        caught.append(signum)

    for sig in (signal.SIGINT, signal.SIGTERM):
        try:
            handlers[sig] = signal.signal(sig, handle)
        except ValueError:  # not the main thread: leave signals alone
            pass
    try:
        yield caught
    finally:
        for sig, old in handlers.items():
            signal.signal(sig, old)
