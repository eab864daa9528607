"""Simulation: Taichi kernels that step and photograph many arms at once, and the run loop that records them.

Taichi starts in `runtime.init_taichi`, called at the edge (the CLI or a public entry point), never
on import. A user picks the backend from `ARCHS`.
"""

ARCHS = ("cpu", "gpu", "auto")  # Taichi backends a user can ask for; runtime.init_taichi maps them


def check_arch(arch: str) -> None:
    """Refuse an unknown backend before any work (a refused run creates no folder)."""
    from softarm.errors import SoftarmError

    if arch not in ARCHS:
        raise SoftarmError(f"--arch {arch!r} is not known: use one of {', '.join(ARCHS)}")
