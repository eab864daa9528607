"""What several test modules share: running the CLI as a user would, reference runs, analytic bodies and the
tiny training settings."""
