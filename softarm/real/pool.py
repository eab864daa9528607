"""Camera frames segmented in worker processes, one per core: decoding a JPEG holds Python's GIL for much of its
time, so threads gain little on it (1.4x on two cores, against nearly 2x for processes).

The workers are forked from the importing process after its first look, so they inherit the camera reader (its
rule, threshold and background) and the camera topic's decoder instead of being sent them.
"""

import multiprocessing
import os
import signal
import sys
from concurrent.futures import Executor, ProcessPoolExecutor, ThreadPoolExecutor
from contextlib import contextmanager
from typing import Any, Callable, Iterator, Sequence

_WORKER: tuple[Any, Callable[[bytes], Any]] = (None, lambda data: None)  # (CameraReader, decoder), in a worker


@contextmanager
def segmenting_pool(camera: Any, decoder: Callable[[bytes], Any]) -> Iterator[Executor]:
    """A pool whose workers know `camera` and `decoder`: processes where the platform forks, threads elsewhere."""
    global _WORKER
    _WORKER = (camera, decoder)
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
    if sys.platform == "linux" and cores > 1:
        pool: Executor = ProcessPoolExecutor(cores, mp_context=multiprocessing.get_context("fork"),
                                             initializer=_quiet_worker)
    else:
        pool = ThreadPoolExecutor(cores)
    try:
        with pool:
            yield pool
    finally:
        _WORKER = (None, lambda data: None)


def _quiet_worker() -> None:
    """Ctrl-C reaches the whole process group: the importing process handles it; a worker just ends."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def segment_task(frames: Sequence[tuple[int, bytes]]) -> list[tuple[float, bool, Any, tuple[int, int]]]:
    """Each frame's (stamp, header?, mask, camera size), from its log time and message bytes."""
    camera, decode = _WORKER
    return [camera.mask_of(log_time, decode(data)) for log_time, data in frames]
