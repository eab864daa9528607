"""Benchmarks: every figure a ratio against a reference measured in the same run (run each as
`python -m bench.NAME`)."""
