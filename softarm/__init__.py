"""softarm: a simulated soft arm that learns to picture its own body from its stretch sensors."""

import os

# Taichi prints a banner on import; softarm's output is its own (the CLI's --quiet must mean quiet).
os.environ.setdefault("ENABLE_TAICHI_HEADER_PRINT", "false")

__version__ = "0.1.0"
