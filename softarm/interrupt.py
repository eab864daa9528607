"""Ctrl-C as a request: long jobs check a flag at safe points instead of dying mid-write.

SIGINT (Ctrl-C), SIGTERM (`timeout`, batch schedulers, container stops) and SIGHUP (a closed terminal) all
count as the request. A second one while the first is being honoured raises `Escalated`: the job then
ends at once with what is on disk.
"""

import signal
from contextlib import contextmanager
from typing import Iterator

_open: list[list[int]] = []  # the flags of the stop_on_signal blocks in force, innermost last
_heard: list[int] = []       # every stop request any block caught in this process
_raised: list[int] = []      # stop requests raised as KeyboardInterrupt outside any block (`raised_outside`)
SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


def requested() -> bool:
    """Whether a stop request was caught in this process: a job is winding down (the command line then ignores
    the requests that follow it instead of cutting its cleanup short)."""
    return bool(_heard)


def raised_outside(signum: int) -> None:
    """A stop request the command line raised as KeyboardInterrupt while no job was running. Code that swallows
    it (a C extension's initialisation, a callback from C++) leaves the command running with further requests
    ignored; so a job that starts after it starts with the request caught, and stops at its first safe point."""
    _raised.append(signum)


class Escalated(KeyboardInterrupt):
    """A second stop request: stop now, without waiting for a clean end."""


class Stopped(Exception):
    """A stop request ended work that has nothing to keep yet (training while it reads its recordings)."""


class Interrupted(KeyboardInterrupt):
    """A stop request ended a job; its message says what it kept on disk (the command line prints it after
    "interrupted:" and exits 130)."""


@contextmanager
def stop_on_signal() -> Iterator[list[int]]:
    """Turn Ctrl-C (and SIGTERM, SIGHUP) into a flag the loop checks between blocks, so no frame is half
    written; a second request raises Escalated.

    Blocks nest (a suite's levels each run a simulation): an inner block starts with the requests its outer one
    has caught, and passes the ones it catches on to it when it ends, so a request that came before the inner
    job started, or as it finished, still stops both. An outermost block starts with the requests raised before
    it outside any job (`raised_outside`).
    """
    inherited = list(_open[-1]) if _open else list(_raised)
    caught = list(inherited)
    handlers = {}

    def handle(signum: int, _frame: object) -> None:
        caught.append(signum)
        _heard.append(signum)
        if len(caught) > 1:
            raise Escalated()

    for sig in SIGNALS:
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
        if _open:
            _open[-1].extend(caught[len(inherited):])
