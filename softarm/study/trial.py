"""One trial, as a Ray task runs it: train on the shared corpus with the trial's settings, score on the suite.

Everything it reads and writes is a path under the study's folder: on a cluster that folder must be one
that every node sees (a shared file system), since no data travels with the task.
"""

import socket
import time
import traceback
from dataclasses import dataclass
from typing import Any, Optional

from softarm.config import load_config
from softarm.errors import SoftarmError
from softarm.interrupt import stop_on_signal
from softarm.study.ledger import TrialRecord
from softarm.study.plan import Trial
from softarm.study.share import cpu_share

TRIAL_CPUS = 1  # a trial's share: Ray reserves this many CPUs for it, torch runs this many threads


@dataclass(frozen=True)
class TrialJob:
    study: str
    trial: Trial
    key: str
    scale: str
    overrides: dict[str, Any]   # the scale's, then the trial's own
    corpus: str                 # absolute paths, the same on every node
    suite: str
    checkpoint: str
    device: str = "cpu"         # where it trains and scores (softarm.model.device); a GPU task's is "cuda"


def run_trial(job: TrialJob) -> TrialRecord:
    """The trial's record: `ok` with its suite scores, `failed` with the error's message (training or scoring
    went wrong), or `interrupted` when a stop request (Ctrl-C, a cancelled task) ended training."""
    from softarm.learn.training import train
    from softarm.suite.evaluate import evaluate

    start = time.perf_counter()
    with cpu_share(TRIAL_CPUS), stop_on_signal() as caught:
        try:
            config = load_config(overrides={**job.overrides, "train.device": job.device})
            trained = train([job.corpus], config, out=job.checkpoint, force=True, stop=lambda: bool(caught))
            if not trained.complete or caught:
                return trial_record(job, "interrupted", time.perf_counter() - start)
            evaluation = evaluate(job.checkpoint, job.suite, device=job.device)
        except SoftarmError as e:
            return trial_record(job, "failed", time.perf_counter() - start, error=one_line(str(e)))
        except Exception as e:  # a trial that breaks must not take the study down: its record says why
            return trial_record(job, "failed", time.perf_counter() - start, error=one_line(f"{type(e).__name__}: {e}"),
                                trace=traceback.format_exc())
    scores = {k: v for k, v in evaluation.items() if k not in ("suite", "checkpoint", "probes")}
    return trial_record(job, "ok", time.perf_counter() - start, scores=scores)


def trial_record(job: TrialJob, status: str, wall_seconds: float, error: str = "",
                 scores: Optional[dict[str, Any]] = None, trace: Optional[str] = None) -> TrialRecord:
    """The ledger's line for the job, with this host's name."""
    t = job.trial
    return TrialRecord(job.study, t.name, job.key, t.group, t.value, t.overrides, job.scale, status, error,
                       scores or {}, wall_seconds, socket.gethostname(), job.checkpoint, trace)


def one_line(message: str) -> str:
    return " ".join(message.split())
