"""Taichi start-up: called once, at the edge (CLI or a notebook), never on import."""

import contextlib
import io

import taichi as ti

from softarm.errors import SoftarmError

ARCHS = ("cpu", "gpu", "auto")
_started: list[str] = []


def init_taichi(arch: str = "cpu", debug: bool = False) -> str:
    """Start Taichi on `arch` (cpu | gpu | auto) with float64 and the offline kernel cache.

    Returns the backend in use ("x64", "cuda", ...). `auto` takes a GPU when there is one; `gpu`
    refuses to fall back to the CPU silently. A second call with the same arch does nothing.
    """
    if arch not in ARCHS:
        raise SoftarmError(f"--arch {arch!r} is not known: use one of {', '.join(ARCHS)}")
    if _started:
        if _started[0] != arch:
            raise SoftarmError(f"Taichi is already running with arch {_started[0]!r}; restart to use {arch!r}")
        return backend_name()
    choice = {"cpu": ti.cpu, "gpu": ti.gpu, "auto": ti.gpu}[arch]
    try:
        with contextlib.redirect_stdout(io.StringIO()):  # ti.init prints "Starting on arch=..." itself
            ti.init(arch=choice, default_fp=ti.f64, offline_cache=True, debug=debug, log_level=ti.ERROR,
                    enable_fallback=arch != "gpu")
    except RuntimeError as e:
        raise SoftarmError(f"--arch gpu: no GPU backend is available here ({e}); use --arch cpu or auto") from None
    _started.append(arch)
    return backend_name()


def backend_name() -> str:
    return str(ti.lang.impl.current_cfg().arch).rsplit(".", 1)[-1]
