"""The `softarm` command line (installed as `softarm_cli`): parses, calls the softarm library, prints."""
