"""A running simulation: a scene's state on the device, stepped by a cached solver, and
the run loop that calls its writers (frames, checkpoints, callbacks) at output times."""

from __future__ import annotations

import math
import time as _time
import warnings
from dataclasses import dataclass, fields
from pathlib import Path

import numpy as np
import taichi as ti

from ..engine import assembly, runtime, timestep
from ..engine import status as st
from ..engine.diagnosis import SimulationError  # noqa: F401 (taisph.run.simulation.SimulationError)
from ..engine.state import State
from ..engine.timestep import Controls
from . import checkpoint
from .checkpoint import CheckpointWriter
from ..messages import TaisphRuntimeWarning
from ..scene import parameters
from .progress import Progress, RunSummary
from .readout import Readout

# the ranges of the controls sim.set changes (as the command line's options check them)
CONTROL_RANGES = {"dt": parameters.positive, "courant": parameters.courant_number,
                  "max_density_error": parameters.Number(0), "max_out_of_range": parameters.Number(0, 1),
                  **timestep.SETTABLE}

# Below this many particles the sort pass runs serially: waking the thread pool
# costs more than the work (measured, see docs/performance.md), and a serial
# scatter keeps each cell's particles in a reproducible order.
SERIAL_SORT_BELOW = 60_000


@dataclass
class Restore:
    """What :meth:`Simulation.from_checkpoint` resumes: the state's arrays
    (:meth:`taisph.engine.state.State.arrays`), their grid and whether the sort was serial."""

    arrays: dict
    grid: tuple  # taisph.engine.neighbours.GridLayout (lo, cell, shape)
    serial_sort: bool


