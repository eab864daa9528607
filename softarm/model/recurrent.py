"""Latent models whose state is a recurrent layer's: the window model and the stream models. The layer is
`core` (one unidirectional `nn.LSTM` or `nn.GRU`, named `rnn` in checkpoints) and the online readers step it in
NumPy (`softarm.model.cells`)."""

from typing import Any, ClassVar

from torch import nn

from softarm.model.cells import Cell, cell_of
from softarm.model.latent import LatentModel


class RecurrentModel(LatentModel):
    core: ClassVar[type[nn.RNNBase]] = nn.LSTM

    def make_core(self, inputs: int, width: int) -> None:
        self.rnn = self.core(inputs, width, num_layers=1, batch_first=True)

    def cell(self) -> Cell:
        """A NumPy step of this model's recurrent layer, for the online readers."""
        return cell_of(self.rnn)


def detached(state: Any) -> Any:
    """A recurrent state cut from its graph: (h, c) for an LSTM, h for a GRU."""
    return tuple(h.detach() for h in state) if isinstance(state, tuple) else state.detach()
