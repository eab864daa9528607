"""Online imagination gives, sample by sample, the frames, confidences, surprises and alarms a batch replay gives
from the same signals, for every model kind."""

import numpy as np
import pytest

from softarm import StreamingImaginer
from softarm.imagine.replay_data import compute_replay
from softarm.imagine.trained import TrainedModel
from softarm.record.reader import read_recording
from softarm.trust.surprise import WARM


@pytest.mark.slow
@pytest.mark.parametrize("fixture", ["tiny_window_checkpoint", "tiny_checkpoint", "tiny_tcn_checkpoint"])
def test_streamed_frames_equal_the_batch_replays(recordings, fixture, request):
    imaginer = TrainedModel(request.getfixturevalue(fixture).checkpoint).imaginer
    stretch = read_recording(recordings / "s1.mcap", nodes=False).stretch
    prediction, batch = imaginer.imagine(stretch)
    stream = StreamingImaginer(imaginer)
    streamed = {}
    for sample in stretch:
        out = stream.step(sample)
        if out is not None:
            streamed[out.frame] = out
    targets = prediction.targets
    assert min(streamed) == targets[0] and max(streamed) == len(stretch)  # one frame past the last sample
    np.testing.assert_allclose(np.stack([streamed[k].probabilities for k in targets]), batch, atol=1e-5)
    np.testing.assert_allclose([streamed[k].confidence for k in targets], imaginer.confidence(prediction), rtol=1e-5)
    read = targets - imaginer.latent.lead  # the sample each frame is imagined from: felt from sample WARM on
    assert prediction.surprise is not None and (np.isfinite(prediction.surprise) == (read >= WARM)).all()
    np.testing.assert_allclose([streamed[k].surprise for k in targets], prediction.surprise, rtol=1e-4, atol=1e-6)
    assert [streamed[k].alarm for k in targets] == list(prediction.surprise > imaginer.surprise.threshold)
    stream.reset()
    assert stream.step(stretch[0]) is None and stream.samples == 1


@pytest.mark.slow
@pytest.mark.parametrize("fixture, remembers", [("tiny_window_checkpoint", False), ("tiny_checkpoint", True),
                                                ("tiny_tcn_checkpoint", True)])
def test_only_the_memory_models_remember_samples_older_than_the_window(recordings, fixture, remembers, request):
    imaginer = TrainedModel(request.getfixturevalue(fixture).checkpoint).imaginer
    stretch = read_recording(recordings / "s1.mcap", nodes=False).stretch
    changed = stretch.copy()
    changed[:100] += 1e-4  # the first second: frame 110's 6-sample window starts 4 samples later
    frame_110 = [imaginer.predict(s).latents[110 - 6] for s in (stretch, changed)]
    assert (np.abs(frame_110[0] - frame_110[1]).max() > 1e-6) == remembers


@pytest.mark.slow
def test_a_streamer_told_its_sensors_noise_equals_a_replay_told_the_same(recordings, tiny_checkpoint):
    """Through sensors with 50 um of white noise, replay's --sensor-noise and the streamer built with the same
    noise give the same surprises and alarms; without being told, the same readings surprise it several times more."""
    noise = {"noise": 5e-5}
    replayed = compute_replay(tiny_checkpoint.checkpoint, recordings / "s1.mcap", nodes=False, sensor_noise=noise)
    stream = StreamingImaginer.from_checkpoint(tiny_checkpoint.checkpoint, sensor_noise=noise)
    told = {}
    for sample in replayed.inputs[:-1]:  # all but the last (whose frame replay has not): it speaks from sample WARM on
        frame = stream.step(sample)
        if frame is not None:
            told[frame.frame] = frame
    frames = [k for k in told if np.isfinite(replayed.surprise[k])]
    assert len(frames) > 300
    np.testing.assert_allclose([told[k].surprise for k in frames], replayed.surprise[frames], rtol=1e-4, atol=1e-6)
    assert [told[k].alarm for k in frames] == list(replayed.alarm[frames])
    untold = TrainedModel(tiny_checkpoint.checkpoint).imaginer.predict(replayed.inputs)
    assert np.nanmedian(untold.surprise) > 2.5 * np.nanmedian(replayed.surprise)  # part of it read as novelty


@pytest.mark.slow
@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_a_reading_that_is_not_finite_is_refused_and_spoils_nothing_after_it(recordings, tiny_checkpoint, bad):
    imaginer = TrainedModel(tiny_checkpoint.checkpoint).imaginer
    stretch = read_recording(recordings / "s1.mcap", nodes=False).stretch[:120]
    clean, hit = StreamingImaginer(imaginer), StreamingImaginer(imaginer)
    for k, sample in enumerate(stretch):
        if k == 60:
            broken = sample.copy()
            broken[2] = bad
            with pytest.raises(ValueError, match="reading 2 of the sample is .*inf|reading 2 of the sample is nan"):
                hit.step(broken)
        expected, got = clean.step(sample), hit.step(sample)
        if expected is not None:  # the refused sample left no trace: every later answer is the clean stream's
            assert got.frame == expected.frame and got.confidence == expected.confidence
            assert np.isfinite(got.surprise) == np.isfinite(expected.surprise) and got.alarm == expected.alarm
            np.testing.assert_array_equal(got.probabilities, expected.probabilities)
    assert hit.samples == clean.samples == len(stretch)
