"""Where a simulator's per-arm state lives in memory: the CPU's lanes or the GPU's arms-innermost layout.

- "lanes" (the CPU's): groups of up to four arms stepped side by side by one thread, one cell per group and
  node holding each coordinate of the group's arms contiguously, so the compiler packs the lanes into vector
  registers (`forces.accumulate_forces`, `forces.substep`).
- "gathered" (a GPU's): one thread per arm, every field `[arm, node]` stored node-major with the arms innermost,
  so that a warp's loads of one node are one contiguous run; two state buffers and no force array
  (`gathered.advance_gathered`).

Both compute the same numbers; the CPU can run either (the tests run the GPU's on it).
"""

from typing import Any, Optional

import numpy as np
import taichi as ti

from softarm.sim import runtime
from softarm.sim.gathered import incident_springs
from softarm.sim.runtime import lane_layout

LAYOUTS = ("lanes", "gathered")


def chosen_layout(layout: Optional[str]) -> str:
    """`layout` as asked, or the backend's own: lanes on the CPU, gathered on a GPU."""
    if layout is None:
        return "lanes" if runtime.on_cpu() else "gathered"
    if layout not in LAYOUTS:
        raise ValueError(f"layout {layout!r}: one of {LAYOUTS}")
    return layout


def place_state(sim: Any, builder: ti.FieldsBuilder, arms: int, n: int, plain: bool) -> int:
    """Create and place the simulator's per-arm state fields for `sim.layout`; the number of groups of arms a
    kernel task steps (every arm its own group but in CPU lanes). Only a plain batch (no disturbances, no
    muscles) is stepped in lanes: the others' per-arm branches do not vectorise, and their unrolled kernels took
    3-6x as long to compile."""
    sim.x, sim.v = ti.Vector.field(2, ti.f64), ti.Vector.field(2, ti.f64)
    if sim.layout == "gathered":
        sim.lanes = 1
        sim.x2, sim.v2 = ti.Vector.field(2, ti.f64), ti.Vector.field(2, ti.f64)
        builder.dense(ti.j, n).dense(ti.i, arms).place(sim.x, sim.v, sim.x2, sim.v2)
        return arms
    sim.force = ti.Vector.field(2, ti.f64)
    sim.lanes, groups = lane_layout(arms, plain)
    sim.inertia = ti.field(ti.f64) if sim.disturbed else sim.mass
    node = builder.dense(ti.i, groups).dense(ti.j, n)
    for field in (sim.x, sim.v, sim.force):
        for c in range(2):
            node.dense(ti.i, sim.lanes).place(field.get_scalar_field(c))
    if sim.disturbed:
        node.dense(ti.i, sim.lanes).place(sim.inertia)
    return groups


def place_incidence(sim: Any, builder: ti.FieldsBuilder, springs: np.ndarray, n: int) -> Optional[tuple]:
    """The gathered layout's CSR of each node's springs (`gathered.incident_springs`), placed; (starts, entries)
    to load, None for the lanes."""
    if sim.layout != "gathered":
        return None
    starts, entries = incident_springs(springs, n)
    sim.incident_start, sim.incident = ti.field(ti.i32), ti.field(ti.i32)
    builder.dense(ti.i, len(starts)).place(sim.incident_start)
    builder.dense(ti.i, len(entries)).place(sim.incident)
    return starts, entries
