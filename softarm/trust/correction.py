"""The forward model's learned correction: a small network on the same lagged inputs, fitted to what the ridge
regression leaves. The arm's dynamics are nonlinear beyond the products of the newest sample; on a motion new to
it the ridge's residual is structured, and it swamps the few hundredths of a spread a push adds to each sample.
The network takes most of that structure (docs/model.md, Surprise). Fitted with torch at training time, applied
in NumPy (replay, `evaluate`, the streamer), with its gradient for the sensors' noise.
"""

import math
from dataclasses import dataclass
from typing import Any, Optional, Sequence

import numpy as np

HIDDEN = 256     # units of each of its two hidden layers
EPOCHS = 40      # passes over the rows it is fitted on ...
MAX_STEPS = 12_000  # ... but no more optimisation steps than this
BATCH = 1024     # rows a step
RATE = 1e-3      # Adam's step size, annealed to 0 on a cosine
SEED = 0         # its initial weights and the batches' order


def _silu(h: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """SiLU of h and its derivative."""
    s = 1.0 / (1.0 + np.exp(-h))
    return h * s, s * (1.0 + h * (1.0 - s))


@dataclass(frozen=True)
class Correction:
    mean: np.ndarray    # (L,) the inputs' mean it standardises by
    std: np.ndarray     # (L,) and their spread
    layers: tuple[tuple[np.ndarray, np.ndarray], ...]  # (weight (out, in), bias (out,)), SiLU between them
    gain: np.ndarray    # (P,) the output's units: each target's spread when fitted

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """(n, P) the correction of each row of linear inputs (n, L)."""
        a = (x - self.mean) / self.std
        for w, b in self.layers[:-1]:
            a = _silu(a @ w.T + b)[0]
        w, b = self.layers[-1]
        return (a @ w.T + b) * self.gain

    def gradient(self, x: np.ndarray, columns: Sequence[int]) -> np.ndarray:
        """(n, len(columns), P) d correction / d x at each row, for the input columns named."""
        a = (x - self.mean) / self.std
        slopes = []
        for w, b in self.layers[:-1]:
            a, slope = _silu(a @ w.T + b)
            slopes.append(slope)
        (w1, _), *middle, (last, _) = self.layers
        back = np.broadcast_to(last * self.gain[:, None], (len(x), *last.shape))  # (n, P, H)
        for (w, _), slope in zip(reversed(middle), reversed(slopes[1:])):
            back = (back * slope[:, None, :]) @ w
        cols = list(columns)
        through = (back * slopes[0][:, None, :]) @ (w1[:, cols] / self.std[cols])  # (n, P, C)
        return through.transpose(0, 2, 1)

    def to_state(self) -> dict[str, Any]:
        return {"mean": self.mean, "std": self.std, "gain": self.gain, "layers": [[w, b] for w, b in self.layers]}

    @classmethod
    def from_state(cls, state: dict[str, Any]) -> "Correction":
        layers = tuple((np.asarray(w, np.float64), np.asarray(b, np.float64)) for w, b in state["layers"])
        return cls(np.asarray(state["mean"], np.float64), np.asarray(state["std"], np.float64), layers,
                   np.asarray(state["gain"], np.float64))


def fit_correction(x: np.ndarray, y: np.ndarray, device: Optional[str] = None) -> Correction:
    """The network fitted to targets y (n, P) from linear inputs x (n, L) by Adam on the mean squared error in
    units of each target's spread; seeded, so a refit on the same rows and device is the same network."""
    import torch  # the fit alone needs torch: applying the correction is NumPy

    device = torch.device(device or "cpu")
    mean, std = x.mean(axis=0), np.maximum(x.std(axis=0), 1e-9)
    gain = np.maximum(y.std(axis=0), 1e-12)
    generator = torch.Generator().manual_seed(SEED)
    inputs = torch.as_tensor((x - mean) / std, dtype=torch.float32, device=device)
    targets = torch.as_tensor(y / gain, dtype=torch.float32, device=device)
    with torch.random.fork_rng(devices=[]):
        torch.manual_seed(SEED)
        net = torch.nn.Sequential(torch.nn.Linear(x.shape[1], HIDDEN), torch.nn.SiLU(),
                                  torch.nn.Linear(HIDDEN, HIDDEN), torch.nn.SiLU(),
                                  torch.nn.Linear(HIDDEN, y.shape[1])).to(device)
    per_epoch = math.ceil(len(x) / BATCH)
    steps = min(EPOCHS * per_epoch, MAX_STEPS)
    optimiser = torch.optim.Adam(net.parameters(), RATE)
    schedule = torch.optim.lr_scheduler.CosineAnnealingLR(optimiser, steps)
    step = 0
    while step < steps:
        order = torch.randperm(len(x), generator=generator).to(device)
        for start in range(0, len(x), BATCH):
            batch = order[start:start + BATCH]
            loss = ((net(inputs[batch]) - targets[batch]) ** 2).mean()
            optimiser.zero_grad()
            loss.backward()
            optimiser.step()
            schedule.step()
            step += 1
            if step == steps:
                break
    linears = [m for m in net if isinstance(m, torch.nn.Linear)]
    layers = tuple((m.weight.detach().cpu().double().numpy(), m.bias.detach().cpu().double().numpy())
                   for m in linears)
    return Correction(mean, std, layers, gain)
