"""The trained model and how it answers, in one room: the networks, the input channels it reads with their
scalers, the checkpoint, the `Imaginer`, the baselines every answer is judged against, the metrics and one
scorer of the four answers (model, ridge, mean frame, AE ceiling).

`softarm.learn` trains what is here; `softarm.imagine` (replay, the streamer) and `softarm.suite` use a
checkpoint of it. A latent model is one class and one line of `registry`, an input channel likewise.
"""
