"""Recording: one MCAP file per arm in the softarm-recording format (docs/recording.md), written beside
the simulation by a child process and read back, truncated files included, by `reader`."""
