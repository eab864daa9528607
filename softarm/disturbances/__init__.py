"""The world acting on the body (docs/model.md, Disturbances): one module per kind, holding its class (its keys,
how a seed draws it, its effect in NumPy for the reference) and its kernel code. A new kind is its module and
its line in KINDS; the simulator's kind codes are the positions in KINDS."""

from softarm.disturbances.drag import Drag
from softarm.disturbances.kind import Disturbance
from softarm.disturbances.obstacle import Obstacle
from softarm.disturbances.payload import Payload
from softarm.disturbances.push import Push
from softarm.disturbances.stiffness import Stiffness

KINDS: dict[str, type[Disturbance]] = {k.kind: k for k in (Push, Payload, Stiffness, Obstacle, Drag)}

__all__ = ["KINDS", "Disturbance", "Drag", "Obstacle", "Payload", "Push", "Stiffness"]
