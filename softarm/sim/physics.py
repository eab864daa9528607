"""Taichi simulator: many arms stepped together by semi-implicit Euler (docs/model.md, Forces, Integration).

One kernel launch advances every arm a block of frames, in one of two memory layouts (sim/layout.py). On the CPU
("lanes"), the outer loop runs over groups of arms in parallel; a group's substeps are a tight serial loop, because
~160 springs are too few to split across threads on a CPU, and within it the group's arms are stepped side by side,
which the compiler vectorises (sim/forces.py; batches without disturbances or muscles). On a GPU ("gathered"), every
arm is a thread, the arms lie innermost in memory so that a warp's loads coalesce, and each node gathers its springs'
forces from two state buffers (sim/gathered.py). Both give the same numbers; fields are indexed [arm, node].
"""

from functools import partial
from typing import Optional, Sequence, Union

import numpy as np
import taichi as ti

from softarm.arm.body import Body
from softarm.arm.drive import KIND_CODES, Drive
from softarm.arm.muscles import Muscles
from softarm.config import Config
from softarm.disturbances import Disturbance
from softarm.disturbances.slots import WorldFields, pack
from softarm.sim.batch import ArmBatch, arm_batch
from softarm.sim.capacity import check_physics, raise_on_blowup
from softarm.sim.exchange import Exchange
from softarm.sim.forces import accumulate_forces, first_far_node, substep
from softarm.sim.gathered import advance_gathered
from softarm.sim.layout import chosen_layout, place_incidence, place_state
from softarm.sim.load import load
from softarm.sim.muscle_fields import MuscleFields, relax
from softarm.sim.runtime import device_array, host, on_cpu, task_layout, upload

f64nd = ti.types.ndarray(dtype=ti.f64, ndim=4)
i32nd = ti.types.ndarray(dtype=ti.i32, ndim=2)


