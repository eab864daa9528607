"""Imagination: what the arm pictures of its body from its stretch sensors alone. The `Imaginer` puts a
checkpoint's networks together, `TrainedModel` opens one ready to answer a recording, the answers are scored
against the baselines; replay imagines a whole recording, scored against the camera and written as MCAP, the
streamer one sample at a time."""
