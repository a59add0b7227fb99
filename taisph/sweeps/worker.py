"""One run of a sweep, in a worker process: :func:`run_task` (what Dask calls).

Taichi's settings (precision, threads) and its compiled kernels belong to a process,
so a worker process runs one simulation at a time (a lock, should the worker have
more than one thread) and reinitialises Taichi only when a run asks for other
settings. Kernels compile at the first run of each configuration in a process
(faster in later processes: Taichi's offline cache keeps them on disk).

A run is timed in two parts. First a warm-up: a simulation of the run's scene is
built and takes one step, then is closed; that time is the run's ``compile_s``
(kernel compilation, when this process had not compiled them yet, and the set-up).
Then the measured run, on a fresh simulation of the same scene, so its steps and
its state are those of a direct run and its wall time holds no compilation.
"""

from __future__ import annotations

import contextlib
import gc
import inspect
import io
import math
import os
import socket
import threading
import time

from ..engine import runtime
from ..engine.diagnosis import SimulationError
from ..engine.timestep import SETTABLE, fixed_dt
from ..run.simulation import Simulation
from .plan import Task, resolve_case

_ONE_RUN_AT_A_TIME = threading.Lock()
_CONTROLS = ("max_density_error", "deterministic", "remove_escaped", "courant", *SETTABLE)


def run_task(task: Task) -> dict:
    """Run `task` and return its result (a dict: :func:`blank_result`'s keys). Never
    raises for a failed run: the failure is the result's ``status``."""
    with _ONE_RUN_AT_A_TIME:
        result = blank_result(task)
        try:
            _run(task, result)
        except Exception as err:  # a failed run is a result too
            fail(result, err)
        finally:
            gc.collect()  # a failed run's simulation must go before the next run may reinitialise Taichi
        return result


def blank_result(task: Task) -> dict:
    return dict(run=task.name, status="ok", steps=0, wall_s=math.nan, particle_steps_per_s=math.nan,
                wall_s_per_sim_s=math.nan, compile_s=math.nan, error=math.nan, error_name="",
                fluid_particles=0, particles=0, sim_time_s=math.nan, dt=math.nan, setup_s=math.nan,
                metrics={}, diverged=False, failure="", precision=task.settings.get("precision", "f64"),
                threads=task.settings.get("threads"), worker=f"{socket.gethostname()}:{os.getpid()}")


def fail(result: dict, err: BaseException) -> None:
    """Record `err` in `result`: status ``failed: <first line>`` (a tripped guard's
    first line is its diagnosis), failure: the type and the whole message."""
    message = str(err).strip() or repr(err)
    first = message.splitlines()[0]
    result["status"] = "failed: " + (first if isinstance(err, SimulationError) else f"{type(err).__name__}: {first}")
    result["failure"] = f"{type(err).__name__}: {message}"


def _scene(task: Task):
    """The run's scene, built as the plain command and the validation runs build it."""
    if task.validate:  # a validation run built from a scene file (taisph.validation.runs.scene_of)
        from ..validation.runs import scene_of

        scene = scene_of(task.case, task.params)
        if scene is not None:
            return scene
    case = task.case
    if task.validate:  # a validation with a case's scene under another name (dam_break_front)
        from ..validation.runs import SCENE_CASES

        case = SCENE_CASES.get(case, case)
    factory = resolve_case(case)
    accepted = inspect.signature(factory).parameters
    scene = factory(**{k: v for k, v in task.params.items() if k in accepted})
    if task.params.get("solver") is not None:  # a validation run's (taisph.validation.runs)
        scene.solver = task.params["solver"]
    settings = task.settings
    if settings.get("dt") is not None:
        scene.dt = settings["dt"]
    if settings.get("neighbour_skin") is not None:
        scene.neighbour_skin = settings["neighbour_skin"]
    dt_factor = task.params.get("dt_factor", 1.0) if task.validate else 1.0
    if dt_factor != 1.0:  # as taisph.validation.runs does
        scene.dt = (scene.dt or fixed_dt(scene)) * dt_factor
    return scene


def _simulation(task: Task, scene):
    controls = {k: task.settings[k] for k in _CONTROLS if task.settings.get(k) is not None}
    return Simulation(scene, arch="cpu", precision=task.settings["precision"], threads=task.settings.get("threads"),
                      **controls)


def _warm_up(task: Task, scene) -> float:
    """Seconds from building a simulation of `scene` until its first step is done."""
    start = time.perf_counter()
    sim = _simulation(task, scene)
    try:
        sim.step(1)
    finally:
        sim.close()
    return time.perf_counter() - start


def _run(task: Task, result: dict) -> None:
    with contextlib.redirect_stdout(io.StringIO()):  # ti.init prints "[Taichi] Starting on arch=x64"
        rt = runtime.init("cpu", task.settings["precision"], task.settings.get("threads"))
    result["threads"] = rt.threads
    scene = _scene(task)
    result["compile_s"] = _warm_up(task, scene)
    if task.validate:
        from ..validation import run as validation_run

        out = validation_run(task.case, precision=task.settings["precision"], **task.params)
        result.update(steps=out.steps, wall_s=out.wall, fluid_particles=out.fluid, particles=out.particles,
                      sim_time_s=out.sim_time, dt=out.dt, setup_s=out.setup, error=out.error,
                      error_name=out.error_name, metrics=out.metrics, diverged=out.diverged)
        if out.diverged:
            result["status"] = "failed: diverged (non-finite state, or particles far outside the domain)"
    else:
        start = time.perf_counter()
        sim = _simulation(task, scene)
        result["setup_s"] = time.perf_counter() - start
        try:
            summary = sim.run(None, frames=None, out=task.out)  # the scene's t_end and frames
        finally:
            sim.close()
        result.update(steps=summary.steps, wall_s=summary.wall_time, fluid_particles=summary.fluid_particles,
                      particles=summary.particles, sim_time_s=summary.sim_time, dt=summary.dt_mean)
    steps, wall, sim_time = result["steps"], result["wall_s"], result["sim_time_s"]
    if wall > 0:
        result["particle_steps_per_s"] = result["fluid_particles"] * steps / wall
    if sim_time > 0:
        result["wall_s_per_sim_s"] = wall / sim_time
