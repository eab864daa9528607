"""The recording reader on foreign, newer and damaged files: one-line refusals, and every complete
frame recovered from a file cut at any byte."""

import warnings

import numpy as np
from mcap.writer import Writer

from softarm.errors import RecordingError
from softarm.record.reader import TruncatedRecordingWarning, read_recording
from tests.helpers.cli import assert_one_line_error, softarm


def write_mcap(path, metadata=None):
    """A valid MCAP with one JSON channel and, optionally, one metadata record."""
    with open(path, "wb") as f:
        writer = Writer(f)
        writer.start()
        schema = writer.register_schema("x", "jsonschema", b"{}")
        channel = writer.register_channel("/x", "json", schema)
        if metadata:
            writer.add_metadata(*metadata)
        writer.add_message(channel, 0, b"{}", 0)
        writer.finish()


def test_mcap_without_softarm_metadata_is_refused(tmp_path):
    write_mcap(tmp_path / "foreign.mcap")
    assert_one_line_error(softarm("train", "foreign.mcap", "--out", "x.pt", cwd=tmp_path),
                          "foreign.mcap", "not a softarm recording")
    assert not (tmp_path / "x.pt").exists()


def test_recording_of_a_newer_format_is_refused(tmp_path):
    write_mcap(tmp_path / "new.mcap", ("softarm", {"format": "softarm-recording/4", "model": "{}"}))
    assert_one_line_error(softarm("train", "new.mcap", "--out", "x.pt", cwd=tmp_path),
                          "softarm-recording/4", "upgrade softarm")


def test_recording_cut_before_its_metadata_is_refused(recordings, tmp_path):
    (tmp_path / "cut.mcap").write_bytes((recordings / "s0.mcap").read_bytes()[:200])
    assert_one_line_error(softarm("train", "cut.mcap", "--out", "x.pt", cwd=tmp_path), "cut short")


def test_a_recording_cut_at_any_byte_gives_back_every_complete_frame(recordings, tmp_path):
    data = (recordings / "s0.mcap").read_bytes()
    whole = read_recording(recordings / "s0.mcap")
    recovered = []
    for cut in np.linspace(len(data) // 50, len(data) - 1, 23).astype(int):
        (tmp_path / "cut.mcap").write_bytes(data[:cut])
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                rec = read_recording(tmp_path / "cut.mcap")
            except RecordingError as e:
                assert "cut short" in str(e) or "no complete frame" in str(e)
                continue
        assert rec.truncated and not rec.complete
        assert any(issubclass(w.category, TruncatedRecordingWarning) and f"{len(rec.times)} complete frames"
                   in str(w.message) for w in caught)
        n = len(rec.times)
        np.testing.assert_array_equal(rec.frames, whole.frames[:n])
        np.testing.assert_array_equal(rec.stretch, whole.stretch[:n])
        recovered.append(n)
    assert recovered == sorted(recovered) and recovered[-1] == len(whole.times)
