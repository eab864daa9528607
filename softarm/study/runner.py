"""`softarm study` as one call: check the study and its folder, build the shared data, run the trials not yet
recorded as Ray tasks, and rewrite the results as each one finishes.

Ray starts here on this machine with as many CPUs as this process may use, or joins a running cluster
(`address`); a Ray session already started by the caller (a notebook, the tests) is used as it is. Each
trial reserves TRIAL_CPUS of them; on a cluster the study's folder must be a path every node shares.
"""

import json
import logging
import os
from contextlib import contextmanager
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Iterator, Optional, Union

from softarm.config.keys import DEVICES
from softarm.errors import ConfigError, OutputError, SoftarmError
from softarm.files import check_outputs, claimed, made_folders
from softarm.interrupt import stop_on_signal
from softarm.study.builtin import load_study
from softarm.study.ledger import LEDGER, TrialRecord, append_record, latest, read_records, trial_key
from softarm.study.plan import Study, check_overrides
from softarm.study.prepare import StageProgress, prepare
from softarm.study.report import output_paths, write_results
from softarm.study.scale import FULL, Scale
from softarm.study.trial import TRIAL_CPUS, TrialJob, one_line, run_trial, trial_record

PathLike = Union[str, Path]


@dataclass(frozen=True)
class StudyResult:
    study: Study
    records: list[TrialRecord]   # the latest of every planned trial, in order ("pending": never finished)
    ran: int                     # trials run by this call (the others were recorded ok before)
    complete: bool               # False when Ctrl-C (or SIGTERM) stopped it
    results: Path                # results.json
    markdown: Path               # results.md
    png: Path


def run_study(study: Union[PathLike, Study], out: PathLike, scale: Scale = FULL, address: Optional[str] = None,
              trials: Optional[int] = None, force: bool = False,
              progress: Optional[StageProgress] = None, device: str = "auto") -> StudyResult:
    """Run a study (a built-in's name, a TOML file or a Study) into the folder `out`; see softarm.study.

    `scale` is FULL or QUICK (softarm.study.scale); `trials` keeps the first N trials of the plan; `force`
    forgets the trials recorded in `out` and runs every one again. `progress(stage, done, total)` is
    called with stage "corpus", "suite" (building them) and "trials". `device` (auto | cpu | cuda) is where
    the trials train and score: on "cuda", or on "auto" where the Ray cluster has GPUs, each trial asks Ray
    for one GPU.
    """
    if device not in DEVICES:
        raise ConfigError(f"--device {device!r}: give one of {list(DEVICES)}")
    plan = study if isinstance(study, Study) else load_study(study)
    planned = plan.quick_trials() if scale.quick_trials else plan.trials
    if trials is not None:
        if trials < 1:
            raise ConfigError(f"--trials {trials}: run at least 1 trial")
        planned = planned[:trials]
    for trial in planned:
        check_overrides({**scale.train, **trial.overrides}, f"study {plan.name}, trial {trial.name}")
    folder = Path(out).resolve()
    check_folder(folder, plan, scale, force, inputs=[] if isinstance(study, Study) else [Path(study)])
    with made_folders([folder / LEDGER]), claimed([folder / LEDGER]):
        if force:
            (folder / LEDGER).unlink(missing_ok=True)
        return run_planned(plan, planned, folder, scale, address, force, progress, device)


def run_planned(plan: Study, planned: list, folder: Path, scale: Scale, address: Optional[str], force: bool,
                progress: Optional[StageProgress], device: str = "auto") -> StudyResult:
    """The trials of a checked plan in a held folder: the shared data first, then every trial not yet recorded."""
    keys = {t.name: trial_key(t, scale) for t in planned}
    recorded = latest(read_records(folder))
    rows = {t.name: recorded.get((t.name, keys[t.name])) or TrialRecord(plan.name, t.name, keys[t.name], t.group,
                                                                        t.value, t.overrides, scale.name, "pending")
            for t in planned}
    report = lambda: write_results(folder, plan, scale.name, list(rows.values()))  # noqa: E731
    paths = report()
    notify = progress or (lambda *_: None)
    data = prepare(folder, scale, force, notify)
    if data is None:
        return StudyResult(plan, list(rows.values()), 0, False, *paths)
    corpus, suite = data
    jobs = [TrialJob(plan.name, t, keys[t.name], scale.name, {**scale.train, **t.overrides}, str(corpus), str(suite),
                     str(folder / "trials" / f"{t.name}.pt")) for t in planned if rows[t.name].status != "ok"]
    ran, interrupted = 0, False
    if jobs:
        (folder / "trials").mkdir(exist_ok=True)
        notify("trials", len(planned) - len(jobs), len(planned))
        for record in run_jobs(jobs, address, device):
            if record.status == "interrupted":
                interrupted = True
                continue
            append_record(folder, record)
            rows[record.name] = record
            report()
            ran += 1
            notify("trials", len(planned) - len(jobs) + ran, len(planned))
    return StudyResult(plan, list(rows.values()), ran, not interrupted, *paths)


