"""A latent model that is not recurrent: a causal temporal convolution network over the last 2.56 s of samples.

`network.CausalTCN` is the model (the registry's "tcn"), `shape` its receptive field, `rows` cuts its training
data, `reader` streams it one sample at a time in NumPy with the answers of its batch replay.
"""

from softarm.model.tcn.network import CausalTCN

__all__ = ["CausalTCN"]
