"""The streamer's frame decoder (batch norms folded, transposed convolutions as phase convolutions) draws what
the autoencoder's decoder module draws."""

import numpy as np
import torch
import torch.nn.functional as F
from torch import nn

from softarm.model.autoencoder import Autoencoder
from softarm.model.frame_decoder import FrameDecoder, phases


def test_the_phase_convolution_is_the_transposed_convolution():
    torch.manual_seed(0)
    weight, bias, x = torch.randn(6, 3, 4, 4), torch.randn(3), torch.randn(2, 6, 9, 5)
    grid, shift = phases(weight, bias)
    np.testing.assert_allclose(F.pixel_shuffle(F.conv2d(x, grid, shift, padding=1), 2).numpy(),
                               F.conv_transpose2d(x, weight, bias, stride=2, padding=1).numpy(), atol=1e-5)


def test_a_frame_equals_the_modules_with_trained_batch_norms():
    torch.manual_seed(2)
    autoencoder = Autoencoder(84, 52, 16)
    for module in autoencoder.modules():  # batch-norm statistics and affines far from their initial identity
        if isinstance(module, nn.BatchNorm2d):
            n = module.num_features
            module.running_mean.copy_(torch.randn(n)), module.running_var.copy_(torch.rand(n) + 0.2)
            nn.init.normal_(module.weight, 1.0, 0.5), nn.init.normal_(module.bias, 0.0, 0.5)
    autoencoder.eval()
    decoder = FrameDecoder(autoencoder)
    codes = np.random.default_rng(0).normal(0, 2, (20, 16)).astype(np.float32)
    with torch.no_grad():
        expected = torch.sigmoid(autoencoder.decode(torch.from_numpy(codes))).numpy()
    got = np.stack([decoder(code) for code in codes])
    assert got.shape == (20, 84, 52) and got.dtype == np.float32
    assert expected.std() > 0.05  # frames with something in them, not a saturated blank
    np.testing.assert_allclose(got, expected, atol=2e-6)