def check_folder(folder: Path, plan: Study, scale: Scale, force: bool, inputs: list[Path]) -> None:
    """Refuse a folder that holds another study, or this one at another scale, unless `force` (which then
    forgets the trials recorded there), and outputs that would replace an input (the study's file)."""
    paths = output_paths(folder, plan)
    check_outputs([*paths, folder / LEDGER], force=True, inputs=inputs)  # folders, permissions, inputs
    json_path = paths[0]
    if json_path.exists() and not force:
        try:
            held = json.loads(json_path.read_text())
            study, held_scale = held.get("study"), held.get("scale")
        except (OSError, ValueError, AttributeError):
            raise OutputError(f"{json_path} is not a study's results: give another --out, or pass --force to run "
                              f"the study there afresh") from None
        if (study, held_scale) != (plan.name, scale.name):
            raise OutputError(f"{folder} holds the {held_scale} study {study!r}; give another "
                              f"--out, or pass --force to run the {scale.name} study {plan.name!r} there afresh")


def run_jobs(jobs: list[TrialJob], address: Optional[str], device: str = "auto") -> Iterator[TrialRecord]:
    """Every job's record as it finishes, each job a Ray task (with one GPU where the trials run on one);
    Ctrl-C cancels the tasks not finished and yields each of them as interrupted."""
    with stop_on_signal() as caught, ray_session(address) as ray:
        on = trial_device(ray, device)
        task = ray.remote(num_cpus=TRIAL_CPUS, num_gpus=1 if on == "cuda" else 0, max_retries=0)(run_trial)
        pending = {task.remote(replace(job, device=on)): job for job in jobs}
        while pending and not caught:
            ready, _ = ray.wait(list(pending), num_returns=1, timeout=0.2)
            for ref in ready:
                yield _result(ray, ref, pending.pop(ref))
        for ref, job in pending.items():
            ray.cancel(ref)
            yield trial_record(job, "interrupted", 0.0)


def _result(ray: Any, ref: Any, job: TrialJob) -> TrialRecord:
    """The task's record, or a failed one when the task itself failed (its worker died, say)."""
    try:
        return ray.get(ref)
    except ray.exceptions.RayError as e:
        return trial_record(job, "failed", 0.0, error=one_line(f"{type(e).__name__}: {e}"))


def trial_device(ray: Any, device: str) -> str:
    """Where the trials run: "cuda" when asked or, for "auto", when the Ray cluster has a GPU; else "cpu"."""
    gpus = ray.cluster_resources().get("GPU", 0)
    if device == "cuda" and gpus < 1:
        raise SoftarmError("--device cuda: the Ray cluster has no GPU; use --device cpu or auto")
    return "cuda" if device == "cuda" or (device == "auto" and gpus >= 1) else "cpu"


@contextmanager
def ray_session(address: Optional[str]) -> Iterator[Any]:
    """The `ray` module with a session open: the caller's, a new local one or the cluster at `address`."""
    import ray

    if ray.is_initialized():
        yield ray
        return
    options: dict[str, Any] = {"logging_level": logging.ERROR, "log_to_driver": False}
    try:
        if address:
            ray.init(address=address, **options)
        else:
            ray.init(num_cpus=len(os.sched_getaffinity(0)), include_dashboard=False, **options)
    except (ConnectionError, RuntimeError, ValueError) as e:
        raise SoftarmError(f"cannot start Ray{f' on the cluster at {address}' if address else ''}: "
                           f"{one_line(str(e))}") from None
    try:
        yield ray
    finally:
        ray.shutdown()
