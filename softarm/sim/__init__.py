"""Simulation: Taichi kernels that step and photograph many arms at once, and the run loop that records them.

Taichi starts in `runtime.init_taichi`, called at the edge (the CLI or a public entry point), never
on import. A user picks the backend from `ARCHS`.
"""

ARCHS = ("cpu", "gpu", "auto")  # Taichi backends a user can ask for; runtime.init_taichi maps them
