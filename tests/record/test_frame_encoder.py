"""The C frame encoder writes byte for byte what the Python encoder writes, and the block-wise chunking
keeps the MCAP layout: checked against the Python encoder and against the `mcap` package's reader."""

import io
import struct

import numpy as np
import pytest
import zstandard
from mcap.reader import make_reader
from mcap.records import Chunk, MessageIndex
from mcap.stream_reader import StreamReader

from softarm.record import frames
from softarm.record.mcap_writer import HEADER_BYTES, McapWriter
from softarm.record.writer import RecordingWriter

pytestmark = pytest.mark.skipif(frames.native is None, reason="the C encoder was not built (no C compiler)")

FRAME_DT = 0.01


def awkward_positions(rng: np.random.Generator, frames_: int, nodes: int) -> np.ndarray:
    """Node positions over every regime of the float text: 0, -0 (tiny negatives), the d.ddde-N range below
    1e-5, fixed decimals, whole numbers, up to just below 1e6, with any number of decimals."""
    magnitude = 10.0 ** rng.uniform(-13, 5.99, (frames_, nodes, 2))
    values = np.where(rng.random((frames_, nodes, 2)) < 0.5, -1, 1) * magnitude
    special = np.array([0.0, -0.0, 1.0, -2.0, 1e-5, 1e-6, -1.5e-8, 1e-9, 4.9e-10, 5e-10, -5e-10, 0.1234567895,
                        999999.999999999, 123456.000000001, 0.00001, 0.000099999])
    values.reshape(-1)[: len(special)] = special
    values[1] = np.round(values[1], 3)  # fewer decimals than nine
    return values


def write(path, block_args, monkeypatch, native: bool, model: dict | None = None) -> bytes:
    if not native:
        monkeypatch.setattr(frames, "native", None)
    writer = RecordingWriter(path, model or {"disturbances": []}, FRAME_DT)
    for images, stretch, positions, displacement in block_args:
        writer.write(images, stretch, positions, displacement)
    writer.close(True)
    monkeypatch.undo()
    return path.read_bytes()


def blocks(rng: np.random.Generator, sizes: list[int], positions) -> list[tuple]:
    out, start = [], 0
    for n in sizes:
        stretch = rng.standard_normal((n, 3)) * 10.0 ** rng.uniform(-20, 20, (n, 3))
        out.append(((rng.random((n, 6, 5)) < 0.5).astype(np.uint8), stretch, positions[start:start + n],
                    rng.standard_normal(n) * 0.01))
        start += n
    return out


def test_the_c_encoder_writes_the_python_encoders_bytes_over_every_float_regime(tmp_path, monkeypatch):
    rng = np.random.default_rng(7)
    args = blocks(rng, [1, 150, 49], awkward_positions(rng, 200, 57))
    model = {"disturbances": [{"start": 0.3, "end": 0.9}, {"start": 0.5, "end": None}]}
    c = write(tmp_path / "c.mcap", args, monkeypatch, native=True, model=model)
    python = write(tmp_path / "py.mcap", args, monkeypatch, native=False, model=model)
    assert c == python


