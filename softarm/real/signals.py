"""A numeric topic of a log as a time series: the field's values at the messages' header stamps (their
acquisition times), or at their log times, with a warning, where the message type has no header."""

import warnings
from dataclasses import dataclass
from typing import Any, Callable, Optional

import numpy as np

from softarm.errors import RecordingError
from softarm.real.fields import attribute_reader, field_values, header_stamp, parse_source
from softarm.real.log import LogFile


@dataclass(frozen=True)
class Series:
    source: str             # TOPIC:FIELD
    stamps: np.ndarray      # (S,) s, increasing
    values: np.ndarray      # (S, F) float64
    header_stamps: bool     # False: log times stand in for the acquisition times

    @property
    def names(self) -> list[str]:
        return [f"{self.source}[{i}]" for i in range(self.values.shape[1])]


class SeriesReader:
    """Collects one source's values ('TOPIC:FIELD') from its messages, as a pass over the log meets them."""

    def __init__(self, log: LogFile, source: str, option: str):
        self.source, self.option = source, option
        self.topic, self.path = parse_source(source, option)
        if self.topic not in log.topics:
            raise RecordingError(f"{option}: topic {self.topic} is not in {log.path}; it has {log.describe()}")
        self.where = f"{option} {self.topic}:{self.path}"
        self.stamps: list[float] = []
        self.values: list[np.ndarray] = []
        self.headers = True
        self._read: Optional[Callable[[object], Any]] = None

    def add(self, log_time: int, message: object) -> None:
        stamp = header_stamp(message)
        self.headers &= stamp is not None
        self.stamps.append(stamp if stamp is not None else log_time * 1e-9)
        if self._read is None:  # the first message checks the path; the rest are read by plain attribute access
            self.values.append(field_values(message, self.path, self.where))
            self._read = attribute_reader(self.path)
        else:
            try:
                self.values.append(self._read(message))
            except (KeyError, IndexError, AttributeError, TypeError):  # a later message that does not fit the path
                self.values.append(field_values(message, self.path, self.where))

    def series(self) -> Series:
        """Every message's values, sorted by stamp, duplicate stamps dropped; one line for what cannot be used."""
        where = self.where
        if len(self.values) < 2:
            raise RecordingError(f"{where}: the log holds {len(self.values)} message(s) on it; "
                                 f"a series needs two or more")
        widths = {np.size(v) for v in self.values}
        if len(widths) != 1:
            raise RecordingError(f"{where}: its messages hold {sorted(widths)} values; every message needs as many")
        if not self.headers:
            warnings.warn(f"{where}: {self.topic} has no header stamp, so its samples are placed at their log time "
                          "(when the log received them); transport delays and their jitter then shift them unreliably",
                          stacklevel=2)
        stamps = np.asarray(self.stamps)
        order = np.argsort(stamps, kind="stable")
        try:
            values = np.array(self.values, np.float64).reshape(len(self.values), -1)[order]
        except (TypeError, ValueError):
            raise RecordingError(f"{where}: some messages hold no numbers at {self.path}") from None
        stamps = stamps[order]
        keep = np.concatenate([[True], np.diff(stamps) > 0])
        if not np.isfinite(values).all():
            raise RecordingError(f"{where}: some values are NaN or infinite")
        return Series(self.source, stamps[keep], values[keep], self.headers)
