"""Where a sensor study puts its stretch sensors: node pairs from the body's grid (rows x columns, row 0 the
driven top, node = row * columns + column), each joining a node to one further down the arm, so that
every sensor measures a real stretch along the arm.

- `edges`: along the two outer edges, each edge cut into equal segments (half the sensors on each side,
  left and right in turn; four are the default sensors), so bending either way stretches one side and
  compresses the other.
- `spread`: one segment after another down the whole arm, taking the left edge, the right edge and the
  middle column in turn: every part of the arm gets a sensor, on every line of it.
- `random`: seeded random pairs of nearby nodes (at most MAX_SPAN rows apart, any columns).

Bend sensors (`bend_triples`) lie along the middle column, rows 1 to the tip cut into equal segments, each
sensor reading the turn between its segment's ends.
"""

import numpy as np

from softarm.config import Config

PLACEMENTS = ("edges", "spread", "random")
MAX_SPAN = 3        # rows between the two nodes of a random pair, at most
RANDOM_SEED = 14    # with the count: each count's random layout is fixed


def sensor_pairs(placement: str, count: int, config: Config) -> list[list[int]]:
    """`count` node pairs [upper, lower] for the placement, on the body of `config`."""
    rows, columns = config.body.rows, config.body.columns
    if placement == "edges":
        left = _segments((count + 1) // 2, [0], columns, rows)
        right = _segments(count // 2, [columns - 1], columns, rows)
        return [pair for k, upper in enumerate(left) for pair in [upper, *right[k:k + 1]]]
    if placement == "spread":
        return _segments(count, [0, columns - 1, columns // 2], columns, rows)
    if placement == "random":
        return _random_pairs(count, columns, rows)
    raise ValueError(f"unknown placement {placement!r}")


def bend_triples(count: int, config: Config) -> list[list[int]]:
    """`count` bend sensors [top, middle, bottom] down the middle column, one a segment of the arm."""
    rows, columns = config.body.rows, config.body.columns
    if not 1 <= count <= (rows - 2) // 2:
        raise ValueError(f"{count} bend sensors of two rows or more do not fit between rows 1 and {rows - 1}")
    bounds = [1 + (rows - 2) * k // count for k in range(count + 1)]
    middle = columns // 2
    return [[row * columns + middle for row in (top, (top + bottom) // 2, bottom)]
            for top, bottom in zip(bounds[:-1], bounds[1:])]


def _segments(count: int, lines: list[int], columns: int, rows: int) -> list[list[int]]:
    """Rows 1 (below the driven row) to the tip cut into `count` segments down the arm, segment k on
    column lines[k % len(lines)]."""
    if count == 0:
        return []
    if count > rows - 2:
        raise ValueError(f"{count} segments do not fit between rows 1 and {rows - 1}")
    bounds = [1 + (rows - 2) * k // count for k in range(count + 1)]
    return [[bounds[k] * columns + lines[k % len(lines)], bounds[k + 1] * columns + lines[k % len(lines)]]
            for k in range(count)]


def _random_pairs(count: int, columns: int, rows: int) -> list[list[int]]:
    rng = np.random.default_rng([RANDOM_SEED, count])
    pairs: list[list[int]] = []
    while len(pairs) < count:
        top = int(rng.integers(1, rows - 1))
        bottom = min(rows - 1, top + int(rng.integers(1, MAX_SPAN + 1)))
        pair = [top * columns + int(rng.integers(columns)), bottom * columns + int(rng.integers(columns))]
        if pair not in pairs:
            pairs.append(pair)
    return pairs
