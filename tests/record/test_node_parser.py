"""The C node parser reads what orjson reads from /arm/nodes messages of softarm's form, and refuses (so that
orjson reads them) any other: checked against orjson on awkward numbers and on a recording softarm wrote."""

import numpy as np
import orjson
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from mcap.reader import make_reader

from softarm.errors import RecordingError
from softarm.record import decode
from softarm.record.format import NODES
from softarm.record.reader import read_recording
from tests.helpers.fuzz import damaged

pytestmark = pytest.mark.skipif(decode.native is None, reason="the C node parser was not built (no C compiler)")


def messages_of(positions: np.ndarray) -> list[bytes]:
    return [orjson.dumps({"t": k * 0.01, "positions": p.tolist()}) for k, p in enumerate(positions)]


def by_orjson(messages: list[bytes]) -> np.ndarray:
    return np.array([orjson.loads(m)["positions"] for m in messages], np.float64)


def test_awkward_numbers_read_as_orjson_reads_them():
    rng = np.random.default_rng(0)
    values = np.where(rng.random((300, 57, 2)) < 0.5, -1, 1) * 10.0 ** rng.uniform(-320, 300, (300, 57, 2))
    values.reshape(-1)[:9] = [0.0, -0.0, 5e-324, 1.7976931348623157e308, 0.1, 1e-7, 123456789.0, 2.5e-308, 1e-320]
    messages = messages_of(values)
    parsed = decode.native.positions(b"\n".join(messages), len(messages), 57)
    assert parsed is not None
    got = np.frombuffer(parsed, np.float64).reshape(300, 57, 2)
    np.testing.assert_array_equal(got, by_orjson(messages))
    assert np.array_equal(np.signbit(got), np.signbit(by_orjson(messages)))  # -0.0 stays negative


def test_integers_read_as_orjson_reads_them():
    message = b'{"t":0,"positions":[[-0,12],[-7,0],[90071992547409931,-0]]}'
    got = np.frombuffer(decode.native.positions(message, 1, 3), np.float64).reshape(1, 3, 2)
    np.testing.assert_array_equal(got, by_orjson([message]))
    assert np.array_equal(np.signbit(got), np.signbit(by_orjson([message])))  # "-0" is the integer 0 there


@pytest.mark.parametrize("message", [
    b'{"t":0.0,"positions":[[1.0,2.0],[3.0,4.0]]}\n{"t":0.01,"positions":[[1.0,2.0]]}',  # a node short
    b'{"t":0.0,"positions":[[1.0,2.0],[3.0,4.0]]}\n{"t":0.01,"positions":[[1.0,2.0],[3.0,4.0],[5.0,6.0]]}',
    b'{"t":0.0, "positions":[[1.0,2.0],[3.0,4.0]]}\n{"t":0.01,"positions":[[1.0,2.0],[3.0,4.0]]}',  # whitespace
    b'{"positions":[[1.0,2.0],[3.0,4.0]],"t":0.0}\n{"t":0.01,"positions":[[1.0,2.0],[3.0,4.0]]}',  # key order
    b'{"t":0.0,"positions":[[null,2.0],[3.0,4.0]]}\n{"t":0.01,"positions":[[1.0,2.0],[3.0,4.0]]}',
    b'{"t":0.0,"positions":[[01,2.0],[3.0,4.0]]}\n{"t":0.01,"positions":[[1.0,2.0],[3.0,4.0]]}',  # not JSON
    b'{"t":0.0,"positions":[[1.,2.0],[3.0,4.0]]}\n{"t":0.01,"positions":[[1.0,2.0],[3.0,4.0]]}',
    b'{"t":0.0,"positions":[[1e,2.0],[3.0,4.0]]}\n{"t":0.01,"positions":[[1.0,2.0],[3.0,4.0]]}',
    b'{"t":0.0,"positions":[[1e999,2.0],[3.0,4.0]]}\n{"t":0.01,"positions":[[1.0,2.0],[3.0,4.0]]}',  # infinite
    b'{"t":0.0,"positions":[[1.0,2.0],[3.0,4.0]]}\n{"t":0.01,"positions":[[1.0,2.0],[3.0,4.0]]}x',  # trailing
    b'{"t":0.0,"positions":[[1.0,2.0],[3.0,4.0]]}\n{"t":0.01,"positions":[[1.0,2.0],[3.0,4.0]',  # cut short
    b'\n{"t":0.0,"positions":[[1.0,2.0],[3.0,4.0]]}{"t":0.01,"positions":[[1.0,2.0],[3.0,4.0]]}',  # two in one
    b'{"t":0.0,"positions":[[1.0,2.0],[3.0,4.0]\n]}{"t":0.01,"positions":[[1.0,2.0],[3.0,4.0]]}',  # cut, its end next
])
def test_anything_but_softarms_form_is_left_to_orjson(message):
    assert decode.native.positions(message, 2, 2) is None
    good = b'{"t":0.0,"positions":[[1.0,2.0],[3.0,4.0]]}\n{"t":0.01,"positions":[[1.0,2.0],[3.0,-4.0]]}'
    assert np.frombuffer(decode.native.positions(good, 2, 2), np.float64).tolist() == [1, 2, 3, 4, 1, 2, 3, -4]


