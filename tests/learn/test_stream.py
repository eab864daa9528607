"""Online imagination gives, sample by sample, the frames a batch replay imagines from the same signals."""

import numpy as np

from softarm.learn.checkpoint import load_checkpoint
from softarm.learn.imaginer import Imaginer
from softarm.learn.stream import StreamingImaginer
from softarm.record.reader import read_recording


def test_streamed_frames_equal_the_batch_replays(recordings, tiny_checkpoint):
    imaginer = Imaginer.from_checkpoint(load_checkpoint(tiny_checkpoint.checkpoint))
    stretch = read_recording(recordings / "s1.mcap", nodes=False).stretch
    targets, batch = imaginer.imagine(stretch)
    stream = StreamingImaginer(imaginer)
    streamed = {}
    for sample in stretch:
        out = stream.step(sample)
        if out is not None:
            streamed[out[0]] = out[1]
    assert min(streamed) == targets[0] and max(streamed) == len(stretch)  # one frame past the last sample
    np.testing.assert_allclose(np.stack([streamed[k] for k in targets]), batch, atol=1e-5)
    stream.reset()
    assert stream.step(stretch[0]) is None and stream.samples == 1
