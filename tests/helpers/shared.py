"""Costly test data made once per test run, not once in every pytest-xdist worker: the first worker to ask makes
it while the others wait (a file lock beside it), then all read it."""

import os
import shutil
from pathlib import Path
from typing import Callable

import pytest
from filelock import FileLock


def made_once(tmp_path_factory: pytest.TempPathFactory, name: str, make: Callable[[Path], None]) -> Path:
    """The folder `name` filled by `make(folder)` once in this run; every worker gets the same folder."""
    base = tmp_path_factory.getbasetemp()
    root = base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base  # the run's folder, above the workers'
    folder, made = root / name, root / f"{name}.made"
    with FileLock(str(root / f"{name}.lock")):
        if not made.exists():
            shutil.rmtree(folder, ignore_errors=True)  # a worker that failed halfway
            folder.mkdir()
            make(folder)
            made.touch()
    return folder