def test_the_reader_falls_back_to_orjson_and_refuses_what_it_refuses(tmp_path):
    spaced = {k: orjson.dumps({"t": k, "positions": [[1.5, -2.0]]}, option=orjson.OPT_INDENT_2) for k in range(3)}
    np.testing.assert_array_equal(decode.node_positions(spaced, [0, 1, 2], 1, tmp_path), [[[1.5, -2.0]]] * 3)
    broken = {0: b'{"t":0.0,"positions":[[1.0]]}'}
    with pytest.raises(RecordingError, match=NODES):
        decode.node_positions(broken, [0], 1, tmp_path)


def test_a_recording_reads_the_same_with_and_without_the_parser(recordings, monkeypatch):
    with open(recordings / "s0.mcap", "rb") as f:
        written = [m.data for _, _, m in make_reader(f).iter_messages(topics=[NODES])]
    assert decode.native.positions(b"\n".join(written), len(written), 57) is not None  # softarm's own form
    fast = read_recording(recordings / "s0.mcap").positions
    monkeypatch.setattr(decode, "native", None)
    slow = read_recording(recordings / "s0.mcap").positions
    assert fast.shape == slow.shape and fast.shape[1:] == (57, 2) and fast.flags.writeable
    np.testing.assert_array_equal(fast, slow)


@pytest.mark.slow
def test_damaged_messages_are_read_as_orjson_reads_them_or_left_to_it():
    """Hypothesis damages newline-joined messages (tests/helpers/fuzz.py); whatever the parser accepts must be
    exactly what orjson reads from each line, and both outcomes must occur."""
    rng = np.random.default_rng(1)
    joined = b"\n".join(messages_of(np.round(rng.normal(0, 0.05, (4, 3, 2)), 9)))
    outcomes: list[bool] = []

    @settings(max_examples=400, deadline=None, derandomize=True, database=None,
              suppress_health_check=[HealthCheck.too_slow])
    @given(data=st.data())
    def case(data):
        text = data.draw(damaged(joined))
        parsed = decode.native.positions(text, 4, 3)
        outcomes.append(parsed is not None)
        if parsed is not None:
            lines = [orjson.loads(line) for line in text.split(b"\n")]
            assert [sorted(line) for line in lines] == [["positions", "t"]] * 4
            np.testing.assert_array_equal(np.frombuffer(parsed, np.float64).reshape(4, 3, 2),
                                          np.array([line["positions"] for line in lines], np.float64))

    case()
    assert any(outcomes) and not all(outcomes), f"{sum(outcomes)} read of {len(outcomes)}"
