"""Ctrl-C as a request: long jobs check a flag at safe points instead of dying mid-write.

SIGINT (Ctrl-C), SIGTERM (`timeout`, batch schedulers, container stops) and SIGHUP (a closed terminal) all
count as the request. A second one while the first is being honoured raises `Escalated`: the job then
ends at once with what is on disk.
"""

import signal
import site
import sys
import sysconfig
from contextlib import contextmanager
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from types import FrameType
from typing import Any, Callable, Iterator, Optional

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

    def handle(signum: int, frame: Optional[FrameType]) -> None:
        caught.append(signum)
        _heard.append(signum)
        if len(caught) > 1:
            raise_in_own_code(Escalated(), frame)

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


def raise_in_own_code(error: BaseException, frame: Optional[FrameType]) -> None:
    """Raise `error` from a signal handler where the main thread is (`frame`), unless it is running a library's
    Python: C++ may have called that (torch, Taichi, through pybind11), and an exception there aborts the whole
    process ("terminate called after throwing an instance of 'pybind11::error_already_set'", exit -6, locks and
    `.part` files left behind). Then `error` waits for the main thread to reach softarm's or its user's code again:
    the caller the library returns to (at its next line) or a function of theirs the library calls (at its start),
    whichever comes first: milliseconds in a torch operation's Python, a second or two in an import of torch."""
    caller = _own_caller(frame)
    if caller is None:
        raise error
    before = _waiting.pop().before if _waiting else sys.gettrace()
    _waiting.append(_Waiting(before, error, caller))
    caller.f_trace = _at_next_line
    sys.settrace(_until_own_code)


@dataclass
class _Waiting:
    """A deferred stop: the trace function in force before it, the error, the frame to raise it in."""
    before: Optional[Callable[..., Any]]
    error: BaseException
    frame: FrameType


_waiting: list[_Waiting] = []  # the deferred stop, if one waits


def _own_caller(frame: Optional[FrameType]) -> Optional[FrameType]:
    """None where `frame` runs softarm's code, its user's, or the standard library's called from them; else the
    nearest caller that does."""
    while frame is not None and _kind(frame) == "standard":
        frame = frame.f_back
    if frame is None or _kind(frame) != "library":
        return None
    while frame is not None and _kind(frame) != "own":
        frame = frame.f_back
    return frame


def _due() -> BaseException:
    """The deferred stop, tracing as it was before it."""
    waiting = _waiting.pop()
    waiting.frame.f_trace = None
    sys.settrace(waiting.before)
    return waiting.error


def _until_own_code(frame: FrameType, event: str, _arg: Any) -> None:
    """The trace function while a stop waits: own code a library calls raises it at its start; no frame is traced
    for its own sake."""
    if _waiting and event == "call" and _kind(frame) == "own":
        raise _due()


def _at_next_line(frame: FrameType, event: str, _arg: Any) -> Optional[Callable[..., Any]]:
    """The waiting frame's trace function: its next line raises the stop; should it return first, its caller
    waits instead."""
    if not _waiting or _waiting[0].frame is not frame:
        return None
    if event == "exception":
        return _at_next_line
    if event == "line" or frame.f_back is None:
        raise _due()
    frame.f_trace = None
    _waiting[0].frame = _own_caller(frame.f_back) or frame.f_back
    _waiting[0].frame.f_trace = _at_next_line
    return None


def _kind(frame: FrameType) -> str:
    """"library" (an installed package's code, softarm's own excepted), "standard" (Python's library, and code made
    at run time, a dataclass's `__init__`, which belongs to whoever calls it) or "own" (a script's own top level,
    `python -c`'s, included)."""
    file = frame.f_code.co_filename
    if file.startswith("<"):
        return "own" if frame.f_back is None and not file.startswith("<frozen ") else "standard"
    own, libraries, standard = _roots()
    if file.startswith(own):
        return "own"
    if file.startswith(libraries):
        return "library"
    return "standard" if file.startswith(standard) else "own"


@cache
def _roots() -> tuple[tuple[str, ...], tuple[str, ...], tuple[str, ...]]:
    """The folders of softarm's code (the command line's included, once imported), of installed packages, and of
    Python's library (which may hold site-packages: libraries are told first)."""
    packages = [sys.modules[name] for name in ("softarm", "softarm_cli") if name in sys.modules]
    own = tuple(folder.rstrip("/") + "/" for package in packages for folder in package.__path__)
    paths = sysconfig.get_paths()
    folders = [*site.getsitepackages(), site.getusersitepackages(), paths["purelib"], paths["platlib"],
               *(p for p in sys.path if Path(p).name in ("site-packages", "dist-packages"))]
    libraries = tuple({folder.rstrip("/") + "/" for f in folders for folder in (f, str(Path(f).resolve()))})
    standard = tuple({paths[k].rstrip("/") + "/" for k in ("stdlib", "platstdlib")})
    return own, libraries, standard
