"""The trained model's parts, in one room: the networks, the input channels it reads with their scalers, the
checkpoint, the baselines every answer is judged against, its answers (`Prediction`) and the metrics.

`softarm.learn` trains what is here; `softarm.imagine` puts the parts together into an `Imaginer` and answers
with a checkpoint (replay, the streamer), `softarm.trust` says how far to trust the answers. A latent model is
one class and one line of `registry`, an input channel likewise.
"""
