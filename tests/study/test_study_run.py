"""Running a study through a real local Ray session: every trial's record and scores, a rerun that skips what
is done, a failing trial that leaves the others alone, and an interrupted study that resumes."""

import json
import logging
import os
import shutil
import signal
import time

import pytest

from softarm.config import load_config
from softarm.corpus.build import write_corpus
from softarm.errors import OutputError
from softarm.study.ledger import LEDGER
from softarm.study.plan import Study, Trial
from softarm.study.prepare import corpus_fits
from softarm.study.runner import run_study
from softarm.study.scale import Scale
from softarm.suite.families import SUITE_VERSION

# Seconds of training on 2 arms x 4 s of the paper's drive; scored on two 2 s recordings.
pytestmark = pytest.mark.slow  # each test runs the CLI, trains or compiles kernels: seconds


TINY = Scale("tiny", "paper", 2, 4.0, {"train.latent": 8, "train.lstm_hidden": 32, "train.batch_ae": 32,
                                       "train.max_steps_ae": 40, "train.max_steps_lstm": 60},
             first_recording_only=True)
FAMILIES = {"paper_amplitude": {}, "sensor_noise": {"noise": 2e-5}}


def trial(name: str, **overrides) -> Trial:
    return Trial(name, name, "", {k.replace("__", "."): v for k, v in overrides.items()})


def tiny_study(*trials: Trial) -> Study:
    return Study("tiny", "trial", "a test", trials, tuple(t.name for t in trials))


@pytest.fixture(scope="module")
def ray_session():
    """One local Ray session with two CPUs for every test here (it takes seconds to start)."""
    import ray

    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False, logging_level=logging.WARNING)
    yield ray
    ray.shutdown()


@pytest.fixture(scope="module")
def tiny_data(tmp_path_factory):
    """The tiny scale's corpus, and a two-family suite of two 2 s recordings per level (the real one takes 15 s)."""
    from softarm.sim.simulate import simulate

    folder = tmp_path_factory.mktemp("data")
    write_corpus(folder / "corpus", TINY.preset, TINY.arms, TINY.duration)
    suite = folder / "suite"
    for seed in (7, 8):
        simulate(load_config(overrides={"run.duration": 2.0, "run.seed": seed}), suite / f"s{seed}.mcap")
    levels = lambda sensing: {"level": {"overrides": {}, "sensing": sensing, "seeds": [7, 8],  # noqa: E731
                                        "recordings": ["s7.mcap", "s8.mcap"]}}
    families = {name: {"probes": name, "levels": levels(sensing)} for name, sensing in FAMILIES.items()}
    (suite / "suite.json").write_text(json.dumps({"suite": SUITE_VERSION, "families": families}))
    return folder


def study_folder(tiny_data, tmp_path, corpus: bool = True):
    folder = tmp_path / "study"
    shutil.copytree(tiny_data / "suite", folder / "suite")
    if corpus:
        shutil.copytree(tiny_data / "corpus", folder / "corpus")
    return folder


def ledger(folder) -> list[dict]:
    return [json.loads(line) for line in (folder / LEDGER).read_text().splitlines()]


def test_trials_run_as_ray_tasks_and_a_rerun_skips_them(ray_session, tiny_data, tmp_path):
    (tmp_path / "two.toml").write_text('name = "two"\nvariable = "sensors"\n[[trials]]\nname = "upper"\nvalue = 2\n'
                                       'overrides = { "sensing.pairs" = [[3, 27], [5, 29]] }\n'
                                       '[[trials]]\nname = "four"\nvalue = 4\n')
    folder = study_folder(tiny_data, tmp_path, corpus=False)  # the study builds its own corpus
    done = run_study(tmp_path / "two.toml", folder, TINY)
    assert done.complete and done.ran == 2 and corpus_fits(folder / "corpus", TINY)
    results = json.loads(done.results.read_text())
    assert results["study"] == "two" and results["scale"] == "tiny"
    assert [(t["name"], t["status"], t["value"]) for t in results["trials"]] == [("upper", "ok", 2), ("four", "ok", 4)]
    for row in results["trials"]:
        assert set(row["scores"]["families"]) == set(FAMILIES)
        for family in row["scores"]["families"].values():
            assert 0 < family["iou"] <= 1 and family["frames"] == 200 - 6  # one 2 s recording per level
        assert row["wall_seconds"] > 0 and row["host"] and (folder / "trials" / f"{row['name']}.pt").is_file()
    assert sorted(r["name"] for r in ledger(folder)) == ["four", "upper"]
    table = done.markdown.read_text()
    assert "| upper |" in table and "| four |" in table and "paper_amplitude" in table
    assert done.png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"

    start = time.perf_counter()
    again = run_study(tmp_path / "two.toml", folder, TINY)
    assert again.complete and again.ran == 0 and time.perf_counter() - start < 10
    assert len(ledger(folder)) == 2 and [r.status for r in again.records] == ["ok", "ok"]


def test_a_failing_trial_is_recorded_and_the_others_finish(ray_session, tiny_data, tmp_path):
    folder = study_folder(tiny_data, tmp_path)
    study = tiny_study(trial("broken", sensing__pairs=[[3, 27], [5, 999]]), trial("fine"))
    done = run_study(study, folder, TINY)
    assert done.complete and [r.status for r in done.records] == ["failed", "ok"]
    broken = ledger(folder)[[r["name"] for r in ledger(folder)].index("broken")]
    assert "sensing.pairs[1]" in broken["error"] and "999" in broken["error"] and not broken["scores"]
    assert "- broken: " in done.markdown.read_text()

    again = run_study(study, folder, TINY)  # a failed trial is tried again, a finished one is not
    assert again.ran == 1 and [r["name"] for r in ledger(folder)].count("fine") == 1


def test_an_interrupted_study_runs_only_the_missing_trials_when_run_again(ray_session, tiny_data, tmp_path):
    folder = study_folder(tiny_data, tmp_path)
    study = tiny_study(trial("a", train__seed=1), trial("b", train__seed=2), trial("c", train__seed=3))

    def ctrl_c_after_the_first_trial(stage: str, done: int, total: int) -> None:
        if stage == "trials" and done >= 1:
            os.kill(os.getpid(), signal.SIGINT)

    stopped = run_study(study, folder, TINY, progress=ctrl_c_after_the_first_trial)
    first = [r["name"] for r in ledger(folder)]
    assert not stopped.complete and 1 <= len(first) < 3
    assert {r.name for r in stopped.records if r.status == "pending"} == {"a", "b", "c"} - set(first)

    resumed = run_study(study, folder, TINY)
    assert resumed.complete and resumed.ran == 3 - len(first)
    assert sorted(r["name"] for r in ledger(folder)) == ["a", "b", "c"]


def test_a_folder_of_another_study_is_refused_unless_forced(tiny_data, tmp_path):
    folder = study_folder(tiny_data, tmp_path)
    (folder / "results.json").write_text(json.dumps({"study": "other", "scale": "tiny"}))
    with pytest.raises(OutputError, match="holds the tiny study 'other'.*--force"):
        run_study(tiny_study(trial("a")), folder, TINY)
