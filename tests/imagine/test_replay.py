"""`softarm replay`: the .rrd verifies and holds its entities, the imagination MCAP decodes without
softarm, blind segments change the fused view and split the metrics, mismatches are refused."""

import json
import subprocess

import numpy as np
import pytest
import rerun as rr
from mcap.reader import make_reader
from mcap_protobuf.decoder import DecoderFactory

from softarm.imagine.replay_data import compute_replay
from softarm.trust.surprise import WARM
from tests.helpers.cli import RERUN, assert_one_line_error, softarm

pytestmark = pytest.mark.slow  # each test replays a trained checkpoint through the CLI: seconds


@pytest.fixture(scope="module")
def outputs(recordings, tiny_checkpoint, tmp_path_factory):
    """One CLI replay of the seed-1 recording (not trained on) with a blind second, writing every output."""
    folder = tmp_path_factory.mktemp("replay")
    result = softarm("replay", str(tiny_checkpoint.checkpoint), str(recordings / "s1.mcap"), "--blind", "2.5:3.5",
                     "--rrd", "r.rrd", "--mcap", "i.mcap", "--png", "f.png", cwd=folder)
    assert result.returncode == 0, result.stderr
    return folder, result


def test_rrd_verifies_and_holds_the_replay_entities(outputs):
    folder, _ = outputs
    assert subprocess.run([RERUN, "rrd", "verify", str(folder / "r.rrd")], capture_output=True).returncode == 0
    entities = set(rr.chunk.RrdReader(str(folder / "r.rrd")).store().schema().entity_paths())
    expected = {"/camera/image", "/camera/nodes", "/imagined/image", "/difference/image", "/fused/image",
                "/signals/excitation", "/signals/iou", "/signals/confidence", "/signals/stretch/0",
                "/signals/stretch/3", "/signals/surprise", "/signals/alarm"}
    assert expected <= entities, entities
    assert not (folder / "r.rrd.part").exists()


