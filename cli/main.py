"""The `softarm` command line: parse options, call the softarm library, print. No logic of its own."""

import sys
from pathlib import Path
from typing import Annotated, Callable, Optional, TypeVar

import typer
from rich.console import Console

from cli.progress import LazyProgress
from softarm import __version__
from softarm.config import DEFAULT_CONFIG_TEXT, load_config
from softarm.errors import SoftarmError
from softarm.runtime import ARCHS

app = typer.Typer(help="softarm: a simulated soft arm that learns to picture its own body from its stretch sensors.",
                  no_args_is_help=True, add_completion=False, pretty_exceptions_enable=False,
                  context_settings={"help_option_names": ["-h", "--help"]})
err = Console(stderr=True, highlight=False, soft_wrap=True)
out = Console(highlight=False, soft_wrap=True)
T = TypeVar("T")


def run_or_exit(action: Callable[[], T]) -> T:
    """Run a library call; a user-caused error becomes one line on stderr and exit code 1."""
    try:
        return action()
    except SoftarmError as e:
        err.print(f"error: {e}", markup=False)
        raise typer.Exit(1) from None
    except OSError as e:
        err.print(f"error: {e.strerror or e}" + (f": {e.filename}" if e.filename else ""), markup=False)
        raise typer.Exit(1) from None


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


@app.command()
def sim(
    config: Annotated[Optional[Path], typer.Option("--config", "-c", help="TOML config; omitted keys keep their defaults (see `softarm config`).")] = None,
    duration: Annotated[Optional[float], typer.Option(help="Seconds to simulate [default: 100].")] = None,
    amplitude: Annotated[Optional[float], typer.Option(help="Excitation amplitude A in metres [default: 0.004].")] = None,
    substeps: Annotated[Optional[int], typer.Option(help="Integration substeps per 0.01 s frame [default: 30].")] = None,
    arms: Annotated[Optional[int], typer.Option(help="Arms simulated together; arm i uses seed + i and gets its own file [default: 1].")] = None,
    seed: Annotated[Optional[int], typer.Option(help="Seed of arm 0; seed 0 is the paper's run [default: 0].")] = None,
    arch: Annotated[str, typer.Option(help=f"Taichi backend: {' | '.join(ARCHS)}.")] = "cpu",
    out_path: Annotated[Optional[Path], typer.Option("--out", "-o", help="Output .mcap [default: recordings/seed<SEED>.mcap]; a batch writes <stem>_arm<i>.mcap.")] = None,
    force: Annotated[bool, typer.Option("--force", help="Overwrite existing output files.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar and no summary.")] = False,
) -> None:
    """Simulate the arm and record camera frames, stretch sensors, node positions and excitation as MCAP.

    Example: softarm sim --duration 10 --arms 4 --out recordings/short.mcap
    """
    from softarm.sim import simulate  # imports Taichi: only for the commands that need it

    overrides = {"run.duration": duration, "excitation.amplitude": amplitude, "integration.substeps": substeps,
                 "run.arms": arms, "run.seed": seed}
    cfg = run_or_exit(lambda: load_config(config, overrides))
    with LazyProgress(err, "simulating", cfg.n_frames, "frames", scale=cfg.run.arms, quiet=quiet) as bar:
        result = run_or_exit(lambda: simulate(cfg, out_path, force=force, arch=arch, progress=bar.update))
    files = ", ".join(str(p) for p in result.paths)
    size = result.bytes / 1e6
    if not result.complete:
        err.print(f"interrupted: kept {result.frames} frames per arm in {files} ({size:.1f} MB, complete = false)",
                  markup=False)
        raise typer.Exit(130)
    if not quiet:
        out.print(f"wrote {result.frames} frames x {len(result.paths)} arm(s) to {files} ({size:.1f} MB) in "
                  f"{result.wall_seconds:.1f} s: {result.real_time_factor:.0f}x real time", markup=False)


if __name__ == "__main__":
    sys.exit(app())
