"""The causal convolution network's shape: which past samples each state reads."""

KERNEL = 2                                     # taps of each convolution
DILATIONS = (1, 2, 4, 8, 16, 32, 64, 128)      # one layer each: the receptive field doubles layer by layer
RECEPTIVE = 1 + (KERNEL - 1) * sum(DILATIONS)  # 256 samples (2.56 s at 100 Hz) shape one state
