"""A numeric topic of a log as a time series: the field's values at the messages' header stamps (their
acquisition times), or at their log times, with a warning, where the message type has no header."""

import warnings
from dataclasses import dataclass

import numpy as np

from softarm.errors import RecordingError
from softarm.real.fields import field_values, header_stamp, parse_source
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


def read_series(log: LogFile, source: str, option: str) -> Series:
    """Every message's values of `source` ('TOPIC:FIELD'), sorted by stamp, duplicate stamps dropped."""
    topic, path = parse_source(source, option)
    if topic not in log.topics:
        raise RecordingError(f"{option}: topic {topic} is not in {log.path}; it has {log.describe()}")
    stamps, values, headers = [], [], True
    where = f"{option} {topic}:{path}"
    for log_time, message in log.messages(topic):
        stamp = header_stamp(message)
        headers &= stamp is not None
        stamps.append(stamp if stamp is not None else log_time * 1e-9)
        values.append(field_values(message, path, where))
    if len(values) < 2:
        raise RecordingError(f"{where}: the log holds {len(values)} message(s) on it; a series needs two or more")
    widths = {len(v) for v in values}
    if len(widths) != 1:
        raise RecordingError(f"{where}: its messages hold {sorted(widths)} values; every message needs as many")
    if not headers:
        warnings.warn(f"{where}: {topic} has no header stamp, so its samples are placed at their log time (when "
                      "the log received them); transport delays and their jitter then shift them unreliably",
                      stacklevel=2)
    stamps_array = np.asarray(stamps)
    order = np.argsort(stamps_array, kind="stable")
    stamps_array, values_array = stamps_array[order], np.stack(values)[order]
    keep = np.concatenate([[True], np.diff(stamps_array) > 0])
    if not np.isfinite(values_array).all():
        raise RecordingError(f"{where}: some values are NaN or infinite")
    return Series(source, stamps_array[keep], values_array[keep], headers)