def test_with_obstacles_both_encoders_write_the_same_touching_lists(tmp_path, monkeypatch):
    """Two discs beside a swinging cloud of nodes: the frames where some free node is inside each (the driven
    node 0 never counts), written alike by both encoders."""
    rng = np.random.default_rng(3)
    positions = np.cumsum(rng.normal(0, 0.004, (120, 6, 2)), axis=0)
    positions[:, 0] = (0.0, 0.0)  # the driven node, inside the first disc all along
    discs = [{"kind": "obstacle", "start": 0.0, "end": None, "centre": [0.0, 0.0], "radius": 0.02},
             {"kind": "push", "start": 0.2, "end": 0.5},
             {"kind": "obstacle", "start": 0.4, "end": 1.0, "centre": [0.01, -0.01], "radius": 0.015}]
    model = {"disturbances": discs, "nodes": [[0.0, 0.0]] * 6, "driven": [0]}
    args = [(np.zeros((n, 4, 3), np.uint8), rng.normal(size=(n, 2)), positions[s:s + n], np.zeros(n))
            for s, n in ((0, 1), (1, 70), (71, 49))]
    c = write(tmp_path / "c.mcap", args, monkeypatch, native=True, model=model)
    python = write(tmp_path / "py.mcap", args, monkeypatch, native=False, model=model)
    assert c == python
    from softarm.record.reader import _disturbance
    messages = {int(m.log_time): m.data for _, _, m in make_reader(io.BytesIO(c)).iter_messages(["/arm/disturbance"])}
    active, touching = _disturbance(messages, sorted(messages), model, tmp_path / "c.mcap")
    free = positions[:, 1:]
    for d, disc in ((0, discs[0]), (2, discs[2])):
        inside = (np.linalg.norm(free - disc["centre"], axis=2) < disc["radius"]).any(axis=1)
        assert np.array_equal(touching[:, d], inside & active[:, d])
        assert 0 < touching[:, d].sum() < active[:, d].sum()  # touched sometimes, not always
    assert not touching[:, 1].any()


@pytest.mark.parametrize("bad", [1e6, -3e7, np.nan, np.inf])
def test_values_the_c_encoder_cannot_write_exactly_fall_back_to_python(tmp_path, monkeypatch, bad):
    rng = np.random.default_rng(1)
    positions = rng.uniform(-0.3, 0.3, (20, 57, 2))
    positions[13, 40, 1] = bad
    args = blocks(rng, [20], positions)
    sizes = np.empty((20, 5), np.int64)
    images, stretch, pos, displacement = args[0]
    rows, items = b"[" + b",".join([b"[1.0]"] * 20) + b"]", b"[" + b",".join([b"0.5"] * 20) + b"]"
    assert frames.native.encode(np.arange(20, dtype=np.int64) * 10**7, (1, 2, 3, 4, 5), b"", b"", images, rows, pos,
                                57, items, b"[" + b",".join([b"[]"] * 20) + b"]", b"", sizes) is None
    assert write(tmp_path / "c.mcap", args, monkeypatch, native=True) == write(tmp_path / "p.mcap", args, monkeypatch,
                                                                               native=False)


def test_malformed_json_rows_are_refused_not_read_past():
    sizes = np.empty((2, 5), np.int64)
    with pytest.raises(ValueError, match="fewer rows"):
        frames.native.encode(np.array([0, 10], np.int64), (1, 2, 3, 4, 5), b"", b"", np.zeros((2, 4), np.uint8),
                             b"[[1.0]]", np.zeros((2, 1, 2)), 1, b"[0.1,0.2]", b"[[],[]]", b"", sizes)
    with pytest.raises(ValueError, match="fewer rows"):  # the touching lists too
        frames.native.encode(np.array([0, 10], np.int64), (1, 2, 3, 4, 5), b"", b"", np.zeros((2, 4), np.uint8),
                             b"[[1.0],[2.0]]", np.zeros((2, 1, 2)), 1, b"[0.1,0.2]", b"[[],[]]", b"[[0]]", sizes)


def chunks_and_indexes(data: bytes) -> list[tuple[bytes, list[MessageIndex]]]:
    """Each chunk's uncompressed records with the message indexes that follow it, read by the mcap package."""
    out = []
    for record in StreamReader(io.BytesIO(data), emit_chunks=True, validate_crcs=True).records:
        if isinstance(record, Chunk):
            out.append((zstandard.ZstdDecompressor().decompress(record.data, record.uncompressed_size), []))
        elif isinstance(record, MessageIndex):
            out[-1][1].append(record)
    return out


