"""`softarm demo` as one call: the whole pipeline on defaults into one folder.

Simulate the default 100 s, train on it (with the training's live view saved), then replay it with a
camera blackout over the last 5 s, writing the timeline, the imagination as MCAP and a filmstrip.
"""

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Callable, Optional, Union

from softarm.config import load_config

if TYPE_CHECKING:
    from softarm.imagine.replay import ReplayOutcome
    from softarm.learn.training import TrainResult
    from softarm.sim.simulate import SimResult

BLACKOUT = "95:100"  # s: the camera is off for the last 5 s
STAGES = ("simulating", "training", "replaying")
Progress = Callable[[str, int, int, dict[str, float]], None]  # (stage, done, total, latest losses)


@dataclass
class DemoResult:
    folder: Path
    simulated: Optional["SimResult"] = None
    trained: Optional["TrainResult"] = None
    replayed: Optional["ReplayOutcome"] = None
    outputs: dict[str, Path] = field(default_factory=dict)  # what each file of the folder is

    @property
    def stopped_in(self) -> Optional[str]:
        """The stage an interruption ended (None: the demo ran to the end)."""
        if self.simulated is not None and not self.simulated.complete:
            return "simulating"
        if self.trained is not None and not self.trained.complete:
            return "training"
        return None


def demo(folder: Union[str, Path] = "recordings/demo", force: bool = False,
         progress: Optional[Progress] = None) -> DemoResult:
    """Run sim, train and replay on defaults into `folder`; every output is checked before any work."""
    from softarm.imagine.replay import replay
    from softarm.learn.training import check_train_outputs, train
    from softarm.sim.simulate import simulate

    folder = Path(folder)
    tell = progress or (lambda *_: None)
    result = DemoResult(folder, outputs={
        "recording": folder / "seed0.mcap", "checkpoint": folder / "model.pt", "training view": folder / "train.rrd",
        "replay rrd": folder / "replay.rrd", "replay mcap": folder / "imagination.mcap",
        "replay png": folder / "filmstrip.png"})
    o = result.outputs
    check_train_outputs(o["checkpoint"], o["training view"], resume=False, force=force)
    config = load_config()
    result.simulated = simulate(config, o["recording"], force=force,
                                progress=lambda done: tell("simulating", done, config.n_frames, {}))
    if result.stopped_in:
        return result
    result.trained = train([o["recording"]], config, o["checkpoint"], force=force, rrd=o["training view"],
                           progress=lambda done, total, losses: tell("training", done, total, losses))
    if result.stopped_in:
        return result
    tell("replaying", 0, 1, {})
    result.replayed = replay(o["checkpoint"], o["recording"], [BLACKOUT], rrd=o["replay rrd"], mcap=o["replay mcap"],
                             png=o["replay png"], force=True)
    tell("replaying", 1, 1, {})
    return result
