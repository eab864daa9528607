"""Training settings small enough for a test: seconds on 2 cores, still enough to learn."""

TINY = {"train.epochs_ae": 10, "train.epochs_lstm": 12, "train.batch_ae": 32, "train.latent": 8,
        "train.lstm_hidden": 32, "train.lr_ae": 0.003}
