"""The `softarm` command line: one module per command group parses options, calls the softarm library and
prints; this one gathers them under one app."""

import sys
from typing import Annotated, Optional

import typer
from softarm_cli.console import out
from softarm_cli.control import babble
from softarm_cli.demo import demo
from softarm_cli.imagination import evaluate, replay
from softarm_cli.real import import_log, robot_log
from softarm_cli.recording import corpus, sim, suite
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
def main(version: Annotated[Optional[bool], typer.Option("--version", callback=version_callback, is_eager=True,
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

if __name__ == "__main__":
    sys.exit(app())
