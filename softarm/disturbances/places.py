"""Where on the body a disturbance acts: nodes, rows, segments of springs and the arm's edge, by index and
by row (node = row * columns + column), checked against the body; errors name the config key they came from."""

from dataclasses import dataclass, replace
from typing import Any, Optional, Sequence

import numpy as np

from softarm.arm.body import Body
from softarm.config import WorldConfig
from softarm.errors import ConfigError


@dataclass(frozen=True)
class Places:
    body: Body
    columns: int
    hanging: np.ndarray   # (N, 2): the arm hanging at rest, where obstacles are placed beside it
    world: WorldConfig
    key: str = "disturbances"  # the table being read, for messages

    def at(self, key: str) -> "Places":
        return replace(self, key=key)

    @property
    def rows(self) -> int:
        return self.body.n_nodes // self.columns

    def require(self, ok: bool, name: str, value: Any, allowed: str) -> None:
        if not ok:
            raise ConfigError(f"config key '{self.key}.{name}' = {value!r} is out of range: {allowed}")

    def present(self, name: str, value: Any, why: str) -> None:
        if value is None:
            raise ConfigError(f"config key '{self.key}.{name}' is missing: {why}")

    def nodes(self, indices: Optional[Sequence[int]], name: str) -> tuple[int, ...]:
        n = self.body.n_nodes
        self.require(indices is not None and len(indices) > 0, name, indices, "list at least one node")
        bad = [i for i in indices if not 0 <= i < n]
        self.require(not bad, name, list(indices),
                     f"names node {bad[0] if bad else ''}, but the body has nodes 0..{n - 1}")
        return tuple(int(i) for i in indices)

    def springs(self, indices: Optional[Sequence[int]], name: str) -> tuple[int, ...]:
        s = len(self.body.springs)
        self.require(indices is not None and len(indices) > 0, name, indices, "list at least one spring")
        bad = [i for i in indices if not 0 <= i < s]
        self.require(not bad, name, list(indices),
                     f"names spring {bad[0] if bad else ''}, but the body has springs 0..{s - 1} "
                     f"(the model's spring list)")
        return tuple(int(i) for i in indices)

    def row(self, row: int) -> tuple[int, ...]:
        """The nodes of one row (0: the top)."""
        self.require(0 <= row < self.rows, "rows", row, f"rows are 0..{self.rows - 1}")
        return tuple(range(row * self.columns, (row + 1) * self.columns))

    def segment(self, first: int, span: int) -> tuple[int, ...]:
        """Every spring with both ends in rows first .. first + span (the cells between them)."""
        self.require(0 <= first < self.rows - 1 and span >= 1, "rows", [first, span],
                     f"a segment starts at a row in 0..{self.rows - 2} and spans at least one row")
        rows = self.body.springs // self.columns
        last = min(first + span, self.rows - 1)
        return tuple(int(k) for k in np.flatnonzero((rows >= first).all(axis=1) & (rows <= last).all(axis=1)))

    def edge(self, row: int, side: int) -> np.ndarray:
        """The hanging arm's outer node of a row on one side (-1: left, 1: right)."""
        nodes = self.row(row)
        return self.hanging[nodes[0] if side < 0 else nodes[-1]]

    def driven(self) -> np.ndarray:
        return self.hanging[self.body.driven]
