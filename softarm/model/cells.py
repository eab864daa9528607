"""A stream model's recurrent step and readout in NumPy, for one sample at a time.

A robot's loop advances the recurrent layer by one sample every 10 ms. Through `nn.LSTM` a single step costs
about 0.19 ms on one core, almost all of it the call's own overhead; the same arithmetic as one float32
matrix-vector product in NumPy costs 0.035 ms (`bench/streaming.py` has the whole step). The weights are read
from the trained layers when the reader is made, so the answers equal `nn.LSTM`'s and `nn.GRU`'s to float32
rounding (tests/model/test_cells.py).
"""

from typing import ClassVar

import numpy as np
import torch
from torch import nn


def _sigmoid(x: np.ndarray) -> np.ndarray:
    """The logistic function through tanh: no overflow warning for a saturated gate, unlike 1 / (1 + exp(-x))."""
    return 0.5 + 0.5 * np.tanh(0.5 * x)


def _weights(tensor: torch.Tensor) -> np.ndarray:
    return tensor.detach().cpu().numpy().astype(np.float32)


class Cell:
    """One layer's state, advanced sample by sample: `step(sample)` returns the new hidden state (H,)."""

    mode: ClassVar[str]  # the torch layer's `mode` this cell steps

    def __init__(self, rnn: nn.RNNBase):
        if rnn.mode != self.mode or rnn.num_layers != 1 or rnn.bidirectional or not rnn.bias or rnn.proj_size:
            raise ValueError(f"a NumPy {self.mode} cell reads one unidirectional {self.mode} layer with biases and "
                             f"no projection, not this {rnn.mode}")
        self.inputs, self.hidden = rnn.input_size, rnn.hidden_size
        self.reset()

    def reset(self) -> None:
        """Back to the zero state a torch layer starts from."""
        self.h = np.zeros(self.hidden, np.float32)

    def step(self, sample: np.ndarray) -> np.ndarray:
        raise NotImplementedError


class LstmCell(Cell):
    """`nn.LSTM`'s step: gates i, f, g, o in that order; the cell state c beside h."""

    mode = "LSTM"

    def __init__(self, rnn: nn.LSTM):
        self.w = np.ascontiguousarray(np.concatenate([_weights(rnn.weight_ih_l0), _weights(rnn.weight_hh_l0)], 1).T)
        self.b = _weights(rnn.bias_ih_l0) + _weights(rnn.bias_hh_l0)  # (P + H, 4H) and (4H,)
        super().__init__(rnn)

    def reset(self) -> None:
        super().reset()
        self.xh = np.zeros(self.inputs + self.hidden, np.float32)  # [sample, h]
        self.c = np.zeros(self.hidden, np.float32)

    def step(self, sample: np.ndarray) -> np.ndarray:
        h, xh = self.hidden, self.xh
        xh[:self.inputs] = sample
        g = xh @ self.w + self.b
        i, f, o = _sigmoid(g[:h]), _sigmoid(g[h:2 * h]), _sigmoid(g[3 * h:])
        self.c = f * self.c + i * np.tanh(g[2 * h:3 * h])
        self.h = o * np.tanh(self.c)
        xh[self.inputs:] = self.h
        return self.h


class GruCell(Cell):
    """`nn.GRU`'s step: gates r, z, n in that order; the reset gate scales the hidden part of n only."""

    mode = "GRU"

    def __init__(self, rnn: nn.GRU):
        self.w_input = np.ascontiguousarray(_weights(rnn.weight_ih_l0).T)   # (P, 3H)
        self.w_hidden = np.ascontiguousarray(_weights(rnn.weight_hh_l0).T)  # (H, 3H)
        self.b_input, self.b_hidden = _weights(rnn.bias_ih_l0), _weights(rnn.bias_hh_l0)
        super().__init__(rnn)

    def step(self, sample: np.ndarray) -> np.ndarray:
        h = self.hidden
        gi = sample.astype(np.float32) @ self.w_input + self.b_input
        gh = self.h @ self.w_hidden + self.b_hidden
        r, z = _sigmoid(gi[:h] + gh[:h]), _sigmoid(gi[h:2 * h] + gh[h:2 * h])
        n = np.tanh(gi[2 * h:] + r * gh[2 * h:])
        self.h = (1.0 - z) * n + z * self.h
        return self.h


def cell_of(rnn: nn.RNNBase) -> Cell:
    """The NumPy step of a torch recurrent layer."""
    cells = {cls.mode: cls for cls in (LstmCell, GruCell)}
    if rnn.mode not in cells:
        raise ValueError(f"no NumPy cell steps a {rnn.mode} layer")
    return cells[rnn.mode](rnn)


class Dense:
    """An `nn.Linear` on one vector in NumPy, float32 (at one sample 0.4 of `F.linear`'s time)."""

    def __init__(self, layer: nn.Linear):
        self.weight, self.bias = np.ascontiguousarray(_weights(layer.weight).T), _weights(layer.bias)

    def __call__(self, x: np.ndarray) -> np.ndarray:
        return x @ self.weight + self.bias


class Readout:
    """The latent head and the error head (Linear, ReLU, Linear) of a latent model, on one state (H,)."""

    def __init__(self, head: nn.Linear, error: nn.Sequential):
        if not (len(error) == 3 and isinstance(error[0], nn.Linear) and isinstance(error[1], nn.ReLU)
                and isinstance(error[2], nn.Linear)):
            raise ValueError("the error head must be Linear, ReLU, Linear")
        self.head, self.first, self.last = Dense(head), Dense(error[0]), Dense(error[2])

    def __call__(self, state: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The latent (K,) and its log squared errors (K,)."""
        return self.head(state), self.last(np.maximum(self.first(state), 0.0))
