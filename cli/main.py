"""The `softarm` command line: one module per command group parses options, calls the softarm library and
prints; this one gathers them under one app."""

import sys
from typing import Annotated, Optional

import typer
from softarm_cli.console import err, interruption_said, out
from softarm_cli.control import babble
from softarm_cli.demo import demo
from softarm_cli.imagination import evaluate, replay
from softarm_cli.real import import_log, robot_log
from softarm_cli.recording import corpus, sim, suite
from softarm_cli.stopping import ignore_requests, interrupt_as_ctrl_c
from softarm_cli.study import study
from softarm_cli.training import adapt, train

from softarm import __version__
from softarm.config import DEFAULT_CONFIG_TEXT

# Plain help (no rich markup): rich would read every "[default: ...]" as a markup tag and drop it,
# and would show flags as if they took a <bool> value.
app = typer.Typer(help="softarm: a simulated soft arm that learns to picture its own body from its stretch sensors.",
                  no_args_is_help=True, add_completion=False, pretty_exceptions_enable=False, rich_markup_mode=None,
                  context_settings={"help_option_names": ["-h", "--help"], "max_content_width": 120})


def version_callback(value: bool) -> None:
    if value:
        out.print(f"softarm {__version__}")
        raise typer.Exit()


@app.callback()
def root(version: Annotated[Optional[bool], typer.Option("--version", callback=version_callback, is_eager=True,
                                                          help="Print the version and exit.")] = None) -> None:
    """softarm: simulate a soft octopus arm, record it, learn to imagine it from its stretch sensors."""


@app.command()
def config() -> None:
    """Print the documented default config (TOML); save it, edit it, pass it to --config.

    Example: softarm config > my_arm.toml
    """
    out.print(DEFAULT_CONFIG_TEXT, markup=False, end="")


for command in (sim, train, adapt, replay, corpus, suite, evaluate, demo, study, babble):
    app.command()(command)
app.command("import")(import_log)
app.command("robot-log")(robot_log)


def main() -> int:
    """The `softarm` console script: the app, with a command line it cannot parse (an unknown option, a value of the
    wrong kind, a missing argument) refused in one line and exit code 2, as every other mistake is in one line;
    and SIGTERM and SIGHUP stopping a command as Ctrl-C does (`softarm_cli.stopping`)."""
    interrupt_as_ctrl_c()
    command = typer.main.get_command(app)
    try:
        code = int(command.main(args=sys.argv[1:], prog_name="softarm", standalone_mode=False) or 0)
    except typer.TyperException as e:  # click's usage errors, as Typer carries them
        if type(e).__name__ == "NoArgsIsHelpError":  # `softarm` alone, or a group without its command: the help
            out.print(e.format_message(), markup=False)
            return 0
        hint = f" (softarm {e.ctx.info_name} -h for help)" if getattr(e, "ctx", None) and e.ctx.parent else ""
        err.print(f"error: {e.format_message()}{hint}", markup=False)
        return getattr(e, "exit_code", 2)
    except typer.Abort:  # a stop request outside a library call (while a command parses), as older Typers say it
        code = 130
    finally:
        ignore_requests()
    if code == 130 and not interruption_said():  # newer Typers turn that request into exit code 130 silently
        err.print("interrupted", markup=False)
    return code


if __name__ == "__main__":
    sys.exit(main())
