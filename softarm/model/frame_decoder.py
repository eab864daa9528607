"""The autoencoder's decoder prepared for one code at a time: what the streamer draws every 10 ms.

At one code the decoder's layers are tiny and each module call's overhead counts: the batch norms (fixed
affine maps once trained) are folded into the convolutions before them, the layers run as plain functional
calls on those folded weights, the feature maps and weights are channels-last, and each transposed
convolution runs as an ordinary convolution to its four output phases, interleaved by a pixel shuffle (oneDNN
runs the last one, of one output channel, faster so; the others as fast). Measured on one core, round-robin
against the alternatives: 0.62-0.78 ms a frame, against 0.81 ms with the folding alone and 1.0-1.1 ms through
the module (`bench/streaming.py` times the whole step); the pixels equal the module's to float32 rounding
(tests/model/test_frame_decoder.py).
"""

from typing import Callable, Optional

import numpy as np
import torch
import torch.nn.functional as F
from torch import nn

from softarm.model.autoencoder import Autoencoder
from softarm.model.cells import Dense

Layer = Callable[[torch.Tensor], torch.Tensor]


def folded(conv: nn.Module, norm: nn.BatchNorm2d) -> tuple[torch.Tensor, torch.Tensor]:
    """The weight and bias of `conv` followed by `norm` (in eval mode) as one convolution."""
    if not norm.affine or norm.running_mean is None:
        raise TypeError("the frame decoder folds only affine batch norms with running statistics")
    gain = norm.weight / torch.sqrt(norm.running_var + norm.eps)
    # a convolution's weight is (out, in, k, k); a transposed one's (in, out, k, k)
    shape = (1, -1, 1, 1) if isinstance(conv, nn.ConvTranspose2d) else (-1, 1, 1, 1)
    bias = conv.bias if conv.bias is not None else torch.zeros_like(norm.running_mean)
    return (conv.weight * gain.view(shape)).contiguous(), ((bias - norm.running_mean) * gain + norm.bias).contiguous()


def phases(weight: torch.Tensor, bias: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """A transposed convolution of kernel 4, stride 2, padding 1 (weight (in, out, 4, 4)) as a 3x3 convolution of
    padding 1 to out x 4 channels whose pixel shuffle is its output: output pixel (2m + a, 2n + b) reads input
    (m - d, n - e) through kernel tap (2d + a + 1, 2e + b + 1), for the d, e in {-1, 0, 1} that put the tap
    inside the kernel."""
    c_in, c_out = weight.shape[:2]
    out = torch.zeros(c_out, 2, 2, c_in, 3, 3)
    for a in range(2):
        for b in range(2):
            for d in (-1, 0, 1):
                for e in (-1, 0, 1):
                    row, column = 2 * d + a + 1, 2 * e + b + 1
                    if 0 <= row < 4 and 0 <= column < 4:
                        out[:, a, b, :, 1 - d, 1 - e] = weight[:, :, row, column].T
    return out.reshape(c_out * 4, c_in, 3, 3), bias.repeat_interleave(4)


def convolution(conv: nn.Module, weight: torch.Tensor, bias: Optional[torch.Tensor]) -> Layer:
    """The functional call of a convolution or transposed one, its weight channels-last."""
    if conv.groups != 1 or conv.dilation != (1, 1) or conv.padding_mode != "zeros":
        raise TypeError("the frame decoder runs only plain convolutions (no groups, dilation or padding mode)")
    if isinstance(conv, nn.ConvTranspose2d):
        if (conv.kernel_size, conv.stride, conv.padding, conv.output_padding) == ((4, 4), (2, 2), (1, 1), (0, 0)):
            grid, shift = phases(weight, bias if bias is not None else torch.zeros(weight.shape[1]))
            grid = grid.contiguous(memory_format=torch.channels_last)
            return lambda x: F.pixel_shuffle(F.conv2d(x, grid, shift, padding=1), 2)
        weight = weight.contiguous(memory_format=torch.channels_last)
        return lambda x: F.conv_transpose2d(x, weight, bias, conv.stride, conv.padding, conv.output_padding)
    weight = weight.contiguous(memory_format=torch.channels_last)
    return lambda x: F.conv2d(x, weight, bias, conv.stride, conv.padding)


def dense(module: nn.Module) -> Callable[[np.ndarray], np.ndarray]:
    """One of the fully connected layers before the feature map, in NumPy (a float32 matrix-vector product there
    costs 0.4 of `F.linear`'s at one code)."""
    if isinstance(module, nn.Linear):
        return Dense(module)
    if isinstance(module, nn.ReLU):
        return lambda x: np.maximum(x, 0.0, dtype=np.float32)
    raise TypeError(f"the frame decoder cannot run a {type(module).__name__} before the feature map")


def layer(module: nn.Module) -> Layer:
    """One of the convolutional layers from the feature map on, as a functional call."""
    if isinstance(module, nn.ReLU):
        return torch.relu
    if isinstance(module, (nn.Conv2d, nn.ConvTranspose2d)):
        return convolution(module, module.weight.detach(), None if module.bias is None else module.bias.detach())
    if isinstance(module, nn.Sequential) and len(module) == 3 and isinstance(module[1], nn.BatchNorm2d):
        convolve, activate = convolution(module[0], *folded(module[0], module[1])), layer(module[2])
        return lambda x: activate(convolve(x))  # conv, norm, activation
    raise TypeError(f"the frame decoder cannot run a {type(module).__name__}")


class FrameDecoder:
    """Pixel probabilities (H, W) of one raw latent code (F,), from the autoencoder's weights when made: the
    fully connected layers in NumPy up to the feature map (the decoder's `nn.Unflatten`), the rest in torch."""

    def __init__(self, autoencoder: Autoencoder):
        self.height, self.width = autoencoder.height, autoencoder.width
        modules = list(autoencoder.decoder)
        split = next(i for i, m in enumerate(modules) if isinstance(m, nn.Unflatten))
        self.size = tuple(modules[split].unflattened_size)
        with torch.no_grad():
            self.dense = [dense(module) for module in modules[:split]]
            self.layers = [layer(module) for module in modules[split + 1:]]

    @torch.inference_mode()
    def __call__(self, code: np.ndarray) -> np.ndarray:
        x = np.asarray(code, np.float32)
        for call in self.dense:
            x = call(x)
        y = torch.from_numpy(x).view(1, *self.size).contiguous(memory_format=torch.channels_last)
        for call in self.layers:
            y = call(y)
        return torch.sigmoid(y[0, 0, :self.height, :self.width]).numpy()
