"""A trial's CPU share: torch's threads and the cores it runs on, never a core another trial holds."""

import os

import pytest
import torch

from softarm.study import share
from softarm.study.share import _lock, cpu_share


@pytest.fixture(autouse=True)
def own_locks(tmp_path, monkeypatch):
    """Lock files of these tests' own, so a study running on this machine does not hold their cores."""
    monkeypatch.setattr(share, "LOCKS", tmp_path / "cores")


@pytest.mark.skipif(len(os.sched_getaffinity(0)) < 2, reason="needs two cores")
def test_a_trial_is_pinned_to_a_core_no_other_trial_holds():
    allowed = sorted(os.sched_getaffinity(0))
    threads = torch.get_num_threads()
    other = _lock(share.LOCKS / f"{allowed[0]}.lock")  # as another trial on this machine holds it
    try:
        with cpu_share(1) as cores:
            assert cores == [allowed[1]] and os.sched_getaffinity(0) == {allowed[1]}
            assert torch.get_num_threads() == 1
    finally:
        other.close()
    assert sorted(os.sched_getaffinity(0)) == allowed and torch.get_num_threads() == threads


def test_a_trial_runs_unpinned_when_every_core_is_held():
    allowed = sorted(os.sched_getaffinity(0))
    others = [_lock(share.LOCKS / f"{core}.lock") for core in allowed]
    try:
        with cpu_share(1) as cores:
            assert cores == allowed and sorted(os.sched_getaffinity(0)) == allowed
    finally:
        for lock in others:
            lock.close()