@pytest.mark.parametrize("chunk_size", [1, 700, 5000])
def test_chunks_close_after_the_record_that_fills_them_and_every_index_entry_points_at_its_message(chunk_size):
    rng = np.random.default_rng(chunk_size)
    sizes = rng.integers(0, 600, 120)
    datas = [bytes(rng.integers(0, 256, n, dtype=np.uint8)) for n in sizes]
    channels = rng.integers(1, 4, 120).tolist()
    times = np.cumsum(rng.integers(0, 3, 120)).tolist()
    stream = io.BytesIO()
    writer = McapWriter(stream, chunk_size=chunk_size)
    writer.start("", "test")
    schema = writer.register_schema("s", "jsonschema", b"{}")
    for topic in ("a", "b", "c"):
        writer.register_channel(topic, "json", schema)
    for cut in np.split(np.arange(120), [7, 8, 60]):  # blocks of any length, one empty
        writer.add_messages([channels[i] for i in cut], [times[i] for i in cut], [datas[i] for i in cut])
    writer.finish()
    data = stream.getvalue()
    read = [(m.channel_id, m.log_time, m.data) for _, _, m in make_reader(io.BytesIO(data)).iter_messages()]
    assert read == list(zip(channels, times, datas))
    chunks = chunks_and_indexes(data)
    for k, (records, indexes) in enumerate(chunks):
        starts = sorted(offset for index in indexes for _, offset in index.records)
        last = len(records) - starts[-1]
        assert len(records) > chunk_size or k == len(chunks) - 1
        assert len(records) - last <= chunk_size  # it closed right after the record that took it over
        for index in indexes:
            for log_time, offset in index.records:
                _, length, channel, _, stamp, _ = struct.unpack_from("<BQHIQQ", records, offset)
                assert (channel, stamp) == (index.channel_id, log_time) and length >= HEADER_BYTES - 9


def test_messages_out_of_log_time_order_are_refused_before_any_is_taken():
    writer = McapWriter(io.BytesIO())
    writer.start("", "test")
    writer.add_messages([1], [50], [b"x"])
    with pytest.raises(ValueError, match="30 ns after 50 ns"):
        writer.add_messages([1], [30], [b"y"])
    with pytest.raises(ValueError, match="40 ns after 60 ns"):
        writer.add_messages([1, 1], [60, 40], [b"y", b"z"])
    writer.add_messages([1], [55], [b"w"])  # nothing of the refused blocks was taken


def test_a_chunk_exactly_full_takes_one_more_record_as_the_per_message_writer_did():
    stream = io.BytesIO()
    writer = McapWriter(stream, chunk_size=2 * (HEADER_BYTES + 319))
    writer.start("", "test")
    writer.register_channel("a", "json", writer.register_schema("s", "jsonschema", b"{}"))
    writer.add_messages([1] * 7, list(range(7)), [b"x" * 319] * 7)
    writer.finish()
    assert [sum(len(index.records) for index in indexes)
            for _, indexes in chunks_and_indexes(stream.getvalue())] == [3, 3, 1]


def test_float32_and_strided_inputs_write_the_same_bytes_by_both_encoders(tmp_path, monkeypatch):
    rng = np.random.default_rng(3)
    images, stretch, positions, displacement = blocks(rng, [30], rng.uniform(-0.3, 0.3, (30, 57, 2)))[0]
    args = [(images, stretch.astype(np.float32), positions.astype(np.float32),
             np.stack([displacement, displacement], axis=1)[:, 0].astype(np.float32))]
    assert write(tmp_path / "c.mcap", args, monkeypatch, native=True) == write(tmp_path / "p.mcap", args, monkeypatch,
                                                                               native=False)


def test_the_statistics_count_channels_in_order_of_appearance():
    stream = io.BytesIO()
    writer = McapWriter(stream)
    writer.start("", "test")
    schema = writer.register_schema("s", "jsonschema", b"{}")
    for topic in ("a", "b", "c"):
        writer.register_channel(topic, "json", schema)
    writer.add_messages([3, 1, 3, 2], [0, 1, 1, 2], [b"x"] * 4)
    writer.finish()
    counts = make_reader(io.BytesIO(stream.getvalue())).get_summary().statistics.channel_message_counts
    assert list(counts.items()) == [(3, 2), (1, 1), (2, 1)]
