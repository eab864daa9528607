"""Stop requests where Python would lose them: inside a finalizer, which drops what it raises, and while Typer
parses, which turns the KeyboardInterrupt into a silent exit code 130; and where raising them would abort Python:
inside a library's code, which C++ may have called. Each case runs in its own interpreter (the handlers are the
process's), and the finalizer or the library receives the request for certain: it signals itself and then runs
bytecode, where Python calls the handler."""

import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import Optional

import pytest

FINALIZED = """
    import os, signal, sys, time
    from softarm_cli.stopping import interrupt_as_ctrl_c
    from softarm.interrupt import stop_on_signal

    class Finalized:
        def __del__(self):
            os.kill(os.getpid(), signal.SIGINT)
            for _ in range(1000):  # the handler runs here, inside the finalizer
                pass

    def wait() -> None:
        print("the finalizer returned", flush=True)
        end = time.monotonic() + 10
        while time.monotonic() < end:
            time.sleep(0.001)
        print("deaf: still running 10 s after the request", flush=True)

    interrupt_as_ctrl_c()
"""


LIBRARY = """
    import dataclasses, functools, os, signal

    def work(then=None):
        os.kill(os.getpid(), signal.SIGINT)
        total = 0
        for i in range(100000):  # the handler runs here, inside the library
            total += i
        print("the library ran to its end", flush=True)
        return then() if then else total

    @dataclasses.dataclass
    class Made:  # its __init__ is made at run time: no file of the library's holds it
        request: object = dataclasses.field(default_factory=functools.partial(os.kill, os.getpid(), signal.SIGINT))

    def make():
        made = Made()  # the handler runs in Made.__init__, after the request
        print("the library ran to its end", flush=True)
        return made
"""


def run_python(code: str, library: Optional[Path] = None) -> subprocess.CompletedProcess:
    """`code` run by a new interpreter; `library`, a folder named site-packages, on its path as installed packages
    are."""
    path = [str(library or ""), os.environ.get("PYTHONPATH")]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, path))}
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, timeout=60,
                          env=env)


def installed_library(tmp_path: Path) -> Path:
    """A folder of installed packages holding `slowlib`, whose `work` requests a stop and then runs on."""
    folder = tmp_path / "site-packages"
    folder.mkdir()
    (folder / "slowlib.py").write_text(textwrap.dedent(LIBRARY))
    return folder


def test_a_request_a_finalizer_swallowed_comes_again_outside_it():
    result = run_python(FINALIZED + """
    try:
        Finalized()
        wait()
    except KeyboardInterrupt:
        print("interrupted", flush=True)
    """)
    assert result.stdout.splitlines() == ["the finalizer returned", "interrupted"], result.stdout + result.stderr
    assert result.stderr == ""  # not Python's "Exception ignored in ..." traceback


def test_a_second_request_a_finalizer_swallowed_still_escalates():
    result = run_python(FINALIZED + """
    from softarm.interrupt import Escalated
    with stop_on_signal() as caught:
        os.kill(os.getpid(), signal.SIGTERM)  # the first request: a flag the job checks
        try:
            Finalized()  # the second, inside a finalizer
            wait()
        except Escalated:
            print("escalated after", len(caught), "requests", flush=True)
    """)
    assert result.stdout.splitlines() == ["the finalizer returned", "escalated after 3 requests"], \
        result.stdout + result.stderr
    assert result.stderr == ""


def test_a_request_code_swallowed_before_a_job_started_stops_the_job_at_once():
    """Code that catches the KeyboardInterrupt (a C extension's initialisation turns it into an ImportError) leaves
    the command running, its handlers set to ignore further requests: the job that starts next starts stopped."""
    result = run_python(FINALIZED + """
    try:
        os.kill(os.getpid(), signal.SIGINT)
        for _ in range(1000):  # the handler runs here
            pass
    except KeyboardInterrupt:
        pass  # swallowed
    os.kill(os.getpid(), signal.SIGINT)  # a second request: ignored while the first is honoured
    with stop_on_signal() as caught:
        print("the job starts with", caught, flush=True)
    """)
    assert result.stdout.splitlines() == [f"the job starts with [{int(signal.SIGINT)}]"], result.stdout + result.stderr


def test_other_errors_in_finalizers_are_still_reported():
    result = run_python(FINALIZED + """
    class Broken:
        def __del__(self):
            raise ValueError("a finalizer's own bug")
    Broken()
    print("went on", flush=True)
    """)
    assert result.stdout.splitlines() == ["went on"]
    assert "Exception ignored" in result.stderr and "a finalizer's own bug" in result.stderr


def test_a_request_while_the_command_line_parses_says_interrupted():
    """Typer turns a KeyboardInterrupt outside the command's own call into exit code 130 and says nothing."""
    result = run_python("""
    import sys
    import softarm_cli.main as cli

    def interrupted(*_, **__):
        raise KeyboardInterrupt
    cli.out.print = interrupted  # `softarm config` prints the defaults through it
    sys.argv = ["softarm", "config"]
    sys.exit(cli.main())
    """)
    assert (result.returncode, result.stderr) == (130, "interrupted\n"), result.stderr


@pytest.mark.parametrize("call", ["work()", "make()"])
def test_a_request_inside_a_library_is_raised_when_the_library_returns(call, tmp_path):
    """Raised inside a library's Python, which torch's or Taichi's C++ may have called, it would abort Python
    ("terminate called after throwing an instance of 'pybind11::error_already_set'"): it waits for the caller. So it
    does where it lands in code the library made at run time (`make()`: a dataclass's `__init__`)."""
    result = run_python(FINALIZED + f"""
    import slowlib
    try:
        slowlib.{call}
        print("the caller's next line ran", flush=True)
    except KeyboardInterrupt:
        print("interrupted", flush=True)
    """, installed_library(tmp_path))
    assert result.stdout.splitlines() == ["the library ran to its end", "interrupted"], result.stdout + result.stderr
    assert result.stderr == ""


def test_a_request_inside_a_library_is_raised_when_it_calls_softarm(tmp_path):
    """A library that calls back into softarm's code (Typer calling the command, a trainer the environment) does not
    keep the request from it until the library returns."""
    result = run_python(FINALIZED + """
    import slowlib
    from softarm.config import load_config as callback  # any function of softarm's
    try:
        slowlib.work(then=callback)
        print("the callback returned", flush=True)
    except KeyboardInterrupt:
        print("interrupted", flush=True)
    """, installed_library(tmp_path))
    assert result.stdout.splitlines() == ["the library ran to its end", "interrupted"], result.stdout + result.stderr


def test_a_second_request_inside_a_library_escalates_when_the_library_returns(tmp_path):
    result = run_python(FINALIZED + """
    import slowlib
    from softarm.interrupt import Escalated
    with stop_on_signal() as caught:
        os.kill(os.getpid(), signal.SIGTERM)  # the first request: a flag the job checks
        try:
            slowlib.work()  # the second, inside the library
            print("the job's next line ran", flush=True)
        except Escalated:
            print("escalated after", len(caught), "requests", flush=True)
    import sys
    print("tracing", sys.gettrace(), flush=True)
    """, installed_library(tmp_path))
    assert result.stdout.splitlines() == ["the library ran to its end", "escalated after 2 requests", "tracing None"], \
        result.stdout + result.stderr
    assert result.stderr == ""
