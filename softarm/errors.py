"""Errors a user can cause. The CLI prints their message as one line and exits non-zero."""


class SoftarmError(Exception):
    """Base of every error that a user's input (config, file, option) can cause."""


class ConfigError(SoftarmError):
    """A config file or option is malformed or out of range."""


class RecordingError(SoftarmError):
    """A recording is missing, unreadable, of another format, or does not fit what reads it."""


class SimulationError(SoftarmError):
    """The simulation failed (for example it blew up)."""


class OutputError(SoftarmError):
    """An output path cannot be written (exists, parent missing or not a folder)."""


class CheckpointError(SoftarmError):
    """A checkpoint is missing, not a softarm checkpoint, or does not fit the model or recording."""


class BlindRangeError(SoftarmError):
    """A --blind range is malformed or outside the recording."""
