"""softarm: a simulated soft arm that learns to picture its own body from its stretch sensors.

The data path, one stage per subpackage: `arm` (the body as arrays) -> `sim` (Taichi physics and
camera) -> `record` (MCAP) -> `sense` (what the sensors read) -> `model` (the trained model: networks,
inputs, checkpoint, answers, baselines, metrics) trained by `learn` -> `imagine` (replay, the online
streamer) -> `suite` (held-out evaluation) -> `view` (Rerun, PNG); `study` runs grids of trainings and
evaluations as Ray tasks; `demo` runs the whole pipeline; `real` imports a robot's ROS 2 / Foxglove log.

From a notebook::

    import softarm
    result = softarm.simulate(softarm.load_config(), "arm.mcap")
    trained = softarm.train(["arm.mcap"], out="arm.pt")
    replayed = softarm.replay("arm.pt", "arm.mcap", rrd="replay.rrd")
    softarm.write_suite("suite")                      # the held-out motions
    scores = softarm.evaluate("arm.pt", "suite")      # per family, beside the baselines
    done = softarm.run_study("sensors", "studies/sensors")  # a comparative study, trials as Ray tasks
    stream = softarm.StreamingImaginer.from_checkpoint("arm.pt")  # one sample in, one imagined frame out
    adapted = softarm.adapt("arm.pt", "loaded.mcap", seconds=5, out="loaded.pt")  # a changed body, 5 s of camera
    settings = softarm.ImportSettings("/camera/image_raw/compressed", "/arm/stretch:data", roi=(190, 30, 260, 420))
    report = softarm.import_log("lab.mcap", "lab_arm.mcap", settings)  # a robot's ROS 2 log as a recording

Importing softarm is cheap: Taichi, torch and rerun load when a function first needs them.
"""

import importlib
import os
from typing import TYPE_CHECKING, Any

# Taichi prints a banner on import; softarm's output is its own (the CLI's --quiet must mean quiet).
os.environ.setdefault("ENABLE_TAICHI_HEADER_PRINT", "false")

__version__ = "0.2.0"

_API = {
    "load_config": "softarm.config",
    "Config": "softarm.config",
    "SoftarmError": "softarm.errors",
    "simulate": "softarm.sim.simulate",
    "read_recording": "softarm.record.reader",
    "train": "softarm.learn.training",
    "adapt": "softarm.learn.adapt",
    "replay": "softarm.imagine.replay",
    "write_corpus": "softarm.corpus.build",
    "write_suite": "softarm.suite.build",
    "evaluate": "softarm.suite.evaluate",
    "load_study": "softarm.study.builtin",
    "run_study": "softarm.study.runner",
    "demo": "softarm.demo",
    "StreamingImaginer": "softarm.imagine.stream",
    "import_log": "softarm.real.convert",
    "ImportSettings": "softarm.real.settings",
    "preview_log": "softarm.real.preview",
    "make_robot_log": "softarm.real.robot_log",
}
__all__ = list(_API)

if TYPE_CHECKING:  # what editors and type checkers read: the real signatures (re-exported: `x as x`),
    # none of the import cost at run time
    from softarm.config import Config as Config
    from softarm.config import load_config as load_config
    from softarm.corpus.build import write_corpus as write_corpus
    from softarm.demo import demo as demo
    from softarm.errors import SoftarmError as SoftarmError
    from softarm.imagine.replay import replay as replay
    from softarm.imagine.stream import StreamingImaginer as StreamingImaginer
    from softarm.learn.adapt import adapt as adapt
    from softarm.learn.training import train as train
    from softarm.real.convert import import_log as import_log
    from softarm.real.preview import preview_log as preview_log
    from softarm.real.robot_log import make_robot_log as make_robot_log
    from softarm.real.settings import ImportSettings as ImportSettings
    from softarm.record.reader import read_recording as read_recording
    from softarm.sim.simulate import simulate as simulate
    from softarm.study.builtin import load_study as load_study
    from softarm.study.runner import run_study as run_study
    from softarm.suite.build import write_suite as write_suite
    from softarm.suite.evaluate import evaluate as evaluate


def __getattr__(name: str) -> Any:
    """Load a public function's stage on first use (PEP 562), so `import softarm` stays light."""
    if name not in _API:
        raise AttributeError(f"module 'softarm' has no attribute {name!r}")
    value = getattr(importlib.import_module(_API[name]), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted([*globals(), *__all__])
