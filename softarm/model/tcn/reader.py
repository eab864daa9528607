"""The causal convolution network streamed one sample at a time, in NumPy: each layer keeps the inputs its
dilated taps will read (a ring of (KERNEL - 1) x dilation + 1 samples), so a step costs one matrix-vector product
a layer instead of a pass over the whole receptive field. The rings start at zero, as the batch pass pads a
series, so the answers equal `CausalTCN.answer`'s to float32 rounding (tests/model/test_tcn.py)."""

from typing import TYPE_CHECKING, Optional

import numpy as np

from softarm.model.latent import OnlineReader
from softarm.model.tcn.shape import DILATIONS, KERNEL

if TYPE_CHECKING:
    from softarm.model.tcn.network import CausalTCN


class TcnReader(OnlineReader):
    def __init__(self, model: "CausalTCN"):
        self.model = model
        self.readout = model.readout()
        # conv weight (H, C, KERNEL) -> (KERNEL x C, H): the taps, oldest first, as one vector times one matrix
        self.weights = [np.ascontiguousarray(conv.weight.detach().cpu().numpy().astype(np.float32)
                                             .transpose(2, 1, 0).reshape(-1, conv.out_channels))
                        for conv in model.layers]
        self.biases = [conv.bias.detach().cpu().numpy().astype(np.float32) for conv in model.layers]
        self.rings = [np.zeros(((KERNEL - 1) * d + 1, conv.in_channels), np.float32)
                      for d, conv in zip(DILATIONS, model.layers)]
        self.samples = 0

    def step(self, sample: np.ndarray) -> Optional[tuple[np.ndarray, np.ndarray]]:
        t, x = self.samples, sample.astype(np.float32)
        for i, (weight, bias, ring, dilation) in enumerate(zip(self.weights, self.biases, self.rings, DILATIONS)):
            ring[t % len(ring)] = x
            taps = ring[[(t - (KERNEL - 1 - j) * dilation) % len(ring) for j in range(KERNEL)]]
            y = np.maximum(taps.reshape(-1) @ weight + bias, 0.0)
            x = y if i == 0 else x + y
        self.samples += 1
        self.state_vector = x.astype(np.float64)
        if self.samples < self.model.history:
            return None
        return self.readout(x)
