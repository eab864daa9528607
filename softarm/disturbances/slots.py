"""The disturbances of a batch on the simulator: packed into slots (per arm, padded to the most any arm has), and
the Taichi functions the force step calls, which hand each slot to its kind's kernel hook (kind.py).

A slot is a kind code (its position in KINDS; -1: empty), the interval [start, end), the kind's parameters and
masks of the nodes and springs it touches. A batch without any keeps one empty slot of one node and one spring,
and its kernel is compiled without this code. The sums run over the slots in order, loads first, then the forces
on free nodes, so the kernel's arithmetic is the same whichever kinds a build lists.
"""

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
import taichi as ti

from softarm.disturbances import KINDS, Disturbance
from softarm.disturbances.kind import PARAMETERS

CODES = {cls: code for code, cls in enumerate(KINDS.values())}
LOADS = [k for k in KINDS.values() if k.load_on_node is not None]
FACTORS = [k for k in KINDS.values() if k.factor_on_spring is not None]
FIELDS = [k for k in KINDS.values() if k.force_on_free_node is not None]
LOAD_BITS, FACTOR_BITS, FIELD_BITS = (sum(1 << CODES[k] for k in kinds) for kinds in (LOADS, FACTORS, FIELDS))


@dataclass(frozen=True)
class Slots:
    codes: np.ndarray     # (A, D) int32, -1 empty
    windows: np.ndarray   # (A, D, 2) float64 [start, end)
    params: np.ndarray    # (A, D, PARAMETERS) float64
    nodes: np.ndarray     # (A, D, N) int32 masks
    springs: np.ndarray   # (A, D, S) int32 masks

    @property
    def any(self) -> bool:
        return bool((self.codes >= 0).any())


def pack(disturbances: Sequence[Sequence[Disturbance]], arms: int, nodes: int, springs: int) -> Slots:
    """Every arm's disturbances in slots; `disturbances` may be empty (no arm has any)."""
    per_arm = list(disturbances) or [[] for _ in range(arms)]
    slots = max([1, *(len(d) for d in per_arm)])
    if not any(per_arm):
        nodes = springs = 1
    codes = np.full((arms, slots), -1, np.int32)
    windows = np.zeros((arms, slots, 2))
    params = np.zeros((arms, slots, PARAMETERS))
    node_masks = np.zeros((arms, slots, nodes), np.int32)
    spring_masks = np.zeros((arms, slots, springs), np.int32)
    for a, arm in enumerate(per_arm):
        for d, disturbance in enumerate(arm):
            codes[a, d] = CODES[type(disturbance)]
            windows[a, d] = (disturbance.start, math.inf if disturbance.end is None else disturbance.end)
            params[a, d], node_masks[a, d], spring_masks[a, d] = disturbance.slot(nodes, springs)
    return Slots(codes, windows, params, node_masks, spring_masks)


@ti.data_oriented
class WorldFields:
    """The slots of a batch as Taichi fields, in a tree of their own (`destroy` frees it)."""

    def __init__(self, slots: Slots):
        arms, count = slots.codes.shape
        self.codes = ti.field(ti.i32)
        self.windows = ti.Vector.field(2, ti.f64)
        self.params = ti.Vector.field(PARAMETERS, ti.f64)
        self.nodes, self.springs = ti.field(ti.i32), ti.field(ti.i32)
        builder = ti.FieldsBuilder()
        builder.dense(ti.ij, (arms, count)).place(self.codes, self.windows, self.params)
        builder.dense(ti.ijk, slots.nodes.shape).place(self.nodes)
        builder.dense(ti.ijk, slots.springs.shape).place(self.springs)
        self._tree = builder.finalize()
        for field, values in ((self.codes, slots.codes), (self.windows, slots.windows), (self.params, slots.params),
                              (self.nodes, slots.nodes), (self.springs, slots.springs)):
            field.from_numpy(np.ascontiguousarray(values))

    def destroy(self) -> None:
        self._tree.destroy()


@ti.func
def is_active(a: int, d: int, t: ti.f64, world: ti.template()) -> bool:
    return world.codes[a, d] >= 0 and world.windows[a, d][0] <= t and t < world.windows[a, d][1]


@ti.func
def active_kinds(a: int, t: ti.f64, world: ti.template()) -> int:
    """Bit k set: a disturbance of kind code k is active for arm a at run time t."""
    bits = 0
    for d in range(world.codes.shape[1]):
        if is_active(a, d, t, world):
            bits |= 1 << world.codes[a, d]
    return bits


@ti.func
def node_load(a: int, i: int, t: ti.f64, bits: int, world: ti.template()) -> ti.math.vec3:
    """(extra mass, Fx, Fy) of every active load on node i of arm a at t."""
    load = ti.Vector([0.0, 0.0, 0.0], ti.f64)
    if bits & LOAD_BITS:
        for d in range(world.codes.shape[1]):
            if world.nodes[a, d, i] and is_active(a, d, t, world):
                for kind in ti.static(LOADS):
                    if world.codes[a, d] == ti.static(CODES[kind]):
                        load += kind.load_on_node(world.params[a, d])
    return load


@ti.func
def spring_factor(a: int, s: int, t: ti.f64, bits: int, world: ti.template()) -> ti.f64:
    """The product of every active factor on spring s's stiffness."""
    factor = 1.0
    if bits & FACTOR_BITS:
        for d in range(world.codes.shape[1]):
            if world.springs[a, d, s] and is_active(a, d, t, world):
                for kind in ti.static(FACTORS):
                    if world.codes[a, d] == ti.static(CODES[kind]):
                        factor *= kind.factor_on_spring(world.params[a, d])
    return factor


@ti.func
def free_node_force(a: int, t: ti.f64, x: ti.math.vec2, v: ti.math.vec2, bits: int,
                    world: ti.template()) -> ti.math.vec2:
    """The sum of every active state-dependent force on a free node at x moving at v (contact, drag)."""
    f = ti.Vector([0.0, 0.0], ti.f64)
    if bits & FIELD_BITS:
        for d in range(world.codes.shape[1]):
            if is_active(a, d, t, world):
                for kind in ti.static(FIELDS):
                    if world.codes[a, d] == ti.static(CODES[kind]):
                        f += kind.force_on_free_node(world.params[a, d], x, v)
    return f
