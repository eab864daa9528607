"""Stop requests at the command line: SIGINT (Ctrl-C), SIGTERM (`timeout`, schedulers, container stops) and SIGHUP
(a closed terminal) end a command as Ctrl-C does, from the console script's first line to its last.

Kept apart from `softarm_cli.main` so the console script arms them before it imports the command line (a second or
more of typer, rich, NumPy): this module imports nothing heavy.
"""

import os
import signal
import sys
import threading
from types import FrameType
from typing import Any, Optional

from softarm.interrupt import SIGNALS as STOP_SIGNALS
from softarm.interrupt import Escalated, raise_in_own_code, raised_outside, requested

AGAIN_AFTER = 0.005  # s: a request a finalizer swallowed comes again this soon, out of the finalizer


def interrupt_as_ctrl_c() -> None:
    """A stop request becomes a KeyboardInterrupt, so that every output is cleaned up on the way out (its `.part`
    removed, its lock released) and the command says "interrupted" and exits 130. Requests after the first are
    ignored while that cleanup runs, so a second one cannot cut it short and leave a lock behind. A long job's own
    handler (`softarm.interrupt.stop_on_signal`: stop at the next safe point, a second request at once) takes over
    while it runs. A request that a finalizer swallowed is made again (`swallowed_requests_come_again`)."""
    for sig in STOP_SIGNALS:
        signal.signal(sig, _interrupt)
    sys.unraisablehook = swallowed_requests_come_again


def ignore_requests() -> None:
    """The command has answered: a request now would only kill Python while it shuts down (exit -2)."""
    for sig in STOP_SIGNALS:
        signal.signal(sig, signal.SIG_IGN)


def _interrupt(signum: int, frame: Optional[FrameType]) -> None:
    ignore_requests()
    if not requested():  # a job that honoured a request already is on its way out: let it finish that
        raised_outside(signum)  # should the KeyboardInterrupt be swallowed, the next job starts stopped
        raise_in_own_code(KeyboardInterrupt(), frame)


def swallowed_requests_come_again(unraisable: Any) -> None:
    """Python runs a signal's handler wherever the main thread is, a finalizer included (a weak reference's
    callback, `__del__`); what a finalizer raises is printed as "Exception ignored" and dropped. A KeyboardInterrupt
    dropped so would leave the command running deaf, its handlers set to ignore further requests: the request is
    made again a moment later, from a thread, so it lands outside the finalizer. Other unraisable errors go to
    Python's own hook."""
    if not isinstance(unraisable.exc_value, KeyboardInterrupt):
        sys.__unraisablehook__(unraisable)
        return
    if not isinstance(unraisable.exc_value, Escalated):  # a job's own handler raised Escalated and is still armed
        for sig in STOP_SIGNALS:
            signal.signal(sig, _interrupt)
    threading.Timer(AGAIN_AFTER, os.kill, (os.getpid(), signal.SIGINT)).start()
