"""The examples users copy run, at a small size, as the docstrings at their tops say (so that they never rot), and
say what they did."""

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SMALL = {
    "python_api.py": ["--seconds", "6", "--quick"],
    "gymnasium_ppo.py": ["--arms", "8", "--steps", "1024", "--episodes", "8"],
    "import_robot_log.py": ["--seconds", "6"],
    "custom_config.py": ["--seconds", "2", "--arms", "2"],
}
SAYS = {"python_api.py": "streamed", "gymnasium_ppo.py": "PPO after 1024 steps", "import_robot_log.py": "imported",
        "custom_config.py": "push, payload, obstacle"}


def test_every_example_is_run_here():
    assert sorted(p.name for p in (ROOT / "examples").glob("*.py")) == sorted(SMALL)


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(SMALL))
def test_the_example_runs_at_a_small_size(name, tmp_path):
    folder = [] if name == "gymnasium_ppo.py" else ["--folder", str(tmp_path / "out")]
    assert f"python examples/{name}" in (ROOT / "examples" / name).read_text()  # its docstring says how to run it
    result = subprocess.run([sys.executable, str(ROOT / "examples" / name), *SMALL[name], *folder], cwd=tmp_path,
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr[-2000:]
    assert SAYS[name] in result.stdout, result.stdout
