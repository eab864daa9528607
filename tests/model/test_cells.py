"""The NumPy recurrent steps and readout of the online reader give what the torch layers give, sample by sample,
over a long stream (their rounding does not grow)."""

import numpy as np
import pytest
import torch
from torch import nn

from softarm.model.cells import GruCell, LstmCell, Readout, cell_of


@pytest.mark.parametrize("layer, cell", [(nn.LSTM, LstmCell), (nn.GRU, GruCell)])
def test_a_cell_steps_as_the_torch_layer_reads_the_whole_series(layer, cell):
    torch.manual_seed(0)
    rnn = layer(5, 32, batch_first=True)
    series = torch.randn(1, 2000, 5)
    with torch.no_grad():
        expected = rnn(series)[0][0].numpy()
    stepper = cell(rnn)
    got = np.stack([stepper.step(sample).copy() for sample in series[0].numpy()])
    assert got.dtype == np.float32
    np.testing.assert_allclose(got, expected, atol=1e-5)


@pytest.mark.parametrize("rnn, cell", [(nn.LSTM(5, 8, num_layers=2), LstmCell), (nn.GRU(5, 8), LstmCell),
                                       (nn.LSTM(5, 8, proj_size=4), LstmCell), (nn.RNN(5, 8), None)])
def test_a_cell_refuses_a_layer_it_cannot_step(rnn, cell):
    with pytest.raises(ValueError, match="NumPy"):
        cell(rnn) if cell is not None else cell_of(rnn)


def test_the_readout_answers_as_the_heads_do():
    torch.manual_seed(1)
    head, error = nn.Linear(32, 16), nn.Sequential(nn.Linear(32, 64), nn.ReLU(), nn.Linear(64, 16))
    states = torch.randn(50, 32)
    readout = Readout(head, error)
    with torch.no_grad():
        for state, latent, log_error in zip(states.numpy(), head(states).numpy(), error(states).numpy()):
            got = readout(state)
            np.testing.assert_allclose(got[0], latent, atol=1e-6)
            np.testing.assert_allclose(got[1], log_error, atol=1e-6)
