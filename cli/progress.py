"""A progress bar that appears on the first update, so errors found before any work print alone; only on a
terminal, so that a log or a pipe holds the command's messages and nothing else."""

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn


class LazyProgress:
    """`update(done)` draws a bar of `total` `unit` with a rate column; `close()` ends it (safe if never drawn)."""

    def __init__(self, console: Console, label: str, total: int, unit: str, scale: float = 1.0, quiet: bool = False):
        self.console, self.label, self.total, self.unit, self.scale, self.quiet = console, label, total, unit, scale, quiet
        self.progress: Progress | None = None
        self.task = None

    def update(self, done: int, total: int | None = None, **fields: str) -> None:
        """Show `done` of the total (which `total` may change, e.g. once a job knows its size)."""
        if self.quiet or not self.console.is_terminal:  # a log or a pipe gets the summary, not a bar's last frame
            return
        if total is not None:
            self.total = total
        if self.progress is None:
            self.progress = Progress(TextColumn(self.label), BarColumn(), MofNCompleteColumn(), TextColumn(self.unit),
                                     TextColumn("{task.fields[rate]}"), TextColumn("{task.fields[extra]}"),
                                     TimeElapsedColumn(), TimeRemainingColumn(), console=self.console)
            self.progress.start()
            self.task = self.progress.add_task(self.label, total=self.total, rate="", extra="")
        elapsed = self.progress.tasks[self.task].elapsed or 1e-9
        rate = f"{done * self.scale / elapsed:,.0f} {self.unit}/s"
        self.progress.update(self.task, completed=done, total=self.total, rate=rate, extra=" ".join(fields.values()))

    def close(self) -> None:
        if self.progress is not None:
            self.progress.stop()

    def __enter__(self) -> "LazyProgress":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
