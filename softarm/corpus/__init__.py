"""Training corpora: many arms, many kinds of motion, simulated in one command (`softarm corpus`), from seeds
below the held-out suite's."""
