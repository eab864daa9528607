"""Training settings small enough for a test: seconds on 2 cores, still enough to learn."""

import json

# fp32, not "auto": the tests compare one run with another, and auto's timing may choose differently each time
# where the two arithmetics run about as fast (a Zen 4 with AVX-512 BF16 does; a resumed run keeps its own choice)
TINY = {"train.epochs_ae": 10, "train.epochs_lstm": 12, "train.batch_ae": 32, "train.latent": 8,
        "train.lstm_hidden": 32, "train.lr_ae": 0.003, "train.precision": "fp32"}


def tiny_toml() -> str:
    """TINY as the `[train]` table of a config file (for `softarm train --config`)."""
    return "[train]\n" + "".join(f"{key.split('.')[1]} = {json.dumps(value)}\n" for key, value in TINY.items())
