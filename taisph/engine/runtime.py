"""The Taichi runtime, initialised once per process.

``ti.init`` settings (backend, default float precision) are global to a process and
re-initialising destroys every Taichi array and compiled kernel. taisph therefore
initialises Taichi lazily, the first time a simulation needs it, and afterwards only
checks that later requests agree. Simulations of any size and parameters share the
runtime and the compiled kernels (see :mod:`taisph.engine.assembly`).

A different precision or backend can be selected once no simulation is alive
(:func:`init` then resets Taichi and drops the kernel cache); asking for it while a
simulation is alive raises, because resetting would silently destroy that
simulation's state.
"""

from __future__ import annotations

import contextlib
import io
import os
import weakref
from dataclasses import dataclass

import taichi as ti

from ..messages import InputError

PRECISIONS = {"f32": ti.f32, "f64": ti.f64}
ARCHS = {"cpu": ti.cpu, "cuda": ti.cuda, "vulkan": ti.vulkan, "metal": ti.metal, "gpu": ti.gpu}
DEVICE_NAMES = {"cuda": "CUDA", "vulkan": "Vulkan", "metal": "Metal"}


class RuntimeConflict(RuntimeError):
    """Raised when a simulation asks for a backend/precision other than the live one."""


class BackendUnavailable(InputError, RuntimeError):
    """The requested backend (``arch``) cannot start on this machine. A ValueError (the
    command line reports it as ``taisph: error: ...``, exit code 2: nothing was run) and
    a RuntimeError (what it was before)."""


@contextlib.contextmanager
def _taichi_quiet():
    """Taichi's log below errors off (its warnings while probing a backend that is not
    there: "libcuda.so lib not found", "falling back to CPU"), restored afterwards."""
    level = next((name for name in ("trace", "debug", "info", "warn", "error", "critical")
                  if ti.is_logging_effective(name)), "warn")
    ti.set_logging_level("error")
    try:
        yield
    finally:
        ti.set_logging_level(level)


def available(arch: str) -> bool:
    """Can Taichi start backend `arch` (a key of :data:`ARCHS`) on this machine? Asks
    quietly (no Taichi log lines) and starts nothing."""
    if arch in ("cpu", "gpu"):  # gpu: any GPU, else Taichi falls back to the CPU
        return True
    with _taichi_quiet():
        return bool(ti.lang.misc.is_arch_supported(ARCHS[arch]))


@dataclass(frozen=True)
class Runtime:
    arch: str
    precision: str
    threads: int

    @property
    def real(self):
        """Taichi float type of every particle quantity and every kernel."""
        return PRECISIONS[self.precision]

    @property
    def numpy_real(self):
        import numpy as np

        return np.float32 if self.precision == "f32" else np.float64


_current: Runtime | None = None
_live = weakref.WeakSet()  # simulations holding Taichi arrays
_on_reset = []  # callbacks run when Taichi is reset (e.g. clear kernel caches)


def on_reset(callback):
    """Register `callback` to run when Taichi is reset (compiled kernels are gone)."""
    if callback not in _on_reset:
        _on_reset.append(callback)
    return callback


def default_threads() -> int:
    env = os.environ.get("TAISPH_THREADS")
    if env:
        return int(env)
    return os.cpu_count() or 1


def init(arch: str | None = None, precision: str | None = None, threads: int | None = None) -> Runtime:
    """Initialise Taichi if needed and return the live runtime.

    ``None`` means "whatever is live, or the default": CPU, f64, all cores.
    """
    global _current
    if arch is not None and arch not in ARCHS:
        raise ValueError(f"unknown arch {arch!r}; choose one of {', '.join(ARCHS)}")
    if precision is not None and precision not in PRECISIONS:
        raise ValueError(f"unknown precision {precision!r}; choose f32 or f64")
    if arch is not None and (_current is None or arch != _current.arch) and not available(arch):
        # before anything is reset: the live runtime stays usable
        raise BackendUnavailable(
            f"arch={arch} was requested but Taichi could not start it on this machine (no "
            f"{DEVICE_NAMES.get(arch, arch)} device or driver found); check the driver/device, or use --arch cpu"
        )
    if _current is not None:
        wanted = Runtime(
            arch or _current.arch, precision or _current.precision, threads or _current.threads
        )
        if wanted == _current:
            return _current
        if len(_live):
            raise RuntimeConflict(
                f"Taichi is running with arch={_current.arch}, precision={_current.precision}, "
                f"threads={_current.threads}; {len(_live)} simulation(s) still hold Taichi arrays. "
                f"Close them (sim.close()) or delete them before asking for arch={wanted.arch}, "
                f"precision={wanted.precision}, threads={wanted.threads}: re-initialising Taichi "
                "destroys every array."
            )
        reset()
    rt = Runtime(arch or "cpu", precision or "f64", threads or default_threads())
    kwargs = dict(
        arch=ARCHS[rt.arch],
        default_fp=rt.real,
        default_ip=ti.i32,
        log_level=ti.WARN,
        offline_cache=True,
    )
    if rt.arch == "cpu":
        kwargs["cpu_max_num_threads"] = rt.threads
    if os.environ.get("TAISPH_PROFILE"):
        # per-task timings: ti.profiler.print_kernel_profiler_info()
        kwargs["kernel_profiler"] = True
    # ti.init prints "[Taichi] Starting on arch=..." to standard output, which carries
    # results only (taisph.messages): the line is dropped
    with contextlib.redirect_stdout(io.StringIO()):
        ti.init(**kwargs)
    actual = ti.lang.impl.current_cfg().arch
    if rt.arch not in ("cpu", "gpu") and actual != ARCHS[rt.arch]:
        ti.reset()
        raise BackendUnavailable(
            f"arch={rt.arch} was requested but Taichi could not start it on this machine "
            f"(it fell back to {actual.name}); check the driver/device, or use --arch cpu"
        )
    _current = rt
    return rt


def is_current(rt: Runtime) -> bool:
    """Is `rt` the live runtime (its arrays and kernels still valid)?"""
    return _current is rt


def current() -> Runtime:
    return _current if _current is not None else init()


def register(sim) -> None:
    _live.add(sim)


def unregister(sim) -> None:
    _live.discard(sim)


def reset() -> None:
    """Reset Taichi: all arrays and compiled kernels are gone afterwards."""
    global _current
    for callback in _on_reset:
        callback()
    if _current is not None:
        ti.reset()
    _current = None


def free_ndarray(array) -> None:
    """Release a Taichi ndarray's memory now.

    Taichi 1.7 frees scalar ndarrays when Python collects them, but vector and
    matrix ndarrays leak (taichi-dev/taichi#8763), so taisph frees those itself
    when a simulation closes. Do not use `array` afterwards.
    """
    if array is None or getattr(array, "_taisph_freed", False) or hasattr(type(array), "__del__"):
        return
    from taichi.lang import impl

    rt = impl.get_runtime()
    if rt is not None and rt.prog is not None:
        rt.prog.delete_ndarray(array.arr)
        array._taisph_freed = True
