"""The held-out imagination suite: a fixed, versioned set of motions no training corpus may use, and
the evaluation of a checkpoint on it beside trivial baselines (`softarm suite`, `softarm evaluate`)."""
