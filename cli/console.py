"""Where the command line speaks: `out` (results, and progress lines when it is a log) and `err` (errors,
warnings, progress bars), and the one rule that turns a user's mistake into one line and exit code 1."""

import os
import sys
import warnings
from typing import Callable, NoReturn, TypeVar

import typer
from rich.console import Console

from softarm.errors import SoftarmError

_interruption_said: list[str] = []  # the line an interrupted command ended with
LOG_WIDTH = 200  # columns of a stream that is no terminal (a log): tables keep every column whole there


def console(stderr: bool) -> Console:
    """A terminal's own width; a log's LOG_WIDTH (rich would cut tables at 80), unless COLUMNS says otherwise."""
    stream = sys.stderr if stderr else sys.stdout
    width = None if "COLUMNS" in os.environ or (hasattr(stream, "isatty") and stream.isatty()) else LOG_WIDTH
    return Console(stderr=stderr, highlight=False, soft_wrap=True, width=width)


err = console(stderr=True)
out = console(stderr=False)
T = TypeVar("T")


def one_line_warning(message: Warning | str, category: type[Warning], *_: object, **__: object) -> None:
    """Warnings (a truncated recording, an unreachable viewer) as one 'warning:' line, no source echo."""
    err.print(f"warning: {message}", markup=False)


warnings.showwarning = one_line_warning


def run_or_exit(action: Callable[[], T]) -> T:
    """Run a library call; a user-caused error becomes one line on stderr and exit code 1, a stop request
    that the call could not turn into a clean end one line and exit code 130."""
    try:
        return action()
    except KeyboardInterrupt as e:  # softarm.interrupt.Escalated (a second Ctrl-C) says what stays on disk
        stop_interrupted(f"interrupted: {e}" if str(e) else "interrupted")
    except SoftarmError as e:
        err.print(f"error: {e}", markup=False)
        raise typer.Exit(1) from None
    except OSError as e:
        err.print(f"error: {e.strerror or e}" + (f": {e.filename}" if e.filename else ""), markup=False)
        raise typer.Exit(1) from None


def stop_interrupted(line: str) -> NoReturn:
    """End an interrupted command: its one line ("interrupted: ..." and what it kept) and exit code 130."""
    _interruption_said.append(line)
    err.print(line, markup=False)
    raise typer.Exit(130)


def interruption_said() -> bool:
    """Whether the command said why it stopped: a request it could not turn into its own line still gets one."""
    return bool(_interruption_said)


def say(text: str) -> None:
    """A plain line of results on stdout."""
    out.print(text, markup=False)


def complain(text: str) -> None:
    """A plain line on stderr (an interruption, a failed trial)."""
    err.print(text, markup=False)
