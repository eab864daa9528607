"""A user's slip (a missing or misplaced input, a malformed range) is refused before torch loads: in well under a
second, not after the seconds a network library takes to import. Checked in a fresh interpreter, by whether torch
is among its modules once the call has been refused."""

import subprocess
import sys

import pytest

from tests.helpers.suites import mini_suite

CALLS = {  # the call, and what its refusal names
    "replay, missing recording": ("from softarm.imagine.replay import replay; replay(CKPT, 'missing.mcap')",
                                  "recording missing.mcap not found"),
    "replay, folder as checkpoint": ("from softarm.imagine.replay import replay; replay('.', REC)",
                                     "is a folder, not a checkpoint"),
    "replay, malformed --blind": ("from softarm.imagine.replay import replay; replay(CKPT, REC, ['2:1'])", "'2:1'"),
    "adapt, missing checkpoint": ("from softarm.learn.adapt import adapt; adapt('missing.pt', REC, 2.0, 'a.pt')",
                                  "checkpoint missing.pt not found"),
    "train, missing recording": ("from softarm.learn.training import train; train(['missing.mcap'], out='m.pt')",
                                 "recording missing.mcap not found"),
    "evaluate, missing checkpoint": ("from softarm.suite.evaluate import evaluate; evaluate('missing.pt', SUITE)",
                                     "checkpoint missing.pt not found"),
}


@pytest.mark.parametrize("call, words", list(CALLS.values()), ids=list(CALLS))
def test_a_slip_is_refused_before_torch_loads(recordings, tiny_checkpoint, call, words, tmp_path):
    suite = mini_suite(tmp_path / "suite", recordings / "s0.mcap")
    program = (f"import sys\nCKPT, REC, SUITE = {str(tiny_checkpoint.checkpoint)!r}, {str(recordings / 's0.mcap')!r}, "
               f"{str(suite)!r}\nfrom softarm.errors import SoftarmError\ntry:\n    {call}\nexcept SoftarmError as e:\n"
               f"    print('refused:', e)\nprint('torch' in sys.modules)")
    result = subprocess.run([sys.executable, "-c", program], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    refusal, torch_loaded = result.stdout.strip().splitlines()
    assert refusal.startswith("refused:") and words in refusal and torch_loaded == "False", result.stdout
