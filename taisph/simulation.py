"""A running simulation: the particle state of one scene, stepped by a cached solver."""

import math
import os
import pickle
import shutil
import time as _time
import warnings
from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np
import taichi as ti

from .engine import runtime, assembly as _solver
from .engine import timestep as stepping
from .engine.neighbours import layout_grid
from .engine.layout import FLUID, WALL

# Grids with more cells than this per particle are refused: the domain is too large
# for the smoothing length (a typo in a unit, usually) and memory would explode.
MAX_CELLS_PER_PARTICLE = 64
CHECKPOINT_VERSION = 2  # 2: neighbour lists saved


class SimulationError(RuntimeError):
    """A guard tripped (non-finite state, density error, particle out of the domain).

    ``str(err)`` explains what happened, where, the likely cause and a remedy;
    ``err.report`` holds the same as data, ``err.files`` the frames written."""

    def __init__(self, message, report, files=()):
        super().__init__(message)
        self.report = report
        self.files = list(files)


@dataclass
class Controls:
    """Time-step and guard settings (runtime values; see :mod:`taisph.stepping`).

    dt                 fixed time step (s); None: adaptive (the default)
    dt_max             cap on the adaptive step (s)
    courant            C in dt = C h / max(c + |v|)                 (0.25)
    force_factor       C in dt = C sqrt(h / max |a|)                (0.25)
    viscous_factor     C in dt = C h^2 / nu for physical viscosity  (0.125)
    max_density_error  stop when |rho/rho0 - 1| exceeds this (0 disables)
    remove_escaped     remove particles that leave the domain instead of stopping
    deterministic      serial (stable) cell sort at every size: bit-reproducible runs
    """

    dt: float | None = None
    dt_max: float = math.inf
    courant: float = 0.25
    force_factor: float = 0.25
    viscous_factor: float = 0.125
    max_density_error: float = 0.2
    remove_escaped: bool = False
    deterministic: bool = False


@dataclass
class RunSummary:
    """What :meth:`Simulation.run` did."""

    particles: int
    fluid_particles: int
    steps: int
    sim_time: float
    wall_time: float
    frames: int
    out: str | None
    dt_min: float = float("nan")
    dt_mean: float = float("nan")
    dt_max: float = float("nan")
    removed: int = 0
    list_rebuilds: int | None = None  # neighbour list rebuilds during the run (None: no lists)

    @property
    def particle_steps_per_second(self) -> float:
        """Fluid particle-steps per wall second (the number SPH codes compare)."""
        return self.fluid_particles * self.steps / self.wall_time if self.wall_time > 0 else float("nan")

    def __str__(self) -> str:
        out = f", output in {self.out}" if self.out else ""
        removed = f", {self.removed} particles removed (left the domain)" if self.removed else ""
        if self.list_rebuilds is not None:
            removed = f", neighbour lists rebuilt {self.list_rebuilds} times" + removed
        return (
            f"{self.fluid_particles} fluid + {self.particles - self.fluid_particles} wall particles, "
            f"{self.steps} steps to t = {self.sim_time:.4g} s in {self.wall_time:.2f} s wall "
            f"({self.particle_steps_per_second / 1e6:.2f} M fluid particle-steps/s), "
            f"dt min/mean/max {self.dt_min:.3g}/{self.dt_mean:.3g}/{self.dt_max:.3g} s, "
            f"{self.frames} frames{removed}{out}"
        )


