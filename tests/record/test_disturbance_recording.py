"""Disturbances in the recordings (softarm-recording/3): every kind, set or drawn, passes the format's independent
checker, says which disturbances act at every frame, and re-simulates from its metadata alone."""

import subprocess
import sys

import numpy as np
import pytest

from softarm.config import load_config
from softarm.record.reader import read_recording
from softarm.sim.simulate import simulate
from tests.helpers.resimulate import resimulate
from tests.record.test_excitation_kinds import CHECKER
from tests.sim.test_disturbances import ONE_OF_EACH

DRAWN = {"kind": "push", "share": 1.0, "count": [2, 3], "start": [0.2, 1.6], "duration": [0.05, 0.2],
         "force": [0.05, 0.3], "rows": [9, 18]}
CURRENT = {"kind": "drag", "share": 1.0, "count": [1, 2], "start": [0.3, 1.2], "duration": [0.2, 0.6],
           "speed": [0.02, 0.08], "coefficient": [0.01, 0.03], "quadratic": [0.1, 0.3]}
CASES = {**{kind: {"disturbances": [table]} for kind, table in ONE_OF_EACH.items()},
         "drawn": {"world.random": [DRAWN, CURRENT]},
         "all at once": {"disturbances": list(ONE_OF_EACH.values()), "world.random": [DRAWN]}}


@pytest.mark.slow
@pytest.mark.parametrize("case", list(CASES))
def test_every_kind_records_re_simulates_from_its_metadata_and_passes_the_checker(tmp_path, case):
    config = load_config(overrides={"run.duration": 2.0, "run.seed": 3, "excitation.amplitude": 0.006, **CASES[case]})
    simulate(config, tmp_path / "r.mcap")
    rec = read_recording(tmp_path / "r.mcap")
    listed = rec.model["disturbances"]
    assert listed and all(d["kind"] in ("push", "payload", "stiffness", "obstacle", "drag") for d in listed)
    for d, entry in enumerate(listed):  # the channel names exactly the frames inside each interval
        inside = (rec.times >= entry["start"]) & ((rec.times < entry["end"]) if entry["end"] is not None else True)
        assert np.array_equal(rec.active[:, d], inside)
    free = np.setdiff1d(np.arange(len(rec.model["nodes"])), rec.model["driven"])
    for d, entry in enumerate(listed):  # the label of contact: an active obstacle some free node is inside
        inside = (entry["kind"] == "obstacle"
                  and (np.linalg.norm(rec.positions[:, free] - entry.get("centre", 0.0), axis=2)
                       < entry.get("radius", 0))
                  .any(axis=1))
        assert np.array_equal(rec.touching[:, d], inside & rec.active[:, d])
    if "obstacle" in [d["kind"] for d in listed]:
        assert 0 < rec.touching.sum() < rec.active[:, [d["kind"] == "obstacle" for d in listed]].sum()
    again = resimulate(rec.model, len(rec.times))
    assert np.abs(again - rec.positions).max() < 1e-3  # MODEL.md's bar; here it agrees to the metadata's rounding
    assert np.abs(again - rec.positions).max() < 1e-7
    if not CHECKER.exists():
        pytest.skip(f"the shared format checker is not beside this clone ({CHECKER})")
    done = subprocess.run([sys.executable, str(CHECKER), str(tmp_path / "r.mcap")], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr


def test_the_same_seed_draws_the_same_disturbances_and_another_seed_others(tmp_path):
    from softarm.sim.batch import arm_batch

    config = load_config(overrides={"world.random": [DRAWN], "run.arms": 2})
    first, again = arm_batch(config), arm_batch(config)
    assert first.disturbances == again.disturbances
    assert first.disturbances[0] != first.disturbances[1]


@pytest.mark.slow
def test_bad_disturbances_are_refused_in_one_line_before_any_file(tmp_path):
    from tests.helpers.cli import assert_one_line_error, softarm

    cases = {"unknown kind": ('kind = "wind"\nstart = 1.0', "kind", "wind"),
             "node out of range": ('kind = "push"\nstart = 1.0\nforce = [1.0, 0.0]\nnodes = [99]', "nodes", "0..56"),
             "spring out of range": ('kind = "stiffness"\nstart = 0.0\nfactor = 2.0\nsprings = [164]', "springs",
                                     "0..163"),
             "negative mass": ('kind = "payload"\nstart = 0.0\nmass = -0.01\nnodes = [55]', "mass", ">= 0"),
             "end before start": ('kind = "push"\nstart = 2.0\nend = 1.0\nforce = [1.0, 0.0]\nnodes = [55]', "end",
                                  "after start"),
             "obstacle on the top row": ('kind = "obstacle"\nstart = 0.0\ncentre = [0.0, 0.0]\nradius = 0.01',
                                         "centre", "driven")}
    for name, (table, key, words) in cases.items():
        (tmp_path / "c.toml").write_text(f"[[disturbances]]\n{table}\n")
        assert_one_line_error(softarm("sim", "--config", "c.toml", "--out", "r.mcap", cwd=tmp_path), f".{key}'", words)
        assert not list(tmp_path.glob("*.mcap*")) and not (tmp_path / "recordings").exists(), name
