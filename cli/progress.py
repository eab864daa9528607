"""Progress of long commands: a bar on a terminal, plain lines in a log.

The bar appears on the first update, so errors found before any work print alone, and only when stderr
is a terminal. When stdout is not a terminal (a log, a pipe, a batch job), a plain line goes there at the
start and end of every stage and at least once a minute in between (steps, rate, time left), so a log
shows life.
"""

import threading
import time
from typing import Optional

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn

LINE_EVERY = 30.0   # s between two plain lines while updates come
HEARTBEAT = 60.0    # s at most without a line, updates or not


class LazyProgress:
    """`update(done)` draws a bar of `total` `unit` with a rate column and writes log lines; `close()` ends both
    (safe if nothing was ever drawn)."""

    def __init__(self, console: Console, label: str, total: int, unit: str, scale: float = 1.0, quiet: bool = False,
                 log: Optional[Console] = None):
        self.console, self.label, self.total, self.unit, self.scale = console, label, total, unit, scale
        self.bar_shown = not quiet and console.is_terminal
        self.log = log if not quiet and log is not None and not log.is_terminal else None
        self.progress: Optional[Progress] = None
        self.task = None
        self.done, self.extra, self.started, self.last_line = 0, "", 0.0, 0.0
        self._lock = threading.Lock()
        self._stop = threading.Event()

    def update(self, done: int, total: Optional[int] = None, **fields: str) -> None:
        """Show `done` of the total (which `total` may change, e.g. once a job knows its size)."""
        if total is not None:
            self.total = total
        if fields:
            self.extra = " ".join(fields.values())
        self.done = done
        if self.log is not None:
            self._log_update()
        if self.bar_shown:
            self._draw()

    def _draw(self) -> None:
        if self.progress is None:
            self.progress = Progress(TextColumn(self.label), BarColumn(), MofNCompleteColumn(), TextColumn(self.unit),
                                     TextColumn("{task.fields[rate]}"), TextColumn("{task.fields[extra]}"),
                                     TimeElapsedColumn(), TimeRemainingColumn(), console=self.console)
            self.progress.start()
            self.task = self.progress.add_task(self.label, total=self.total, rate="", extra="")
        elapsed = self.progress.tasks[self.task].elapsed or 1e-9
        rate = f"{self.done * self.scale / elapsed:,.0f} {self.unit}/s"
        self.progress.update(self.task, completed=self.done, total=self.total, rate=rate, extra=self.extra)

    def _log_update(self) -> None:
        now = time.monotonic()
        if not self.started:
            self.started = now
            self._line(f"{self.label}: started, {self.total:,} {self.unit}")
            threading.Thread(target=self._heartbeat, daemon=True).start()
        elif now - self.last_line >= LINE_EVERY:
            self._line(self._status(now))

    def _heartbeat(self) -> None:
        while not self._stop.wait(5.0):
            now = time.monotonic()
            if now - self.last_line >= HEARTBEAT:
                self._line(self._status(now))

    def _status(self, now: float) -> str:
        elapsed = now - self.started
        share = self.done / self.total if self.total else 0.0
        left = f", about {clock(elapsed / share - elapsed)} left" if 0 < share < 1 else ""
        extra = f", {self.extra}" if self.extra else ""
        return f"{self.label}: {self.done:,} of {self.total:,} {self.unit} ({share:.0%}) in {clock(elapsed)}{left}{extra}"

    def _line(self, text: str) -> None:
        with self._lock:
            self.last_line = time.monotonic()
            self.log.print(text, markup=False)

    def close(self) -> None:
        if self.progress is not None:
            self.progress.stop()
            self.progress = None
        if self.log is not None and self.started and not self._stop.is_set():
            self._stop.set()
            self._line(f"{self.label}: ended at {self.done:,} of {self.total:,} {self.unit} in "
                       f"{clock(time.monotonic() - self.started)}")

    def __enter__(self) -> "LazyProgress":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class StagedProgress:
    """One `LazyProgress` per stage of a pipeline (`progress(stage, done, total[, numbers])`), each closed when
    the next begins. `stages` maps a stage to its label and unit; `numbers` (latest losses) show beside it."""

    def __init__(self, console: Console, stages: dict[str, tuple[str, str]], quiet: bool = False,
                 log: Optional[Console] = None):
        self.console, self.stages, self.quiet, self.log = console, stages, quiet, log
        self.bars: dict[str, LazyProgress] = {}

    def __call__(self, stage: str, done: int, total: int, numbers: Optional[dict[str, float]] = None) -> None:
        if stage not in self.bars:
            self.close()
            label, unit = self.stages[stage]
            self.bars[stage] = LazyProgress(self.console, label, total, unit, quiet=self.quiet, log=self.log)
        self.bars[stage].update(done, total=total, **shown(numbers or {}))

    def close(self) -> None:
        for bar in self.bars.values():
            bar.close()

    def __enter__(self) -> "StagedProgress":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def shown(numbers: dict[str, float]) -> dict[str, str]:
    """Latest losses as the bar's fields: {"ae_train": "ae_train 0.0123"}."""
    return {k: f"{k} {v:.4f}" for k, v in numbers.items()}


def clock(seconds: float) -> str:
    """12 s, 3 min 05 s, 1 h 02 min."""
    seconds = max(0.0, seconds)
    if seconds < 60:
        return f"{seconds:.0f} s"
    if seconds < 3600:
        return f"{int(seconds // 60)} min {int(seconds % 60):02d} s"
    return f"{int(seconds // 3600)} h {int(seconds % 3600 // 60):02d} min"
