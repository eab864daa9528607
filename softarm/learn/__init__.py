"""Training: the autoencoder on camera frames, then a latent model from input windows or streams to the
frames' codes (`softarm.model` holds what is trained); the learning data, the loop, exact resume, a
wall-clock budget and the held-out metrics written beside the checkpoint."""
