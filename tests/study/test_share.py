"""A trial's CPU share: torch's threads and the cores it runs on, never a core another trial holds."""

import os

import pytest
import torch

from softarm.study.share import LOCKS, _lock, cpu_share


@pytest.mark.skipif(len(os.sched_getaffinity(0)) < 2, reason="needs two cores")
def test_a_trial_is_pinned_to_a_core_no_other_trial_holds():
    allowed = sorted(os.sched_getaffinity(0))
    threads = torch.get_num_threads()
    other = _lock(LOCKS / f"{allowed[0]}.lock")  # as another trial on this machine holds it
    try:
        with cpu_share(1) as cores:
            assert cores == [allowed[1]] and os.sched_getaffinity(0) == {allowed[1]}
            assert torch.get_num_threads() == 1
    finally:
        other.close()
    assert sorted(os.sched_getaffinity(0)) == allowed and torch.get_num_threads() == threads


def test_a_trial_runs_unpinned_when_every_core_is_held():
    allowed = sorted(os.sched_getaffinity(0))
    others = [_lock(LOCKS / f"{core}.lock") for core in allowed]
    try:
        with cpu_share(1) as cores:
            assert cores == allowed and sorted(os.sched_getaffinity(0)) == allowed
    finally:
        for lock in others:
            lock.close()