class Simulation(Readout):
    """Simulate a :class:`taisph.Scene`.

    >>> sim = Simulation(taisph.cases.dam_break(dx=0.05))
    >>> sim.run(0.1)                      # doctest: +SKIP
    >>> sim.positions(), sim.pressure()   # numpy arrays in particle-id order

    ``arch`` (``"cpu"``, ``"cuda"``, ``"vulkan"``), ``precision`` (``"f32"``, ``"f64"``)
    and ``threads`` select the Taichi runtime; they are process-wide (see
    :mod:`taisph.engine.runtime`). Kernels are compiled once per configuration and
    shared by every simulation in the process; :meth:`set` changes parameters without
    recompiling. Keyword ``controls`` (:class:`taisph.engine.timestep.Controls` fields:
    ``dt``, ``max_density_error``, ``remove_escaped``, ``deterministic``...) set the
    time step and the guards; the scene's ``dt``, if set, is a fixed step.
    :meth:`close` (or dropping the last reference) frees the arrays.
    """

    def __init__(self, scene, arch=None, precision=None, threads=None, _restore: Restore | None = None, **controls):
        scene.validate()
        self.scene = scene
        self.runtime = runtime.init(arch, precision, threads)
        self.solver = assembly.get(scene)
        self.dim, self._n_fluid = scene.dim, scene.n_fluid
        unknown = set(controls) - {f.name for f in fields(Controls)}
        if unknown:
            raise TypeError(f"unknown simulation option(s): {', '.join(sorted(unknown))}")
        controls.setdefault("dt", scene.dt)
        self.controls = timestep.controls_for(scene, **controls)
        self.serial_sort = scene.n < SERIAL_SORT_BELOW or self.controls.deterministic
        self._step_writers, self._launched = (), 0  # writers called every k steps (run)
        self._warned_dt, self._solve_stats = False, None  # this simulation's solve statistics (pressure_solve)
        self._snapshot_key = None
        self.time, self.steps, self._dt_last, self._dt_stable = 0.0, 0, 0.0, math.inf
        self.state = State(scene, self.solver, self.runtime, _restore.grid if _restore is not None else None)
        runtime.register(self)
        if _restore is not None:
            self.serial_sort = _restore.serial_sort
            self._setup_grid(_restore.grid)
            self.state.restore(_restore.arrays)
        else:
            self.state.upload_particles(scene)
            self._setup_grid(self.state.grid)
            self.state.reset_status()
            self._advance_one(self.time)  # bootstrap (dt = 0): pressure, first rates, maxima
        self._read_status()

    n = property(lambda self: self.state.n, doc="Particles in use (open boundaries create and retire them).")
    n_fluid = property(lambda self: self._n_fluid if not self.solver.creators else int(np.count_nonzero(self.fluid)),
                       doc="Fluid particles (with open boundaries: in the fluid, not in the buffers).")

    def _setup_grid(self, grid=None):
        self.state.setup_grid(self.scene, grid)
        self._upload_parameters()

    def _upload_parameters(self, dt=None):
        self._snapshot_key = None  # e.g. a new c0 changes the pressure of the same state
        self.state.upload_parameters(self.scene, self.controls, dt)
        stepper = self.pressure_solve
        if stepper is not None:  # the stepper is cached with the (pooled, maybe new) fields: bind ours
            self._solve_stats = stepper.bind(self._solve_stats)

    def close(self):
        """Free the Taichi arrays now (they are also freed when the object is dropped)."""
        if getattr(self, "state", None) is not None:
            self.state.free()
        self.state = None
        runtime.unregister(self)

    def __del__(self):
        try:
            self.close()
        except Exception:
            pass

    # --- parameters -------------------------------------------------------------
    def parameters(self) -> dict:
        """Current runtime parameter values (change them with :meth:`set`)."""
        return self.scene.parameters()

    def set(self, **values):
        """Change runtime parameters, e.g. ``sim.set(alpha=0.05, gravity=(0, -1))``: the
        scene's (:meth:`taisph.Scene.set`) and the :class:`Controls` fields (``dt``,
        ``max_density_error``...). No kernel is recompiled."""
        self.open_state()
        control_keys = {f.name for f in fields(Controls)} - {"deterministic"}
        controls = {key: values.pop(key) for key in control_keys & set(values)}
        for key, value in controls.items():  # checked before anything is written, as the scene's
            if value is not None and key in CONTROL_RANGES:
                CONTROL_RANGES[key].check(key, value, "simulation control")
        try:
            self.scene.set(**values)  # checked before anything is written: a refusal changes nothing
        except KeyError as err:
            raise KeyError(f"{err.args[0]}; or a control: {', '.join(sorted(control_keys))}") from None
        vars(self.controls).update(controls)
        if "smoothing_length" in values:
            self._setup_grid()
        self._upload_parameters()

    def set_material(self, index: int, **values):
        """Change constants of one material, e.g. ``sim.set_material(1, rho0=500.0)``."""
        self.scene.materials[index].set(**values)
        self._upload_parameters()

    # --- stepping -----------------------------------------------------------------
    def _advance_one(self, t_target: float):
        """One step towards `t_target` (its dt is chosen on the device)."""
        for kernel in self.state.step_kernels(self.serial_sort):
            kernel(t_target)

    def _read_status(self):
        """Refresh the host's copy of time, step count, dt and guard flags."""
        read = self.state.read
        self.time, self.steps, self._dt_last, self._dt_stable = (read(st.TIME), int(read(st.STEPS)), read(st.DT),
                                                                 read(st.DT_STABLE))
        self._fail_codes = self.state.read_flag(st.CODES)

    @property
    def dt(self) -> float:
        """The fixed time step, or the current adaptive one (before the first step:
        the one the next step will take, from the maxima of the bootstrap evaluation)."""
        if self.controls.dt is not None:
            return self.controls.dt
        if self._dt_last > 0:
            return self._dt_last
        return timestep.estimate(self.state.read, self.scene.smoothing_length, self.controls,
                                 timestep.kinematic_viscosity(self.scene.terms),
                                 timestep.term_limit(self.scene, self.controls))

    def _advance(self, t_target: float, max_steps: int | None = None, progress=None, steps0: int = 0) -> None:
        """Step until the clock reaches `t_target` (or `max_steps` steps are done),
        checking the guards every batch of steps."""
        done, batch = 0, 1
        while True:
            remaining = t_target - self.time
            if max_steps is not None and done >= max_steps:
                return
            if math.isfinite(t_target) and remaining <= 1e-12 * max(1.0, abs(t_target)):
                return
            estimate = math.ceil(remaining / max(self.dt, 1e-300)) if math.isfinite(remaining) else batch
            n = max(1, min(batch, estimate, (max_steps - done) if max_steps is not None else batch))
            if self.state.ensure_room():  # open boundaries: room for the particles they may create
                self._upload_parameters()
            self.state.keep_good(self.time, self.steps)
            start = _time.perf_counter()
            before = self.time
            for _ in range(n):
                self._advance_one(t_target)
                self._launched += 1
                for writer in self._step_writers:
                    if self._launched % writer.every == 0:
                        writer.on_steps(self)
            self._read_status()
            done += n
            self.state.check_room(self.time)  # open boundaries: did every particle they made fit?
            if self._fail_codes:
                self._fail()
            if self.time == before:  # the step underflowed: a guard's diagnosis, with the fastest particles
                self._fail(stalled=True)
            self._warn_if_dt_unstable()
            if progress is not None:
                progress.update(self.time, self.steps - steps0)
            # batches of ~0.2 s between checks, at most 128 steps: each starts with a device
            # copy of the state (the last good one, for a diagnosis; docs/performance.md)
            elapsed = _time.perf_counter() - start
            batch = max(1, min(128, int(n * 0.2 / max(elapsed, 1e-6))))

    def step(self, n: int = 1, dt: float | None = None):
        """Advance `n` steps: of `dt` if given, else of the fixed or adaptive step."""
        self.open_state()
        if dt is not None:
            self._upload_parameters(dt=dt)
        self.state.write(st.END_TIME, math.inf)  # no end to shorten a step for
        try:
            self._advance(math.inf, max_steps=n)
        finally:
            if dt is not None:
                self._upload_parameters()

    def _warn_if_dt_unstable(self):
        if self.controls.dt is None or self._warned_dt:
            return
        limit = self.state.read(st.DT_STABLE_MIN)
        if self.controls.dt > limit:
            self._warned_dt = True
            warnings.warn(
                f"fixed dt = {self.controls.dt:.3g} s is above the stability limit {limit:.3g} s "
                f"(CFL {self.controls.courant} h/(c+|v|), force {self.controls.force_factor} sqrt(h/|a|)); "
                "expect a blow-up, or leave dt unset for the adaptive step",
                TaisphRuntimeWarning, stacklevel=3,
            )

    def run(self, t_end=None, frames=None, out=None, progress=False, callback=None,
            checkpoint_every: int | None = None, writers=(), _writer_state=None, _output_times=None) -> RunSummary:
        """Advance to `t_end` (default: the scene's), writing `frames` VTK frames (plus
        the initial one, when starting from t = 0; 0: that one only) to the folder `out`.

        The output times are ``t0 + (t_end - t0) k / frames``; the last step is shortened
        to land exactly on `t_end`, no other: the writers are called at the first step
        that reaches each output time, with that step's own time (``sim.time``, at most
        one step later), so that how often a run is looked at (frames, probes, checkpoints,
        callbacks) never changes its trajectory: bit for bit with ``deterministic=True``.
        At every output time the run's writers are called: the ParaView frames (if
        `out`), `callback(sim)`, a checkpoint to
        ``out/checkpoint`` every `checkpoint_every` frames
        (:func:`taisph.run.checkpoint.save`), and any further `writers` (objects with
        ``on_start(sim)`` and ``on_frame(sim, k)``; one with an ``every`` attribute also
        gets ``on_steps(sim)`` after every `every` steps, e.g. probes, which read the
        clock with :meth:`device_time`). A tripped guard raises
        :class:`SimulationError` after writing the last good state and the offending
        particles to `out`. (`_output_times`: a resumed run's output times, those its
        checkpoint had left, so that it writes where the uninterrupted run would.)
        """
        self.open_state()
        from .vtk import VTKWriter

        t_end = self.scene.t_end if t_end is None else float(t_end)
        frames = self.scene.frames if frames is None else int(frames)
        if frames < 0:
            raise ValueError(f"frames must be at least 0, got {frames}")
        t0 = self.time  # frames = 0: t_end is the one output time (writers called), no frame written there
        frame_times = [t0 + (t_end - t0) * (k + 1) / frames for k in range(frames - 1)] + [t_end]
        if _output_times is not None and len(_output_times) == frames and _output_times[-1] == t_end:
            frame_times = [float(t) for t in _output_times]
        if t_end > self.time:  # else (a finished run) nothing is stepped: the end stays as it was
            self.state.write(st.END_TIME, t_end)
        self._out = Path(out) if out is not None else None
        frame_writer = VTKWriter(out, self, resume=_writer_state, initial_only=frames == 0) if out is not None else None
        run_writers = [w for w in (frame_writer,) if w is not None]
        if checkpoint_every and out is not None:
            run_writers.append(CheckpointWriter(Path(out) / "checkpoint", checkpoint_every, t_end, frame_times,
                                                frame_writer, *checkpoint.probes_of(writers)))
        run_writers += list(writers)
        self._step_writers = [w for w in run_writers if callable(getattr(w, "on_steps", None))]
        frames0 = frame_writer.frame if frame_writer else 0
        # the caller's writers first: one that refuses its input (a probe in a wall) does so
        # before a frame is written
        for writer in sorted(run_writers, key=lambda w: w not in writers):
            writer.on_start(self)
        if (stepper := self.pressure_solve) is not None:
            stepper.begin_window()
        dt_sum0 = self.state.start_run_statistics()
        steps0, rebuilds0 = self.steps, self.list_rebuilds
        start = _time.perf_counter()
        with Progress(t0, t_end, enabled=progress) as bar:
            for k, t_frame in enumerate(frame_times):
                self._advance(t_frame, progress=bar, steps0=steps0)
                bar.update(self.time, self.steps - steps0, force=True)
                for writer in run_writers:
                    writer.on_frame(self, k)
                if callback is not None:
                    callback(self)
        self._step_writers = ()
        ti.sync()
        wall = _time.perf_counter() - start
        steps = self.steps - steps0
        dt_min, dt_mean, dt_max = self.state.run_statistics(dt_sum0, steps)
        fluid_mass, removed_mass = self.state.fluid_and_removed_mass()
        opened = self.open_boundary_mass() if "open_boundaries" in self.effects() else None
        solves = self._solve_stats.summary() if self._solve_stats is not None else None
        return RunSummary(self.n, self.n_fluid, steps, self.time, wall,
                          frame_writer.frame - frames0 if frame_writer else 0,
                          str(frame_writer.folder) if frame_writer else None, dt_min, dt_mean, dt_max,
                          self.state.read_flag(st.REMOVED_COUNT),
                          self.list_rebuilds - rebuilds0 if self.solver.lists else None,
                          fluid_mass, removed_mass, solves,
                          self.state.read_flag(st.OUT_OF_RANGE_COUNT), frame_writer.removed if frame_writer else 0,
                          opened, int(self.buffer.sum()) if self.solver.imposed_rows else 0)

    @property
    def pressure_solve(self):
        """The step's host-side stepper, for a solver that iterates its pressure solves on the
        host (DFSPH: :class:`taisph.engine.dfsph.solver.Stepper`; ``stats``: this simulation's
        solves); None for one that does not (WCSPH). See ``taisph.engine.method.Method.stepper``."""
        return self.solver.stepper(self.state.fields, self.serial_sort)

    def device_time(self) -> float:
        """The simulated time on the device now (``time`` is the host's copy, refreshed
        between batches of steps)."""
        return self.state.read(st.TIME)

    # --- guards and checkpoints ---------------------------------------------------------
    def _fail(self, stalled=False):
        from ..engine import diagnosis

        diagnosis.fail(self, getattr(self, "_out", None), stalled)

    def save_checkpoint(self, folder, t_end=None, frames_left=None, writer=None, **run) -> Path:
        """Write the complete state to `folder`, atomically (:mod:`taisph.run.checkpoint`;
        `run`: ``checkpoint_every``, ``probes``, ``wall_groups``); :meth:`from_checkpoint` resumes it."""
        return checkpoint.save(self, folder, t_end, frames_left, writer, **run)

    @classmethod
    def from_checkpoint(cls, folder, arch=None, threads=None) -> "Simulation":
        """A simulation continuing exactly where :meth:`save_checkpoint` stopped; its
        ``checkpoint_meta`` holds where the run was going (:func:`taisph.run.checkpoint.read`).
        A folder of another checkpoint version raises :class:`taisph.run.checkpoint.CheckpointError`."""
        meta, arrays = checkpoint.read(folder)
        restore = Restore(arrays=arrays, grid=meta["grid"], serial_sort=meta["serial_sort"])
        sim = cls(meta["scene"], arch=arch or meta["runtime"][0], precision=meta["runtime"][1], threads=threads,
                  _restore=restore, **meta["controls"])
        sim.checkpoint_meta = meta
        return sim

    def neighbour_pairs(self) -> np.ndarray:
        """Ordered pairs of particle ids closer than the kernel support, as the
        neighbour sums visit them: an (M, 2) array (each pair appears as (i, j) and
        (j, i)). With neighbour lists and terms that need walls only within a short
        range (Lennard-Jones walls), fluid-wall pairs beyond that range plus the skin
        are not visited and not listed. Leaves the simulation as it was."""
        return self.state.neighbour_pairs(self.serial_sort, self.time)

    @property
    def list_rebuilds(self) -> int:
        """How many times the neighbour lists were built so far (every step without
        lists: see ``Scene.neighbour_skin``)."""
        if not self.solver.lists:
            return self.steps
        return int(self.state.read(st.REBUILDS))

    def bytes_per_particle(self) -> int:
        """Memory of the particle state per particle (:meth:`taisph.engine.state.State.bytes_per_particle`)."""
        return self.state.bytes_per_particle()

    def effects(self) -> list:
        """Names of the terms compiled into this simulation's kernels (DFSPH: those it keeps;
        ``taisph.engine.method.Method.terms``)."""
        return [t.name for t in self.solver.active_terms(self.scene)]
