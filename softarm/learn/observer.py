"""What training tells a live view, and how it gets one: training never imports rerun itself.

`softarm.view.training_view.TrainingView` implements `TrainingObserver`; without an .rrd file or a
viewer to show it, training gets `NoObserver` and spends nothing on drawing.
"""

from contextlib import contextmanager
from pathlib import Path
from typing import Callable, Iterator, Optional, Protocol, Union

import numpy as np

Progress = Callable[[int, int, dict[str, float]], None]  # (optimisation steps done, steps in all, latest losses)
StageProgress = Callable[[str, int, int], None]  # ("reading" recordings or "fitting" the fits after training,
# done, in all)


class TrainingObserver(Protocol):
    def loss(self, name: str, step: int, value: float) -> None: ...

    def clip(self, step: int, times: np.ndarray, truth: np.ndarray, reconstruction: np.ndarray,
             imagination: Optional[np.ndarray]) -> None: ...


class NoObserver:
    """Nobody is watching: every report is dropped."""

    def loss(self, name: str, step: int, value: float) -> None:
        pass

    def clip(self, step: int, times: np.ndarray, truth: np.ndarray, reconstruction: np.ndarray,
             imagination: Optional[np.ndarray]) -> None:
        pass


@contextmanager
def open_observer(rrd: Optional[Union[str, Path]], spawn: bool) -> Iterator[TrainingObserver]:
    """The live view asked for (saved to `rrd`, shown in a spawned viewer), closed whole at the end."""
    if rrd is None and not spawn:
        yield NoObserver()
        return
    from softarm.view.training_view import TrainingView  # rerun is imported only when a view is asked for

    with TrainingView(spawn=spawn, rrd=Path(rrd) if rrd is not None else None) as view:
        yield view
