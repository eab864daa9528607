"""The hand-written C physics (physics_reference.c), built with the system compiler and called through ctypes.

The benchmark's "practical limit of one core": the same model and scheme as `softarm.sim.physics.Simulator`,
written as the tight serial loop a person would write by hand, arms one after another.

    sim = CReference(body, drives, frame_dt, substeps, positions, velocities)
    frames = sim.advance(100)  # (arms, 100, N, 2), like Simulator.advance
"""

import ctypes
import hashlib
import os
import shutil
import subprocess
import tempfile
from pathlib import Path
from typing import Optional, Sequence

import numpy as np

from softarm.arm.body import Body
from softarm.arm.drive import Drive
from softarm.config import Config
from softarm.sim.batch import ArmBatch

SOURCE = Path(__file__).with_name("physics_reference.c")
FLAGS = ("-O3", "-march=native", "-shared", "-fPIC")


class NoCompilerError(RuntimeError):
    pass


def find_compiler() -> Optional[str]:
    """Path of the system C compiler (`cc`, else `gcc`), or None."""
    return shutil.which("cc") or shutil.which("gcc")


def build_library() -> tuple[Path, tuple[str, ...]]:
    """Compile physics_reference.c into a cached shared library; (its path, the flags used).

    -march=native is tried first and dropped if the compiler refuses it. The library is cached in the
    temp folder under a hash of the source, the compiler and the flags, so a second run skips the build.
    """
    compiler = find_compiler()
    if compiler is None:
        raise NoCompilerError("the C reference needs a C compiler: no `cc` or `gcc` on PATH "
                              "(on Debian/Ubuntu: apt-get install gcc)")
    source = SOURCE.read_bytes()
    cache = Path(tempfile.gettempdir()) / "softarm-c-reference"
    cache.mkdir(exist_ok=True)
    errors = []
    for flags in (FLAGS, tuple(f for f in FLAGS if f != "-march=native")):
        key = hashlib.sha256(source + "\0".join((compiler,) + flags).encode()).hexdigest()[:16]
        library = cache / f"physics_reference-{key}.so"
        if library.exists():
            return library, flags
        partial = library.with_suffix(f".{os.getpid()}.tmp")
        result = subprocess.run([compiler, *flags, "-o", str(partial), str(SOURCE), "-lm"],
                                capture_output=True, text=True)
        if result.returncode == 0:
            os.replace(partial, library)  # atomic: a parallel build never sees half a library
            return library, flags
        errors.append(f"{compiler} {' '.join(flags)}:\n{result.stderr.strip()}")
    raise NoCompilerError("could not build the C reference:\n" + "\n".join(errors))


_library: list[ctypes.CDLL] = []


def load_library() -> ctypes.CDLL:
    """The built library with `advance` typed (built and loaded once per process)."""
    if not _library:
        lib = ctypes.CDLL(str(build_library()[0]))
        ints = np.ctypeslib.ndpointer(np.int32, flags="C_CONTIGUOUS")
        reals = np.ctypeslib.ndpointer(np.float64, flags="C_CONTIGUOUS")
        writable = np.ctypeslib.ndpointer(np.float64, flags=("C_CONTIGUOUS", "WRITEABLE"))
        c_int, c_double = ctypes.c_int, ctypes.c_double
        lib.advance.restype = None
        lib.advance.argtypes = [c_int, c_int, c_int, ints, reals, reals, reals, reals, ints, reals,
                                c_double, c_double, reals, reals, c_int, reals,
                                c_int, c_int, c_int, c_double, writable, writable, writable, writable]
        _library.append(lib)
    return _library[0]


class CReference:
    """A batch of arms stepped by the C loop; the state lives in NumPy arrays owned here."""

    def __init__(self, body: Body, drives: Sequence[Drive], frame_dt: float, substeps: int,
                 positions: np.ndarray, velocities: np.ndarray):
        if len({d.frequencies for d in drives}) != 1:
            raise ValueError("all arms of a batch share the excitation frequencies")
        if any(d.kind != "product_of_sines" or tuple(d.direction) != (1.0, 0.0) for d in drives):
            raise ValueError("the C reference implements the paper's drive only: product_of_sines, sideways")
        self._lib = load_library()
        arms, n = len(drives), body.n_nodes
        self.body, self.frame_dt, self.substeps, self.arms, self.frame = body, frame_dt, substeps, arms, 0
        self.x = np.array(np.broadcast_to(positions, (arms, n, 2)), np.float64, order="C")  # a writable copy
        self.v = np.array(np.broadcast_to(velocities, (arms, n, 2)), np.float64, order="C")
        self.force = np.zeros((arms, n, 2))
        i32, f64 = (lambda a: np.ascontiguousarray(a, np.int32)), (lambda a: np.ascontiguousarray(a, np.float64))
        self._model = (i32(body.springs), f64(body.rest_lengths), f64(body.stiffness), f64(body.damping),
                       f64(body.masses), i32(body.free), f64(body.rest), float(body.gravity[0]),
                       float(body.gravity[1]), f64([d.amplitude for d in drives]),
                       f64([d.time_offset for d in drives]), len(drives[0].frequencies), f64(drives[0].frequencies))

    @classmethod
    def from_config(cls, config: Config, batch: ArmBatch) -> "CReference":
        """The arms of `batch` started exactly as `softarm.sim.physics.Simulator.from_config` starts them."""
        i = config.integration
        return cls(batch.body, batch.drives, i.frame_dt, i.substeps, batch.positions, batch.velocities)

    def advance(self, n_frames: int) -> np.ndarray:
        """(arms, n_frames, N, 2) positions at the next n_frames frame times, float64."""
        history = np.empty((self.arms, n_frames, self.body.n_nodes, 2))
        self._lib.advance(self.arms, self.body.n_nodes, len(self.body.springs), *self._model,
                          self.frame, n_frames, self.substeps, self.frame_dt, self.x, self.v, self.force, history)
        self.frame += n_frames
        return history
