"""Where torch runs: `auto` is the CPU on a machine without CUDA and changes nothing there, `cuda` is refused in one
line where torch sees no GPU, the training's device code (frames unpacked on the device, checkpoints written from
the CPU) equals the host's arithmetic, and a checkpoint answers the same wherever it is loaded. The tests marked
`cuda` run only where torch sees a GPU (the GPU machine's bench runs them)."""

import warnings

import numpy as np
import pytest
import torch

from softarm.config import load_config
from softarm.errors import ConfigError, SoftarmError
from softarm.imagine.trained import TrainedModel
from softarm.learn.packed_frames import PackedFrames
from softarm.learn.train_state import _saved_config
from softarm.model.device import on_cpu, torch_device
from softarm.study.runner import trial_device
from tests.helpers.cli import assert_one_line_error, softarm
from tests.helpers.tiny import TINY

cuda = pytest.mark.skipif(not torch.cuda.is_available(), reason="torch sees no CUDA GPU here")


def test_auto_is_the_gpu_where_torch_sees_one_and_the_cpu_elsewhere():
    assert torch_device("auto").type == ("cuda" if torch.cuda.is_available() else "cpu")
    assert torch_device("cpu") == torch.device("cpu")
    with pytest.raises(ConfigError, match="give one of"):
        torch_device("tpu")


@pytest.mark.slow
@pytest.mark.skipif(torch.cuda.is_available(), reason="this machine has a GPU")
def test_cuda_without_a_gpu_is_refused_in_one_line_before_any_work(recordings, tmp_path):
    with pytest.raises(ConfigError, match="torch sees no CUDA GPU"):
        torch_device("cuda")
    result = softarm("train", str(recordings / "s0.mcap"), "--device", "cuda", "--out", "m.pt", cwd=tmp_path)
    assert_one_line_error(result, "--device cpu or auto")
    assert list(tmp_path.iterdir()) == []


def test_frames_unpacked_on_the_device_equal_numpys_unpacking():
    frames = (np.random.default_rng(3).random((40, 84, 52)) < 0.4).astype(np.uint8)
    packed = PackedFrames.pack(frames)
    index = torch.tensor([0, 39, 7, 7, 12])
    on_device = packed.on(torch_device("auto"))[index.to(torch_device("auto"))]
    assert on_device.dtype == torch.uint8
    assert np.array_equal(on_device.cpu().numpy(), frames[index.numpy()])


def test_checkpoints_hold_cpu_tensors_only_and_answer_the_same_when_loaded_again(tiny_checkpoint, recordings):
    state = torch.load(tiny_checkpoint.checkpoint, map_location=lambda storage, where: storage, weights_only=True)
    tensors = [v for v in _leaves(state) if isinstance(v, torch.Tensor)]
    assert tensors and all(t.device.type == "cpu" for t in tensors)  # as written, wherever it was trained
    model = TrainedModel(tiny_checkpoint.checkpoint, "cpu")
    reading = model.read(recordings / "s1.mcap")
    first = model.imaginer.imagine(reading.inputs)
    again = TrainedModel(tiny_checkpoint.checkpoint, "auto").imaginer.imagine(reading.inputs)
    assert np.abs(first[1] - again[1]).max() < 1e-5


def test_on_cpu_keeps_structure_and_values():
    state = {"a": torch.arange(3.0), "b": [torch.ones(2), (1, "x")], "c": {"d": None}}
    moved = on_cpu(state)
    assert moved["b"][1] == (1, "x") and moved["c"] == {"d": None} and torch.equal(moved["a"], state["a"])


def test_resume_trains_on_the_device_asked_now_without_a_warning():
    saved = {"config": load_config(overrides={"train.device": "cuda"}).to_dict()}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        config = _saved_config(saved, load_config(overrides={"train.device": "cpu"}))
    assert config.train.device == "cpu"


class Cluster:
    """What `trial_device` reads of a Ray session: the cluster's resources."""
    def __init__(self, gpus: int):
        self.gpus = gpus

    def cluster_resources(self) -> dict:
        return {"CPU": 2.0, **({"GPU": float(self.gpus)} if self.gpus else {})}


def test_a_studys_trials_ask_for_a_gpu_where_the_cluster_has_one():
    assert trial_device(Cluster(0), "auto") == "cpu" and trial_device(Cluster(2), "auto") == "cuda"
    assert trial_device(Cluster(2), "cpu") == "cpu" and trial_device(Cluster(1), "cuda") == "cuda"
    with pytest.raises(SoftarmError, match="no GPU"):
        trial_device(Cluster(0), "cuda")


@cuda
def test_a_model_trained_on_the_gpu_answers_on_the_cpu_as_on_the_gpu(recordings, tmp_path):
    from softarm.learn.training import train

    trained = train([recordings / "s0.mcap"], load_config(overrides={**TINY, "train.device": "cuda"}),
                    tmp_path / "gpu.pt")
    gpu, cpu = TrainedModel(trained.checkpoint, "cuda"), TrainedModel(trained.checkpoint, "cpu")
    reading = cpu.read(recordings / "s1.mcap")
    assert np.abs(gpu.imaginer.imagine(reading.inputs)[1] - cpu.imaginer.imagine(reading.inputs)[1]).max() < 1e-5


def _leaves(value):
    if isinstance(value, dict):
        for item in value.values():
            yield from _leaves(item)
    elif isinstance(value, (list, tuple)):
        for item in value:
            yield from _leaves(item)
    else:
        yield value
