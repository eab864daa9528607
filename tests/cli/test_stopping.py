"""Stop requests where Python would lose them: inside a finalizer, which drops what it raises, and while Typer
parses, which turns the KeyboardInterrupt into a silent exit code 130. Each case runs in its own interpreter (the
handlers are the process's), and the finalizer receives the request for certain: it signals itself and then runs
bytecode, where Python calls the handler."""

import signal
import subprocess
import sys
import textwrap

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


def run_python(code: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, timeout=60)


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
