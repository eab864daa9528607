"""Imagination: what the arm pictures of its body from its stretch sensors alone, over a whole
recording, scored against the camera and written as MCAP (`replay`)."""
