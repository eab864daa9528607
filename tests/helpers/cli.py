"""Running the installed `softarm` command in a subprocess, as a user would."""

import os
import subprocess
import sys
from pathlib import Path

SOFTARM = str(Path(sys.executable).with_name("softarm"))
RERUN = str(Path(sys.executable).with_name("rerun"))  # rerun-sdk's command line, beside the interpreter


def softarm(*args: str, cwd: Path, timeout: float = 120, **kwargs) -> subprocess.CompletedProcess:
    env = {**os.environ, "COLUMNS": "200"}
    return subprocess.run([SOFTARM, *args], cwd=cwd, capture_output=True, text=True, timeout=timeout, env=env,
                          **kwargs)


def assert_one_line_error(result: subprocess.CompletedProcess, *words: str) -> str:
    """Exit code != 0, no traceback, one line on stderr that names the problem."""
    message = result.stderr.strip()
    assert result.returncode != 0, result.stdout + result.stderr
    assert "Traceback" not in result.stderr
    assert len(message.splitlines()) == 1, message
    for word in words:
        assert word in message, message
    return message


def files_under(folder: Path) -> list[Path]:
    return sorted(p for p in folder.rglob("*") if p.is_file() and p.suffix in (".mcap", ".part"))
