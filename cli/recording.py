"""`softarm sim`, `softarm corpus` and `softarm suite`: simulate arms and record them."""

import json
from pathlib import Path
from typing import Annotated, Optional

import typer
from softarm_cli.console import err, out, run_or_exit, say, stop_interrupted
from softarm_cli.options import Arch, ConfigFile, D, Force, Quiet
from softarm_cli.progress import LazyProgress

from softarm.config import load_config
from softarm.corpus.build import DEFAULT_ARMS, DEFAULT_DURATION
from softarm.suite.families import SUITE_VERSION


def sim(
    config: ConfigFile = None,
    duration: Annotated[Optional[float], typer.Option(help=f"Seconds to simulate [default: {D.run.duration:g}].")] = None,
    amplitude: Annotated[Optional[float], typer.Option(help=f"Excitation amplitude A in metres [default: {D.excitation.amplitude:g}].")] = None,
    substeps: Annotated[Optional[int], typer.Option(help=f"Integration substeps per {D.integration.frame_dt:g} s frame [default: {D.integration.substeps}].")] = None,
    arms: Annotated[Optional[int], typer.Option(help=f"Arms simulated together; arm i uses seed + i and gets its own file [default: {D.run.arms}].")] = None,
    seed: Annotated[Optional[int], typer.Option(help=f"Seed of arm 0; seed 0 is the paper's run [default: {D.run.seed}].")] = None,
    arch: Arch = "cpu",
    out_path: Annotated[Optional[Path], typer.Option("--out", "-o", help="Output .mcap [default: recordings/seed<SEED>.mcap]; a batch writes <stem>_arm<i>.mcap.")] = None,
    force: Force = False,
    quiet: Quiet = False,
) -> None:
    """Simulate the arm and record camera frames, stretch sensors, node positions and excitation as MCAP.

    \b
    Example: softarm sim --duration 10 --arms 4 --out recordings/short.mcap
    """
    from softarm.sim.simulate import simulate  # imports Taichi: only for the commands that need it

    overrides = {"run.duration": duration, "excitation.amplitude": amplitude, "integration.substeps": substeps,
                 "run.arms": arms, "run.seed": seed}
    cfg = run_or_exit(lambda: load_config(config, overrides))
    with LazyProgress(err, "simulating", cfg.n_frames, "frames", scale=cfg.run.arms, quiet=quiet, log=out) as bar:
        result = run_or_exit(lambda: simulate(cfg, out_path, force=force, arch=arch, progress=bar.update,
                                              inputs=[config] if config else []))
    files = ", ".join(str(p) for p in result.paths)
    size = result.bytes / 1e6
    if not result.complete:
        stop_interrupted(f"interrupted: kept {result.frames} frames per arm in {files} ({size:.1f} MB, complete = false)")
    if not quiet:
        say(f"wrote {result.frames} frames x {len(result.paths)} arm(s) to {files} ({size:.1f} MB) in "
            f"{result.wall_seconds:.1f} s: {result.real_time_factor:.0f}x real time")


def corpus(
    folder: Annotated[Path, typer.Argument(metavar="DIR", help="Folder for the corpus's recordings and corpus.json.")],
    preset: Annotated[str, typer.Option(help="general: every kind of motion; paper: the paper's drive at many time offsets.")] = "general",
    arms: Annotated[int, typer.Option(help="Arms in all, spread over the preset's groups.")] = DEFAULT_ARMS,
    duration: Annotated[float, typer.Option(help="Seconds simulated per arm.")] = DEFAULT_DURATION,
    arch: Arch = "cpu",
    force: Force = False,
    quiet: Quiet = False,
) -> None:
    """Simulate a training corpus: many arms and kinds of motion, from seeds below the held-out suite's.

    \b
    Example: softarm corpus recordings/corpus && softarm train recordings/corpus --out general.pt
    """
    from softarm.corpus.build import write_corpus

    with LazyProgress(err, "corpus", 1, "arm-frames", quiet=quiet, log=out) as bar:
        manifest = run_or_exit(lambda: write_corpus(folder, preset=preset, arms=arms, duration=duration, force=force,
                                                    arch=arch, progress=bar.update))
    if manifest is None:
        stop_interrupted(f"interrupted: {folder} holds part of the corpus and no corpus.json; run the command again")
    if not quiet:
        written = json.loads(manifest.read_text())["arms"]
        say(f"wrote a {preset} corpus of {written} arm(s) x {duration:g} s to {folder}")


def suite(
    folder: Annotated[Path, typer.Argument(metavar="DIR", help="Folder for the suite's recordings and suite.json.")],
    arch: Arch = "cpu",
    force: Force = False,
    quiet: Quiet = False,
) -> None:
    """Write the held-out imagination suite: every family and level from its reserved seeds (no corpus uses them).

    \b
    Example: softarm suite recordings/suite
    """
    from softarm.suite.build import write_suite

    with LazyProgress(err, "suite", 1, "arm-frames", quiet=quiet, log=out) as bar:
        manifest = run_or_exit(lambda: write_suite(folder, force=force, arch=arch, progress=bar.update))
    if manifest is None:
        stop_interrupted(f"interrupted: {folder} holds part of the suite and no suite.json; run the command again")
    if not quiet:
        say(f"wrote {SUITE_VERSION} to {folder} ({manifest.name} and its recordings)")
