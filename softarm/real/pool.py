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
    """A pool whose workers know `camera` and `decoder`: processes where the platform forks, threads elsewhere.
    Left normally, it waits for its tasks; left by an exception (a stop request, an error), it cancels what is
    queued and ends its worker processes at once, so that nothing waits on a worker that will not answer."""
    global _WORKER
    _WORKER = (camera, decoder)
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
    if sys.platform == "linux" and cores > 1:
        pool: Executor = ProcessPoolExecutor(cores, mp_context=multiprocessing.get_context("fork"),
                                             initializer=_quiet_worker)
    else:
        pool = ThreadPoolExecutor(cores)
    try:
        yield pool
    except BaseException:
        _abandon(pool)
        raise
    else:
        pool.shutdown(wait=True)
    finally:
        _WORKER = (None, lambda data: None)


def _abandon(pool: Executor) -> None:
    """Cancel the queued tasks and end the worker processes now (a thread pool's threads finish their task)."""
    workers = list(getattr(pool, "_processes", None) or {})  # ProcessPoolExecutor keeps its workers by pid
    for pid in workers:
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    pool.shutdown(wait=True, cancel_futures=True)  # its manager thread sees the workers gone and ends at once


def _quiet_worker() -> None:
    """Stop requests reach the whole process group: the importing process answers them and ends its workers
    itself, so a worker ignores them."""
    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(sig, signal.SIG_IGN)


def segment_task(frames: Sequence[tuple[int, bytes]]) -> list[tuple[float, bool, Any, tuple[int, int]]]:
    """Each frame's (stamp, header?, mask, camera size), from its log time and message bytes."""
    camera, decode = _WORKER
    return [camera.mask_of(log_time, decode(data)) for log_time, data in frames]
