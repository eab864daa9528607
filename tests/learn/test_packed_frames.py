import numpy as np
import pytest

from softarm.learn.packed_frames import PackedFrames


@pytest.fixture
def frames() -> np.ndarray:
    return (np.random.default_rng(0).random((300, 84, 52)) > 0.7).astype(np.uint8)


def test_packed_frames_index_as_the_frames_do(frames):
    packed = PackedFrames.pack(frames)
    rows = np.random.default_rng(1).integers(0, len(frames), 128)
    mask = np.random.default_rng(2).random(len(frames)) > 0.5
    assert packed.shape == frames.shape and len(packed) == len(frames)
    assert packed.bits.nbytes == len(frames) * 84 * 7  # 52 pixels a row in 7 bytes
    for key in (5, -1, slice(3, 40), slice(None, None, 7), rows, mask):
        assert packed[key].dtype == np.uint8 and np.array_equal(packed[key], frames[key])
    assert np.array_equal(packed.select(mask)[:], frames[mask])
    joined = PackedFrames.join([packed.select(slice(0, 100)), packed.select(mask)])
    assert np.array_equal(joined[:], np.concatenate([frames[:100], frames[mask]]))


def test_the_mean_frame_is_numpys(frames):
    many = np.concatenate([frames] * 30)  # more than one chunk of sums
    assert np.array_equal(PackedFrames.pack(many).mean(), many.mean(axis=0))


def test_only_binary_frames_pack(frames):
    with pytest.raises(ValueError, match="binary"):
        PackedFrames.pack(frames * 255)
    with pytest.raises(ValueError, match="binary"):
        PackedFrames.pack(frames.astype(np.float32))
