"""Damaged files as Hypothesis draws them, and the one property every loader must keep: a read that succeeds,
or a softarm error, never another exception and never a hang."""

import json
import signal
import warnings
from contextlib import contextmanager
from typing import Any, Callable, Iterator

from hypothesis import strategies as st

from softarm.errors import SoftarmError

HANG_SECONDS = 10


@st.composite
def damaged(draw: Any, original: bytes) -> bytes:
    """`original` cut short, with bits flipped, a span overwritten, bytes inserted or deleted, or none of it
    left (random bytes)."""
    data = bytearray(original)
    kind = draw(st.sampled_from(["truncate", "flip", "overwrite", "insert", "delete", "random"]))
    at = draw(st.integers(0, max(0, len(data) - 1)))
    if kind == "truncate":
        return bytes(data[:at])
    if kind == "flip":
        for position in draw(st.lists(st.integers(0, max(0, len(data) - 1)), min_size=1, max_size=8)):
            data[position] ^= 1 << draw(st.integers(0, 7))
        return bytes(data)
    if kind == "overwrite":
        span = draw(st.binary(min_size=1, max_size=64))
        data[at:at + len(span)] = span
        return bytes(data)
    if kind == "insert":
        return bytes(data[:at] + draw(st.binary(min_size=1, max_size=64)) + data[at:])
    if kind == "delete":
        return bytes(data[:at] + data[at + draw(st.integers(1, 256)):])
    return draw(st.binary(max_size=2048))


JSON_VALUES = st.recursive(st.none() | st.booleans() | st.integers() | st.floats(allow_nan=False) | st.text(max_size=8),
                           lambda inner: (st.lists(inner, max_size=4)
                                          | st.dictionaries(st.text(max_size=8), inner, max_size=4)),
                           max_leaves=12)


@st.composite
def reshaped(draw: Any, document: Any) -> Any:
    """Valid JSON of the wrong shape: one value somewhere inside `document` deleted or replaced by another."""
    if not isinstance(document, (dict, list)) or not document or draw(st.integers(0, 4)) == 0:
        return draw(JSON_VALUES)
    keys = list(document) if isinstance(document, dict) else list(range(len(document)))
    key = draw(st.sampled_from(keys))
    copy = dict(document) if isinstance(document, dict) else list(document)
    if draw(st.booleans()) and isinstance(copy, dict):
        del copy[key]
    else:
        copy[key] = draw(reshaped(document[key]))
    return copy


def json_bytes(document: Any) -> bytes:
    return json.dumps(document).encode()


@contextmanager
def no_hang(seconds: int = HANG_SECONDS) -> Iterator[None]:
    def hung(*_: Any) -> None:
        raise TimeoutError(f"a loader ran for more than {seconds} s")

    old = signal.signal(signal.SIGALRM, hung)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


def refused_or_read(load: Callable[[], Any]) -> bool:
    """True when `load()` read the file, False when it refused it with a softarm error; anything else fails the
    test (it propagates)."""
    with no_hang(), warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a truncated recording warns, and still reads
        try:
            load()
        except SoftarmError as e:
            assert "\n" not in str(e).strip(), f"a refusal must be one line: {e}"
            return False
    return True
