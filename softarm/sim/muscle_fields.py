"""The muscles of a batch on the simulator: each arm's commands and activations, and the Taichi functions that
relax the activations and shorten the springs (docs/model.md, Muscles)."""

import numpy as np
import taichi as ti

from softarm.arm.muscles import Muscles


@ti.data_oriented
class MuscleFields:
    """Per spring its group (-1: passive), per group its largest contraction, per arm and group the command u
    and the activation a; in a tree of their own (`destroy` frees it)."""

    def __init__(self, muscles: Muscles, arms: int):
        self.group, self.contraction = ti.field(ti.i32), ti.field(ti.f64)
        self.command, self.activation = ti.field(ti.f64), ti.field(ti.f64)
        builder = ti.FieldsBuilder()
        builder.dense(ti.i, len(muscles.group)).place(self.group)
        builder.dense(ti.i, muscles.count).place(self.contraction)
        builder.dense(ti.ij, (arms, muscles.count)).place(self.command, self.activation)
        self._tree = builder.finalize()
        self.group.from_numpy(np.ascontiguousarray(muscles.group, np.int32))
        self.contraction.from_numpy(np.ascontiguousarray(muscles.max_contraction, np.float64))
        zero = np.zeros((arms, muscles.count))
        self.command.from_numpy(zero)
        self.activation.from_numpy(zero)

    def destroy(self) -> None:
        self._tree.destroy()


@ti.func
def relax(a: int, decay: ti.f64, muscles: ti.template()):
    """One substep of da/dt = (u - a) / tau with u held: a <- u + (a - u) exp(-h / tau) (decay = exp(-h / tau))."""
    for g in range(muscles.activation.shape[1]):
        u = muscles.command[a, g]
        muscles.activation[a, g] = u + (muscles.activation[a, g] - u) * decay


@ti.func
def rest_scale(a: int, s: int, muscles: ti.template()) -> ti.f64:
    """The factor 1 - a c_max on spring s's rest length (1 for a passive spring)."""
    scale = 1.0
    g = muscles.group[s]
    if g >= 0:
        scale = 1.0 - muscles.activation[a, g] * muscles.contraction[g]
    return scale