def test_imagination_mcap_decodes_with_a_plain_mcap_reader(outputs, recordings, tiny_checkpoint):
    folder, _ = outputs
    images, ious, trust, surprise, alarm = [], [], [], [], []
    with open(folder / "i.mcap", "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        meta = {m.name: m.metadata for m in reader.iter_metadata()}
        for _, _, message, decoded in reader.iter_decoded_messages(topics=["/imagination/image"]):
            assert decoded.encoding == "mono8" and (decoded.height, decoded.width) == (84, 52)
            images.append(message.log_time)
        for schema, _, message in reader.iter_messages(topics=["/imagination/iou"]):
            assert schema.encoding == "jsonschema" and json.loads(schema.data)["properties"]["iou"]
            ious.append((message.log_time, json.loads(message.data)["iou"]))
        for schema, _, message in reader.iter_messages(topics=["/imagination/confidence"]):
            assert json.loads(schema.data)["properties"]["confidence"]
            trust.append((message.log_time, json.loads(message.data)["confidence"]))
        for schema, _, message in reader.iter_messages(topics=["/imagination/surprise"]):
            assert json.loads(schema.data)["properties"]["surprise"]
            surprise.append((message.log_time, json.loads(message.data)["surprise"]))
        for schema, _, message in reader.iter_messages(topics=["/imagination/alarm"]):
            assert json.loads(schema.data)["properties"]["alarm"]["type"] == "boolean"
            alarm.append((message.log_time, json.loads(message.data)["alarm"]))
    # 4 s at 100 Hz, history 6: frames 6..399, at the source frames' times
    assert images == [round(k * 0.01 * 1e9) for k in range(6, 400)] == [t for t, _ in ious] == [t for t, _ in trust]
    assert [t for t, _ in surprise] == [t for t, _ in alarm] == images
    replayed = compute_replay(tiny_checkpoint.checkpoint, recordings / "s1.mcap", nodes=False)
    felt = [np.nan if v is None else v for _, v in surprise]  # null before the surprise is warm
    np.testing.assert_allclose(felt, replayed.surprise[6:400], rtol=1e-6)
    assert np.isnan(felt[WARM - 6]) and np.isfinite(felt[WARM + 1 - 6:]).all()  # frame k + 1 from sample k on
    assert np.nanmin(felt) >= 0
    assert [v for _, v in alarm] == list(replayed.alarm[6:400])
    assert all(0 <= v <= 1 for _, v in ious) and all(0 < v <= 1 for _, v in trust)
    info = meta["softarm.imagination"]
    assert info["source_recording"].endswith("s1.mcap") and info["checkpoint"].endswith("tiny.pt")


def test_png_filmstrip_and_metrics_table(outputs):
    folder, result = outputs
    from PIL import Image
    image = Image.open(folder / "f.png")
    assert image.width > image.height > 3 * 84
    assert "camera blind" in result.stdout and "camera seeing" in result.stdout and "real time" in result.stdout


def test_blind_segment_changes_the_fused_view_and_splits_the_metrics(recordings, tiny_checkpoint):
    seeing = compute_replay(tiny_checkpoint.checkpoint, recordings / "s1.mcap")
    blind = compute_replay(tiny_checkpoint.checkpoint, recordings / "s1.mcap", [(2.0, 3.0)])
    assert seeing.blind.sum() == 0 and blind.blind.sum() == 100
    np.testing.assert_array_equal(seeing.fused, seeing.recording.frames)  # no blackout: the camera itself
    inside = blind.blind
    np.testing.assert_array_equal(blind.fused[inside], blind.imagined[inside])
    np.testing.assert_array_equal(blind.fused[~inside], blind.recording.frames[~inside])
    assert seeing.metrics["imagination_blind"] is None and blind.metrics["blind_frames"] == 100
    assert blind.metrics["imagination_blind"]["iou"] != blind.metrics["imagination_seeing"]["iou"]
    assert blind.metrics["fused"]["iou"] < seeing.metrics["fused"]["iou"] == 1.0
    assert blind.metrics["imagination"] == seeing.metrics["imagination"]  # blackouts change no imagination


@pytest.mark.parametrize("blind, words", [("5:9", ["outside the recording", "0..4"]), ("5-6", ["START:END"]),
                                          ("2:1", ["START < END"])])
def test_blind_range_outside_or_malformed_is_refused(recordings, tiny_checkpoint, tmp_path, blind, words):
    result = softarm("replay", str(tiny_checkpoint.checkpoint), str(recordings / "s0.mcap"), "--blind", blind,
                     "--rrd", "x.rrd", cwd=tmp_path)
    assert_one_line_error(result, *words)
    assert not list(tmp_path.iterdir())


def test_recording_with_other_sensors_is_refused(recordings, tiny_checkpoint, tmp_path):
    result = softarm("replay", str(tiny_checkpoint.checkpoint), str(recordings / "three_sensors.mcap"),
                     "--mcap", "x.mcap", cwd=tmp_path)
    assert_one_line_error(result, "3 stretch sensors", "trained with 4")
    assert not list(tmp_path.iterdir())


def test_a_file_that_is_not_a_checkpoint_is_refused(recordings, tmp_path):
    (tmp_path / "fake.pt").write_bytes(b"not a checkpoint at all")
    result = softarm("replay", "fake.pt", str(recordings / "s0.mcap"), cwd=tmp_path)
    assert_one_line_error(result, "fake.pt", "not a softarm checkpoint")


def test_fused_scores_equal_scoring_the_fused_frames_directly(recordings, tiny_checkpoint):
    from softarm.model.metrics import frame_scores, summarise
    result = compute_replay(tiny_checkpoint.checkpoint, recordings / "s1.mcap", [(1.0, 2.5)])
    direct = summarise(frame_scores(result.fused.astype(np.float64), result.recording.frames, 400.0))
    for key, value in result.metrics["fused"].items():
        assert value == pytest.approx(direct[key], rel=1e-6, abs=1e-9), key


def test_png_span_picks_the_filmstrip_frames_and_shows_the_alarm(recordings, tiny_checkpoint, tmp_path):
    from PIL import Image

    result = softarm("replay", str(tiny_checkpoint.checkpoint), str(recordings / "s1.mcap"), "--png", "s.png",
                     "--png-span", "1:1.5", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    image = Image.open(tmp_path / "s.png")
    assert image.height == 2 * 14 + 4 * (84 + 4) * 3  # two header lines; camera, imagined, difference, alarm
    empty = softarm("replay", str(tiny_checkpoint.checkpoint), str(recordings / "s1.mcap"), "--png", "e.png",
                    "--mcap", "e.mcap", "--png-span", "50:60", cwd=tmp_path)
    assert_one_line_error(empty, "--png-span")
    assert not (tmp_path / "e.png").exists() and not (tmp_path / "e.mcap").exists()
