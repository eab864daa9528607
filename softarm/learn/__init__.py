"""Learning: a convolutional autoencoder compresses camera frames, an LSTM maps stretch windows to the
next frame's code; datasets, training loop, checkpoints, metrics and the baselines they are judged by."""
