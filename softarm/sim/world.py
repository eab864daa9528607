"""The disturbances of a batch on the simulator: packed into slots (per arm, padded to the most any arm has),
and the Taichi functions that read them in the force step (docs/model.md, Disturbances).

A slot is a kind code (-1: empty), the interval [start, end), six parameters (push: Fx, Fy; payload: mass;
stiffness: factor; obstacle: cx, cy, radius, k_c, b_c) and masks of the nodes and springs it touches. A batch
without any keeps one empty slot of one node and one spring, and its kernel is compiled without this code.
"""

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
import taichi as ti

from softarm.arm.disturbances import PARAMETERS, Disturbance, Obstacle, Payload, Push, Stiffness

PUSH, PAYLOAD, STIFFNESS, OBSTACLE = Push.code, Payload.code, Stiffness.code, Obstacle.code


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
            codes[a, d] = disturbance.code
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
def is_active(a: int, d: int, t: ti.f64, codes: ti.template(), windows: ti.template()) -> bool:
    return codes[a, d] >= 0 and windows[a, d][0] <= t and t < windows[a, d][1]


@ti.func
def active_kinds(a: int, t: ti.f64, codes: ti.template(), windows: ti.template()) -> int:
    """Bit k set: a disturbance of kind code k is active for arm a at run time t."""
    bits = 0
    for d in range(codes.shape[1]):
        if is_active(a, d, t, codes, windows):
            bits |= 1 << codes[a, d]
    return bits


@ti.func
def node_load(a: int, i: int, t: ti.f64, bits: int, codes: ti.template(), windows: ti.template(),
              params: ti.template(), nodes: ti.template()) -> ti.math.vec3:
    """(payload mass, push Fx, push Fy) on node i of arm a at t."""
    load = ti.Vector([0.0, 0.0, 0.0], ti.f64)
    if bits & ((1 << PAYLOAD) | (1 << PUSH)):
        for d in range(codes.shape[1]):
            if nodes[a, d, i] and is_active(a, d, t, codes, windows):
                p = params[a, d]
                if codes[a, d] == PAYLOAD:
                    load[0] += p[0]
                elif codes[a, d] == PUSH:
                    load[1] += p[0]
                    load[2] += p[1]
    return load


@ti.func
def spring_factor(a: int, s: int, t: ti.f64, bits: int, codes: ti.template(), windows: ti.template(),
                  params: ti.template(), springs: ti.template()) -> ti.f64:
    factor = 1.0
    if bits & (1 << STIFFNESS):
        for d in range(codes.shape[1]):
            if codes[a, d] == STIFFNESS and springs[a, d, s] and is_active(a, d, t, codes, windows):
                factor *= params[a, d][0]
    return factor


@ti.func
def contact(a: int, t: ti.f64, x: ti.math.vec2, v: ti.math.vec2, bits: int, codes: ti.template(),
            windows: ti.template(), params: ti.template()) -> ti.math.vec2:
    """Penalty force of every active obstacle on a node at x moving at v: max(0, k p - b v.n) n inside a disc."""
    f = ti.Vector([0.0, 0.0], ti.f64)
    if bits & (1 << OBSTACLE):
        for d in range(codes.shape[1]):
            if codes[a, d] == OBSTACLE and is_active(a, d, t, codes, windows):
                p = params[a, d]
                offset = x - ti.Vector([p[0], p[1]], ti.f64)
                distance = ti.sqrt(offset[0] * offset[0] + offset[1] * offset[1])
                if 0.0 < distance < p[2]:
                    n = offset * (1.0 / distance)
                    f += ti.max(0.0, p[3] * (p[2] - distance) - p[4] * v.dot(n)) * n
    return f