class Simulation:
    """Simulate a :class:`taisph.Scene`.

    >>> sim = Simulation(taisph.cases.dam_break(dx=0.05))
    >>> sim.run(0.1)                      # doctest: +SKIP
    >>> sim.positions(), sim.pressure()   # numpy arrays in particle-id order

    ``arch`` (``"cpu"``, ``"cuda"``, ``"vulkan"``), ``precision`` (``"f32"``, ``"f64"``)
    and ``threads`` select the Taichi runtime; they are process-wide (see
    :mod:`taisph.runtime`). Kernels are compiled once per configuration and shared
    by every simulation in the process; :meth:`set` changes parameters without
    recompiling. Keyword ``controls`` (:class:`Controls` fields: ``dt``,
    ``max_density_error``, ``remove_escaped``, ``deterministic``...) set the time
    step and the guards; the scene's ``dt``, if set, is a fixed step.
    :meth:`close` (or dropping the last reference) frees the arrays.
    """

    def __init__(self, scene, arch=None, precision=None, threads=None, _restore=None, **controls):
        scene.validate()
        self.scene = scene
        self.runtime = runtime.init(arch, precision, threads)
        self.solver = _solver.get(scene)
        self.dim = scene.dim
        self.n = scene.n
        self.n_fluid = scene.n_fluid
        unknown = set(controls) - {f.name for f in fields(Controls)}
        if unknown:
            raise TypeError(f"unknown simulation option(s): {', '.join(sorted(unknown))}")
        if "dt" not in controls:
            controls["dt"] = scene.dt
        self.controls = Controls(**controls)
        self._serial_sort = self.n < _solver.SERIAL_SORT_BELOW or self.controls.deterministic
        self._graph_args = None
        self._warned_dt = False
        self._snapshot_key = None
        self.time, self.steps, self._dt_last, self._dt_stable = 0.0, 0, 0.0, math.inf
        self._allocate()
        runtime.register(self)
        if _restore is not None:
            self._restore(_restore)
        else:
            self._upload(scene)
            self._reset_status()
            self._advance_arrays(self.time)  # bootstrap (dt = 0): pressure, first rates, maxima
        self._read_status()

    # --- memory ---------------------------------------------------------------
    def _allocate(self):
        sv = self.solver
        L = sv.layout
        real, n = self.runtime.real, self.n
        self._C = (ti.ndarray(sv.vec, (len(L.vectors), n)), ti.ndarray(real, (len(L.scalars), n)), ti.ndarray(ti.i32, (len(L.integers), n)))
        self._S = (ti.ndarray(sv.vec, (len(L.vectors), n)), ti.ndarray(real, (len(L.scalars), n)), ti.ndarray(ti.i32, (len(L.integers), n)))
        self._cell_of = ti.ndarray(ti.i32, n)
        self._params = ti.ndarray(real, sv.n_params)
        self._mat = ti.ndarray(real, (len(self.scene.materials), len(sv.material_columns)))
        self._gshape = ti.ndarray(ti.i32, 4)
        self._status = ti.ndarray(ti.f64, stepping.STATUS_SIZE)
        self._flags = ti.ndarray(ti.i32, stepping.FLAGS_SIZE)
        self._cells = None
        self._good = None
        # neighbour lists (taisph.grid); a dummy row when the scene has none
        self.list_capacity = self._list_capacity() if sv.lists else 1
        rows = n if sv.lists else 1
        self._x_ref = ti.ndarray(sv.vec, rows)
        self._nlist = ti.ndarray(ti.i32, (rows, self.list_capacity))
        self._ncount = ti.ndarray(ti.i32, rows)
        self._ncount.fill(-1)

    def _list_capacity(self) -> int:
        """Entries per particle's neighbour list: 1.5 times the particles within
        support + skin of a particle in a lattice of spacing dx, plus a margin.
        A particle with more (a compressed spot, a wall of closer particles) walks
        the cells instead; its neighbours are still all found."""
        scene = self.scene
        reach = scene.support_radius * (1.0 + scene.neighbour_skin)
        ball = {1: 2 * reach, 2: math.pi * reach**2, 3: 4 / 3 * math.pi * reach**3}[self.dim]
        return int(min(self.n, math.ceil(1.5 * ball / scene.dx**self.dim) + 8))  # device copy of the last state that passed the guards

    def _setup_grid(self, grid=None):
        scene = self.scene
        support = scene.support_radius
        # with neighbour lists the cells hold everything within support + skin; a
        # periodic axis needs 3 cells, which may shorten the skin
        reach = support * (1.0 + scene.neighbour_skin)
        lo_d, hi_d = (np.asarray(a, float) for a in scene.domain)
        for d in range(self.dim):
            if scene.periodic[d]:
                reach = max(support, min(reach, (hi_d[d] - lo_d[d]) / 3.0))
        self.list_skin = reach - support
        if grid is None:
            pos = scene.position if self._cells is None else self.positions()
            grid = layout_grid(scene.domain, scene.periodic, reach, pos)
        lo, cell, shape = grid
        n_cells = int(np.prod(shape))
        if n_cells > MAX_CELLS_PER_PARTICLE * self.n + 4096:
            raise ValueError(
                f"the neighbour grid would need {n_cells} cells of {support:g} m for {self.n} particles "
                f"(domain {scene.domain[0]} .. {scene.domain[1]}); the domain is too large for the "
                "smoothing length"
            )
        self.grid_lo, self.grid_cell, self.grid_shape = np.asarray(lo), np.asarray(cell), tuple(shape)
        self._cells = tuple(ti.ndarray(ti.i32, k) for k in (n_cells, n_cells + 1, n_cells))
        self._cells[0].fill(0)
        self._graph_args = None  # arrays changed: rebind the step graph
        g = np.zeros(4, np.int32)
        g[: self.dim] = shape
        g[self.dim : 3] = 1
        g[3] = n_cells
        self._gshape.from_numpy(g)
        self._status.arr.write_float([stepping.FORCE_REBUILD], 1.0)  # new cells: new lists

    def _upload(self, scene):
        sv = self.solver
        L = sv.layout
        n, d = self.n, self.dim
        npreal = self.runtime.numpy_real
        vec = np.zeros((len(L.vectors), n, d), npreal)
        vec[L.q.position] = scene.position
        vec[L.q.velocity] = scene.velocity
        sca = np.zeros((len(L.scalars), n), npreal)
        sca[L.q.density] = scene.density
        sca[L.q.mass] = scene.mass
        ints = np.zeros((len(L.integers), n), np.int32)
        ints[L.q.id] = np.arange(n)
        ints[L.q.material] = scene.material
        ints[L.q.kind] = scene.kind
        for name, values in scene.quantities.items():
            try:
                kind = L.kind_of(name)
            except KeyError:
                raise ValueError(
                    f"scene {scene.name!r} gives initial values of {name!r}, but none of its terms "
                    f"stores it (stored: {', '.join(L.vectors + L.scalars)})"
                ) from None
            {"vector": vec, "scalar": sca, "integer": ints}[kind][getattr(L.q, name)] = values
        for arr, data in zip(self._C, (vec, sca, ints)):
            arr.from_numpy(data)
        self._setup_grid()
        self._upload_parameters()

    def _control_values(self, dt=None) -> dict:
        c = self.controls
        scene = self.scene
        fixed = c.dt if dt is None else dt
        lo, hi = scene.domain
        margin = scene.support_radius
        nu = max([getattr(t, "viscosity", lambda: 0.0)() for t in scene.terms] + [0.0])
        h = scene.smoothing_length
        return dict(
            dt_fixed=0.0 if fixed is None else float(fixed),
            dt_max=min(c.dt_max, 1e30),  # 'no limit', finite in f32 too
            courant=c.courant,
            force_factor=c.force_factor,
            dt_viscous=c.viscous_factor * h * h / nu if nu > 0 else 1e30,
            max_density_error=c.max_density_error,
            remove_escaped=1.0 if c.remove_escaped else 0.0,
            guard_lo=lo - margin,
            guard_hi=hi + margin,
            list_skin=self.list_skin,
            list_reach2=(scene.support_radius + self.list_skin) ** 2,
            list_wall_reach2=(self._wall_range() + self.list_skin) ** 2,
        )

    def _wall_range(self) -> float:
        """How far any term looks at wall neighbours, when none needs the full support
        (e.g. the Lennard-Jones cut-off); the support radius otherwise."""
        reach = 0.0
        for t, r in zip(self.scene.terms, self.solver.wall_ranges):
            if r == "support":
                return self.scene.support_radius
            if r is not None:
                reach = max(reach, float(t.values[r]))
        return reach

    def _upload_parameters(self, dt=None):
        self._snapshot_key = None  # e.g. a new c0 changes the pressure of the same state
        lo, hi = self.scene.domain
        period = np.where(self.scene.periodic, hi - lo, 0.0)
        table = self.solver.param_table(self.scene, self.grid_lo, self.grid_cell, period, self._control_values(dt))
        self._params.from_numpy(table.astype(self.runtime.numpy_real))
        self._mat.from_numpy(self.solver.material_table(self.scene).astype(self.runtime.numpy_real))

    def _reset_status(self):
        status = np.zeros(stepping.STATUS_SIZE)
        status[stepping.DT_MIN] = status[stepping.DT_STABLE_MIN] = np.inf
        status[stepping.FORCE_REBUILD] = 1.0
        self._status.from_numpy(status)
        self._flags.from_numpy(np.zeros(stepping.FLAGS_SIZE, np.int32))

    def close(self):
        """Free the Taichi arrays now (they are also freed when the object is dropped)."""
        if getattr(self, "_C", None) is not None and runtime._current is self.runtime:
            for array in (*self._C, *self._S, *(self._good or ()), self._x_ref, self._nlist, self._ncount):
                runtime.free_ndarray(array)
        self._C = self._S = self._cells = self._good = None
        self._cell_of = self._params = self._mat = self._gshape = None
        self._x_ref = self._nlist = self._ncount = None
        self._graph_args = None
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
        """Change runtime parameters, e.g. ``sim.set(alpha=0.05, gravity=(0, -1))``.

        Also accepts :class:`Controls` fields (``dt``, ``max_density_error``...).
        Material constants are set per material: ``sim.set(c0=40.0)`` changes every
        material, ``sim.set_material(1, rho0=500.0)`` one. No kernel is recompiled.
        """
        by_param = {}
        for t in self.scene.terms:
            for k in t.params:
                by_param[k] = t
        material_keys = {"rho0", "c0", "gamma"}
        control_keys = {f.name for f in fields(Controls)} - {"deterministic"}
        for key, value in values.items():
            if key == "smoothing_length":
                self.scene.smoothing_length = float(value)
            elif key in material_keys:
                for m in self.scene.materials:
                    setattr(m, key, float(value))
            elif key in control_keys:
                setattr(self.controls, key, value)
            elif key in by_param:
                by_param[key].values[key] = value
            else:
                names = sorted(set(self.parameters()) | control_keys)
                raise KeyError(f"no parameter {key!r}; parameters: {', '.join(names)}")
        self.scene.validate()
        if "smoothing_length" in values:
            self._setup_grid()
        self._upload_parameters()

    def set_material(self, index: int, **values):
        m = self.scene.materials[index]
        for key, value in values.items():
            if not hasattr(m, key) or key == "name":
                raise KeyError(f"materials have no constant {key!r} (rho0, c0, gamma)")
            setattr(m, key, float(value))
        m.check()
        self._upload_parameters()

    # --- stepping -----------------------------------------------------------------
    def _kernel_args(self):
        return (*self._C, *self._S, self._cell_of, *self._cells, self._params, self._mat, self._gshape,
                self._status, self._flags, self._x_ref, self._nlist, self._ncount)

    def _advance_arrays(self, t_target: float):
        """One step towards `t_target` (its dt is chosen on the device)."""
        if self._graph_args is None:
            args = self._kernel_args()
            self._graph = self.solver.step_graph(self._serial_sort, args)
            self._graph_args = dict(zip(self.solver.ARG_NAMES, args))
        if self._graph is not None:
            self._graph_args["t_target"] = float(t_target)
            self._graph.run(self._graph_args)
        else:
            args = self._kernel_args()
            for kernel in self.solver.kernels(self._serial_sort):
                kernel(*args, float(t_target))

    def _read_status(self):
        """Refresh the host's copy of time, step count, dt and guard flags."""
        read = self._status.arr.read_float
        self.time = read([stepping.TIME])
        self.steps = int(read([stepping.STEPS]))
        self._dt_last = read([stepping.DT])
        self._dt_stable = read([stepping.DT_STABLE])
        self._fail_codes = self._flags.arr.read_int([stepping.CODES])

    @property
    def dt(self) -> float:
        """The fixed time step, or the current adaptive one (before the first step:
        the one the next step will take, from the maxima of the bootstrap evaluation)."""
        if self.controls.dt is not None:
            return self.controls.dt
        if self._dt_last > 0:
            return self._dt_last
        read = self._status.arr.read_float
        signal, acc2 = read([stepping.MAX_SIGNAL]), read([stepping.MAX_ACC2])
        h = self.scene.smoothing_length
        limits = [self.controls.dt_max, self._control_values()["dt_viscous"]]
        if signal > 0:
            limits.append(self.controls.courant * h / signal)
        if acc2 > 0:
            limits.append(self.controls.force_factor * math.sqrt(h / math.sqrt(acc2)))
        return min(limits)

    def _advance(self, t_target: float, max_steps: int | None = None, progress=None, steps0: int = 0) -> None:
        """Step until the clock reaches `t_target` (or `max_steps` steps are done),
        checking the guards every batch of steps."""
        done = 0
        batch = 1
        while True:
            remaining = t_target - self.time
            if max_steps is not None and done >= max_steps:
                return
            if math.isfinite(t_target) and remaining <= 1e-12 * max(1.0, abs(t_target)):
                return
            estimate = math.ceil(remaining / max(self.dt, 1e-300)) if math.isfinite(remaining) else batch
            n = max(1, min(batch, estimate, (max_steps - done) if max_steps is not None else batch))
            self._keep_good_state()
            start = _time.perf_counter()
            before = self.time
            for _ in range(n):
                self._advance_arrays(t_target)
            self._read_status()
            done += n
            if self._fail_codes:
                self._fail()
            if self.time == before:
                raise RuntimeError(f"the time step is zero at t = {self.time:.6g} s (dt limits: "
                                   f"stable {self._dt_stable:.3g} s, controls {self.controls})")
            self._warn_if_dt_unstable()
            if progress is not None:
                progress.update(self.time, self.steps - steps0)
            # batches of ~0.2 s between checks, at most 128 steps: each batch starts
            # with a device copy of the state (the last good state for a diagnosis),
            # which cost ~7 % of the run time at 50 ms batches (20k particles)
            elapsed = _time.perf_counter() - start
            batch = max(1, min(128, int(n * 0.2 / max(elapsed, 1e-6))))

    def step(self, n: int = 1, dt: float | None = None):
        """Advance `n` steps: of `dt` if given, else of the fixed or adaptive step."""
        if dt is not None:
            self._upload_parameters(dt=dt)
        try:
            self._advance(math.inf, max_steps=n)
        finally:
            if dt is not None:
                self._upload_parameters()

    def _warn_if_dt_unstable(self):
        if self.controls.dt is None or self._warned_dt:
            return
        limit = self._status.arr.read_float([stepping.DT_STABLE_MIN])
        if self.controls.dt > limit:
            self._warned_dt = True
            warnings.warn(
                f"fixed dt = {self.controls.dt:.3g} s is above the stability limit {limit:.3g} s "
                f"(CFL {self.controls.courant} h/(c+|v|), force {self.controls.force_factor} sqrt(h/|a|)); "
                "expect a blow-up, or leave dt unset for the adaptive step",
                RuntimeWarning,
                stacklevel=3,
            )

    def run(self, t_end=None, frames=None, out=None, progress=False, callback=None,
            checkpoint_every: int | None = None, _writer_state=None) -> RunSummary:
        """Advance to `t_end` (default: the scene's), writing `frames` VTK frames (plus
        the initial one, when starting from t = 0) to the folder `out`.

        Steps are shortened where needed so that frames land exactly on
        ``t0 + (t_end - t0) k / frames``. `callback(sim)` is called after every frame;
        with `checkpoint_every` = k a checkpoint is written to ``out/checkpoint``
        every k frames (:meth:`save_checkpoint`). A tripped guard raises
        :class:`SimulationError` after writing the last good state and the offending
        particles to `out`.
        """
        from .io.progress import Progress
        from .io.vtk import VTKWriter

        t_end = self.scene.t_end if t_end is None else float(t_end)
        frames = self.scene.frames if frames is None else int(frames)
        if frames < 1:
            raise ValueError("frames must be at least 1")
        t0 = self.time
        frame_times = [t0 + (t_end - t0) * (k + 1) / frames for k in range(frames)]
        self._out = Path(out) if out is not None else None
        writer = VTKWriter(out, self, resume=_writer_state) if out is not None else None
        written = 0
        if writer is not None and self.steps == 0:
            writer.write(self)
            written += 1
        self._run_stats_start()
        steps0 = self.steps
        rebuilds0 = self.list_rebuilds
        start = _time.perf_counter()
        with Progress(t0, t_end, enabled=progress) as bar:
            for k, t_frame in enumerate(frame_times):
                self._advance(t_frame, progress=bar, steps0=steps0)
                bar.update(self.time, self.steps - steps0, force=True)
                if writer is not None:
                    writer.write(self)
                    written += 1
                if callback is not None:
                    callback(self)
                if checkpoint_every and out is not None and (k + 1) % checkpoint_every == 0:
                    self.save_checkpoint(Path(out) / "checkpoint", t_end=t_end, frames_left=frames - k - 1,
                                         writer=writer)
        ti.sync()
        wall = _time.perf_counter() - start
        dt_min, dt_mean, dt_max = self._run_stats_end(self.steps - steps0)
        return RunSummary(self.n, self.n_fluid, self.steps - steps0, self.time, wall, written,
                          str(writer.folder) if writer else None, dt_min, dt_mean, dt_max,
                          self._flags.arr.read_int([stepping.REMOVED_COUNT]),
                          self.list_rebuilds - rebuilds0 if self.solver.lists else None)

    def _run_stats_start(self):
        self._status.arr.write_float([stepping.DT_MIN], math.inf)
        self._status.arr.write_float([stepping.DT_MAX], 0.0)
        self._dt_sum0 = self._status.arr.read_float([stepping.DT_SUM])

    def _run_stats_end(self, steps):
        read = self._status.arr.read_float
        if steps == 0:
            return (float("nan"),) * 3
        return read([stepping.DT_MIN]), (read([stepping.DT_SUM]) - self._dt_sum0) / steps, read([stepping.DT_MAX])

    # --- guards -------------------------------------------------------------------
    def _keep_good_state(self):
        """Copy the current state aside (device to device) before a batch of steps."""
        if self._good is None:
            self._good = tuple(ti.ndarray(a.dtype if i else self.solver.vec, a.shape) for i, a in enumerate(self._C))
        for good, current in zip(self._good, self._C):
            good.copy_from(current)
        self._good_time, self._good_steps = self.time, self.steps
        self._good_dt_stable = self._status.arr.read_float([stepping.DT_STABLE_MIN])

    def _fail(self):
        from .engine import diagnosis

        report = diagnosis.collect(self)
        files = []
        folder = getattr(self, "_out", None)
        if folder is None:  # no output folder chosen: do not litter the working directory
            import tempfile
            folder = Path(tempfile.mkdtemp(prefix=f"taisph-{self.scene.name}-"))
        try:
            files = diagnosis.write_evidence(self, report, folder)
        finally:
            message = diagnosis.explain(self, report, files)
        raise SimulationError(message, report, files)

    # --- checkpoints ----------------------------------------------------------------
    def save_checkpoint(self, folder, t_end=None, frames_left=None, writer=None) -> Path:
        """Write the complete state to `folder`, atomically (a temporary folder renamed
        over the old one): every particle array in its current memory order, the
        device clock and dt history, the guard flags, the grid, the scene (terms,
        parameters, materials) and the controls. :meth:`from_checkpoint` resumes it."""
        folder = Path(folder)
        tmp = folder.with_name(folder.name + ".tmp")
        if tmp.exists():
            shutil.rmtree(tmp)
        tmp.mkdir(parents=True)
        arrays = {f"C{k}": a.to_numpy() for k, a in enumerate(self._C)}
        arrays["status"] = self._status.to_numpy()
        arrays["flags"] = self._flags.to_numpy()
        # the neighbour lists and the cells of their last rebuild: a resumed run walks
        # the same lists in the same order (bit for bit in deterministic mode)
        for name in ("x_ref", "nlist", "ncount"):
            arrays[name] = getattr(self, "_" + name).to_numpy()
        arrays["cell_start"] = self._cells[1].to_numpy()
        np.savez(tmp / "state.npz", **arrays)
        meta = dict(
            version=CHECKPOINT_VERSION,
            scene=self.scene,
            controls=self.controls,
            runtime=(self.runtime.arch, self.runtime.precision),
            grid=(self.grid_lo, self.grid_cell, self.grid_shape),
            serial_sort=self._serial_sort,
            t_end=t_end,
            frames_left=frames_left,
            out=str(writer.folder) if writer is not None else None,
            writer=(writer.frame, writer.entries) if writer is not None else None,
        )
        with open(tmp / "meta.pickle", "wb") as f:
            pickle.dump(meta, f)
        if folder.exists():
            old = folder.with_name(folder.name + ".old")
            if old.exists():
                shutil.rmtree(old)
            os.replace(folder, old)
            os.replace(tmp, folder)
            shutil.rmtree(old)
        else:
            os.replace(tmp, folder)
        return folder

    @classmethod
    def from_checkpoint(cls, folder, arch=None, threads=None) -> "Simulation":
        """A simulation continuing exactly where :meth:`save_checkpoint` stopped."""
        folder = Path(folder)
        with open(folder / "meta.pickle", "rb") as f:
            meta = pickle.load(f)
        if meta.get("version") != CHECKPOINT_VERSION:
            raise ValueError(f"{folder}: checkpoint version {meta.get('version')}, expected {CHECKPOINT_VERSION}")
        saved_arch, precision = meta["runtime"]
        controls = {f.name: getattr(meta["controls"], f.name) for f in fields(Controls)}
        sim = cls(meta["scene"], arch=arch or saved_arch, precision=precision, threads=threads,
                  _restore=(folder, meta), **controls)
        sim.checkpoint_meta = meta
        return sim

    def _restore(self, restore):
        folder, meta = restore
        data = np.load(folder / "state.npz")
        for k, arr in enumerate(self._C):
            arr.from_numpy(data[f"C{k}"])
        self._serial_sort = meta["serial_sort"]
        self._setup_grid(meta["grid"])
        self._upload_parameters()
        self._status.from_numpy(data["status"])
        self._flags.from_numpy(data["flags"])
        for name in ("x_ref", "nlist", "ncount"):
            getattr(self, "_" + name).from_numpy(data[name])
        self._cells[1].from_numpy(data["cell_start"])

    # --- state as numpy, in particle-id order ------------------------------------
    def _arrays(self):
        """All stored quantities as numpy, in particle-id order (cached per step)."""
        key = (self.steps, self.time)
        if self._snapshot_key != key:
            self._snapshot = self._to_numpy(self._C)
            self._snapshot_key = key
        return self._snapshot

    def _to_numpy(self, buffers):
        """(vectors, scalars, integers) of a state buffer in particle-id order, with
        the pressure recomputed from density by the equation of state."""
        self.solver.update_pressure(*buffers, self._params, self._mat)
        vec, sca, ints = (a.to_numpy() for a in buffers)
        order = np.argsort(ints[self.solver.layout.q.id], kind="stable")
        return vec[:, order].astype(float), sca[:, order].astype(float), ints[:, order]

    def _vector(self, name):
        return self._arrays()[0][getattr(self.solver.layout.q, name)].copy()

    def _scalar(self, name):
        return self._arrays()[1][getattr(self.solver.layout.q, name)].copy()

    def _integer(self, name):
        return self._arrays()[2][getattr(self.solver.layout.q, name)].copy()

    def positions(self) -> np.ndarray:
        """(N, dim) positions, in particle-id order (the scene's order)."""
        return self._vector("position")

    def velocities(self) -> np.ndarray:
        return self._vector("velocity")

    def density(self) -> np.ndarray:
        return self._scalar("density")

    def pressure(self) -> np.ndarray:
        """Pressure from the equation of state at the current density."""
        return self._scalar("pressure")

    def masses(self) -> np.ndarray:
        return self._scalar("mass")

    def ids(self) -> np.ndarray:
        return self._integer("id")

    def materials(self) -> np.ndarray:
        return self._integer("material")

    def kinds(self) -> np.ndarray:
        return self._integer("kind")

    def quantity(self, name: str) -> np.ndarray:
        """Any stored per-particle quantity by name, in particle-id order."""
        kind = self.solver.layout.kind_of(name)
        return {"vector": self._vector, "scalar": self._scalar, "integer": self._integer}[kind](name)

    def neighbour_pairs(self) -> np.ndarray:
        """Ordered pairs of particle ids closer than the kernel support, as the
        neighbour sums visit them: an (M, 2) array (each pair appears as (i, j) and
        (j, i)). With neighbour lists and terms that need walls only within a short
        range (Lennard-Jones walls), fluid-wall pairs beyond that range plus the skin
        are not visited and not listed. Leaves the simulation as it was."""
        return self.solver.neighbour_pairs(self)

    @property
    def fluid(self) -> np.ndarray:
        """Boolean mask of (active) fluid particles, in particle-id order."""
        return self.kinds() == FLUID

    @property
    def list_rebuilds(self) -> int:
        """How many times the neighbour lists were built so far (every step without
        lists: see ``Scene.neighbour_skin``)."""
        if not self.solver.lists:
            return self.steps
        return int(self._status.arr.read_float([stepping.REBUILDS]))

    @property
    def wall(self) -> np.ndarray:
        return self.kinds() == WALL

    def bytes_per_particle(self) -> int:
        """Memory of the particle state per particle: the stored rows, three times
        (current and cell-sorted buffers, the saved good state), the cell index, and
        with neighbour lists their reference position, count and entries."""
        L = self.solver.layout
        real = 4 if self.runtime.precision == "f32" else 8
        row = self.dim * real * len(L.vectors) + real * len(L.scalars) + 4 * len(L.integers)
        lists = self.dim * real + 4 + 4 * self.list_capacity if self.solver.lists else 0
        return 3 * row + 4 + lists

    def effects(self) -> list:
        """Names of the terms compiled into this simulation's kernels."""
        return [t.name for t in self.scene.terms]

    def total_mass(self) -> float:
        return float(self.masses()[self.fluid].sum())

    def momentum(self) -> np.ndarray:
        m = self.masses()[self.fluid]
        return (m[:, None] * self.velocities()[self.fluid]).sum(axis=0)

    def kinetic_energy(self) -> float:
        m = self.masses()[self.fluid]
        v = self.velocities()[self.fluid]
        return float(0.5 * (m * (v * v).sum(axis=1)).sum())
