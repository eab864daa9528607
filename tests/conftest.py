import pytest

from softarm.runtime import init_taichi


@pytest.fixture(scope="session", autouse=True)
def taichi_on_cpu():
    """Taichi starts once per test process, on the CPU with float64, as the CLI would start it."""
    init_taichi("cpu")