@ti.data_oriented
class Simulator(Exchange):
    """Owns the state of a batch of arms on the Taichi device and steps it block by block.

    The state lives in Taichi fields whose shapes are fixed per simulator, so the kernel's index
    arithmetic is constant (faster than ndarrays with runtime shapes: README, Benchmarks), at the price of one
    kernel compile per simulator (Taichi's offline cache keeps it for the next run of the same shape).
    `history` holds the last block's positions, (arms, block_frames, N, 2): on the CPU the kernel writes
    it in place (no copy), on a GPU it is the host copy of a device array. With `muscles` (a batch a controller
    commands through `command`), the kernel relaxes their activations and shortens their springs; without, it is
    compiled without that code, as the recordings' runs are.
    """

    def __init__(self, body: Body, drives: Sequence[Drive], frame_dt: float, substeps: int,
                 blowup_distance: float, positions: np.ndarray, velocities: np.ndarray, block_frames: int = 100,
                 disturbances: Sequence[Sequence[Disturbance]] = (), muscles: Optional[Muscles] = None,
                 layout: Optional[str] = None):
        arms, n, springs = len(drives), body.n_nodes, len(body.springs)
        check_physics(arms, n, block_frames, on_gpu=not on_cpu())
        slots = pack(disturbances, arms, n, springs)
        self.disturbed = slots.any  # a batch without any compiles the kernel without their code
        if len({(d.kind, d.direction, len(d.frequencies)) for d in drives}) != 1:
            raise ValueError("all arms of a batch share the excitation kind, direction and component count")
        self.kind = KIND_CODES[drives[0].kind]
        self.body, self.frame_dt, self.substeps, self.blowup_distance = body, frame_dt, substeps, blowup_distance
        self.arms, self.block_frames, self.frame = arms, block_frames, 0
        self.layout = chosen_layout(layout)  # lanes on the CPU, gathered on a GPU (sim/layout.py)
        self.rest = ti.Vector.field(2, ti.f64)
        self.springs, self.spring_params = ti.Vector.field(2, ti.i32), ti.Vector.field(3, ti.f64)
        self.mass, self.amplitude, self.time_offset = (ti.field(ti.f64) for _ in range(3))
        self.freqs, self.amps, self.phases = (ti.field(ti.f64) for _ in range(3))
        self.direction = ti.Vector.field(2, ti.f64, shape=())
        self.free = ti.field(ti.i32)
        self.muscles = muscles if muscles is not None and muscles.count else None
        builder = ti.FieldsBuilder()
        groups = place_state(self, builder, arms, n, plain=not self.disturbed and self.muscles is None)
        incidence = place_incidence(self, builder, body.springs, n)
        builder.dense(ti.i, n).place(self.rest, self.mass, self.free)
        builder.dense(ti.i, springs).place(self.springs, self.spring_params)
        builder.dense(ti.i, arms).place(self.amplitude, self.time_offset)
        builder.dense(ti.ij, (arms, len(drives[0].frequencies))).place(self.freqs, self.amps, self.phases)
        self._tree = builder.finalize()
        self.world = WorldFields(slots) if self.disturbed else None
        self._attach(arms, n)
        f64 = partial(np.ascontiguousarray, dtype=np.float64)
        load(self, f64(np.broadcast_to(positions, (arms, n, 2))), f64(np.broadcast_to(velocities, (arms, n, 2))),
             f64(body.rest), f64(body.masses), np.ascontiguousarray(body.free, np.int32),
             np.ascontiguousarray(body.springs, np.int32),
             f64(np.stack([body.rest_lengths, body.stiffness, body.damping], axis=1)),
             f64([[d.amplitude, d.time_offset] for d in drives]),
             f64([[d.frequencies for d in drives], [d.amplitudes or np.zeros(len(d.frequencies)) for d in drives],
                  [d.phases or np.zeros(len(d.frequencies)) for d in drives]]), f64(drives[0].direction))
        if incidence is not None:
            self.incident_start.from_numpy(incidence[0])
            self.incident.from_numpy(incidence[1])
        self._positions = device_array((arms, block_frames, n, 2), "float64")
        self._status = upload(np.full((arms, 2), -1, np.int32))
        self.history = host(self._positions)
        self._tasks = task_layout(groups)

    def _attach(self, arms: int, n: int) -> None:
        """The muscles' fields (only with groups) and the arrays a controller reads the state through."""
        self.actuators = MuscleFields(self.muscles, arms) if self.muscles is not None else None
        self._state = [device_array((arms, n, 2), "float64") for _ in range(2)]
        self._activation = device_array((arms, self.muscles.count), "float64") if self.muscles is not None else None

    @classmethod
    def from_config(cls, config: Config, batch: Optional[ArmBatch] = None, block_frames: int = 100,
                    muscles: Optional[Muscles] = None, layout: Optional[str] = None) -> "Simulator":
        """The arms of `batch` (default: the config's run) started and stepped exactly as `simulate` does (with
        `muscles`, also commanded through `command`; `layout` forces one, see sim/layout.py)."""
        batch = batch if batch is not None else arm_batch(config)
        integration = config.integration
        return cls(batch.body, batch.drives, integration.frame_dt, integration.substeps, integration.blowup_distance,
                   batch.positions, batch.velocities, block_frames, batch.disturbances, muscles, layout)

    @ti.kernel
    def _advance(self, positions: f64nd, status: i32nd, first_frame: ti.i32, n_frames: ti.i32, substeps: ti.i32,
                 frame_dt: ti.f64,
                 blowup_distance: ti.f64, gx: ti.f64, gy: ti.f64, kind: ti.i32, tasks: ti.i32, spacing: ti.i32,
                 decay: ti.f64, lanes: ti.template(), disturbed: ti.template(), muscled: ti.template()):
        """Record each arm's state as frames first_frame.. into positions[:, :n_frames], stepping between them.

        Task k (at slot k * spacing, see runtime.task_layout) steps the groups of arms k, k + tasks, ... in turn.
        status[a] = (-1, -1) while arm a is healthy, else (frame, node) of its first blow-up; a group stops
        stepping when all its arms blew up (step_block raises on the first). Forces are those of the substep's
        start, at run time (k substeps + s) h, with the muscles' activations relaxed over the substep first
        (decay = exp(-h / tau)).
        """
        h = frame_dt / substeps
        groups = self.x.shape[0] // lanes
        for slot in range(tasks * spacing):
            if slot % spacing == 0:
                task = slot // spacing
                for j in range((groups - task + tasks - 1) // tasks):
                    base = (task + j * tasks) * lanes
                    for f in range(n_frames):
                        healthy = 0
                        for w in ti.static(range(lanes)):
                            for i in range(self.x.shape[1]):
                                positions[base + w, f, i, 0] = self.x[base + w, i][0]
                                positions[base + w, f, i, 1] = self.x[base + w, i][1]
                            healthy += status[base + w, 0] < 0
                        if healthy:
                            k = first_frame + f
                            for s in range(substeps):
                                self._substep(base, lanes, k * substeps + s, substeps, frame_dt, h, gx, gy, kind,
                                              decay, disturbed, muscled)
                            for w in ti.static(range(lanes)):
                                far = first_far_node(base + w, self.x, self.rest, self.free, blowup_distance)
                                if far >= 0 and status[base + w, 0] < 0:
                                    status[base + w, 0] = k + 1
                                    status[base + w, 1] = far

    @ti.func
    def _substep(self, base: int, lanes: ti.template(), step: int, substeps: int, frame_dt: ti.f64, h: ti.f64,
                 gx: ti.f64, gy: ti.f64, kind: int, decay: ti.f64, disturbed: ti.template(), muscled: ti.template()):
        """Substep number `step` of the run for the group of arms base.. (forces at its start, drive at its end)."""
        now = ti.cast(step, ti.f64) / substeps * frame_dt
        if ti.static(muscled):
            for w in ti.static(range(lanes)):
                relax(base + w, decay, self.actuators)
        accumulate_forces(base, lanes, now, self.x, self.v, self.force, self.inertia, self.springs,
                          self.spring_params, self.mass, self.free, gx, gy, self.world, disturbed, self.actuators,
                          muscled)
        t = ti.cast(step + 1, ti.f64) / substeps * frame_dt
        substep(base, lanes, t, h, kind, self.x, self.v, self.force, self.inertia, self.rest, self.mass, self.free,
                self.amplitude, self.time_offset, self.freqs, self.amps, self.phases, self.direction, disturbed)

    def step_block(self, n_frames: int) -> None:
        """Fill `history[:, :n_frames]` with the next n_frames frames and step past them (history is reused:
        read it before the next call)."""
        self.launch(n_frames)
        self.collect()

    def launch(self, n_frames: int) -> None:
        """Start stepping the next n_frames frames into `device_positions`; on a GPU the kernel runs while Python
        goes on, until `collect` (or anything that reads the device) waits for it."""
        if not 1 <= n_frames <= self.block_frames:
            raise ValueError(f"a block holds 1..{self.block_frames} frames, got {n_frames}")
        gx, gy = self.body.gravity
        h = self.frame_dt / self.substeps
        decay = float(np.exp(-h / self.muscles.time_constant)) if self.muscles is not None else 0.0
        if self.layout == "gathered":
            advance_gathered(self, self._positions, self._status, self.frame, n_frames, self.substeps, self.frame_dt,
                             self.blowup_distance, float(gx), float(gy), self.kind, decay, self.disturbed,
                             self.muscles is not None)
        else:
            self._advance(self._positions, self._status, self.frame, n_frames, self.substeps, self.frame_dt,
                          self.blowup_distance, float(gx), float(gy), self.kind, *self._tasks, decay, self.lanes,
                          self.disturbed, self.muscles is not None)
        self._launched = n_frames

    def collect(self) -> np.ndarray:
        """Wait for the launched block, make its frames `history` (on a GPU: copied to the host) and step past
        them; a blow-up raises SimulationError."""
        self.history = host(self._positions)
        self.frame += self._launched
        raise_on_blowup(host(self._status), self.arms, self.frame_dt, self.blowup_distance, self.substeps)
        return self.history

    @property
    def device_positions(self) -> Union[np.ndarray, ti.Ndarray]:
        """The launched block's positions where the kernel writes them: the rasteriser reads them there, so a GPU's
        frames are drawn without a round trip through the host."""
        return self._positions

    def advance(self, n_frames: int) -> np.ndarray:
        """(arms, n_frames, N, 2) positions at the next n_frames frame times, float64."""
        out = []
        while n_frames > 0:
            block = min(n_frames, self.block_frames)
            self.step_block(block)
            out.append(self.history[:, :block].copy())  # the next block overwrites history in place
            n_frames -= block
        return np.concatenate(out, axis=1)

    def close(self) -> None:
        """Free the fields; a process that makes many simulators (a notebook, the tests) should call it."""
        self._tree.destroy()
        for owned in (self.world, self.actuators):
            if owned is not None:
                owned.destroy()
