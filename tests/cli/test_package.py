"""The installed package as a user meets it: a light `import softarm`, a CLI under its own name, help that
shows every default and shows flags as flags."""

import subprocess
import sys

import pytest

from tests.helpers.cli import softarm


def python(code: str, cwd) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code], cwd=cwd, capture_output=True, text=True, timeout=120)


def test_importing_softarm_and_its_public_api_loads_neither_taichi_nor_torch(tmp_path):
    code = ("import softarm, sys; [getattr(softarm, name) for name in softarm.__all__]; "
            "heavy = [m for m in ('taichi', 'torch', 'rerun', 'PIL') if m in sys.modules]; print(heavy)")
    done = python(code, tmp_path)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


def test_public_api_names_the_whole_pipeline():
    import softarm

    assert {"load_config", "simulate", "read_recording", "train", "replay"} <= set(softarm.__all__)
    with pytest.raises(AttributeError):
        _ = softarm.no_such_function


def test_the_cli_installs_as_softarm_cli_and_no_package_called_cli(tmp_path):
    assert python("import softarm_cli.main", tmp_path).returncode == 0
    done = python("import cli", tmp_path)
    assert done.returncode != 0 and "No module named 'cli'" in done.stderr


@pytest.mark.parametrize("command, shown", [
    ("sim", ["--duration <float>", "[default: 100]", "[default: 0.004]", "[default: 30]", "[default: cpu]"]),
    ("train", ["[default: 20]", "[default: 150]", "[default: 6]", "[default: 16]",
               "--include-current / --previous-only"]),
    ("replay", ["CHECKPOINT <path>", "RECORDING <path>", "--blind START:END", "Example: softarm replay"]),
])
def test_help_shows_every_default_and_flags_without_a_value(tmp_path, command, shown):
    done = softarm(command, "--help", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    for text in shown:
        assert text in done.stdout, done.stdout
    assert "<bool>" not in done.stdout
    for line in done.stdout.splitlines():
        if line.strip().startswith(("--force", "--quiet", "-q,", "--spawn", "--resume")):
            assert "<" not in line.split()[1 if line.strip().startswith("-q,") else 0], line
