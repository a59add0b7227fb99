"""A running simulation: the particle state of one scene, stepped by a cached solver."""

from __future__ import annotations

import math
import time as _time
from dataclasses import dataclass

import numpy as np
import taichi as ti

from . import runtime, solver as _solver
from .grid import layout_grid
from .layout import FLUID, WALL

# Grids with more cells than this per particle are refused: the domain is too large
# for the smoothing length (a typo in a unit, usually) and memory would explode.
MAX_CELLS_PER_PARTICLE = 64


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

    @property
    def particle_steps_per_second(self) -> float:
        """Fluid particle-steps per wall second (the number SPH codes compare)."""
        return self.fluid_particles * self.steps / self.wall_time if self.wall_time > 0 else float("nan")

    def __str__(self) -> str:
        out = f", output in {self.out}" if self.out else ""
        return (
            f"{self.fluid_particles} fluid + {self.particles - self.fluid_particles} wall particles, "
            f"{self.steps} steps to t = {self.sim_time:.4g} s in {self.wall_time:.2f} s wall "
            f"({self.particle_steps_per_second / 1e6:.2f} M fluid particle-steps/s), "
            f"{self.frames} frames{out}"
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
    recompiling. :meth:`close` (or dropping the last reference) frees the arrays.
    """

    def __init__(self, scene, arch: str | None = None, precision: str | None = None, threads: int | None = None):
        scene.validate()
        self.scene = scene
        self.runtime = runtime.init(arch, precision, threads)
        self.solver = _solver.get(scene)
        self.dim = scene.dim
        self.n = scene.n
        self.n_fluid = scene.n_fluid
        self.time = 0.0
        self.steps = 0
        self.dt = scene.dt if scene.dt is not None else scene.stable_dt()
        self._serial_sort = self.n < _solver.SERIAL_SORT_BELOW
        self._graph_args = None
        self._allocate()
        self._upload(scene)
        runtime.register(self)
        self._step_arrays(0.0)  # bootstrap: pressure and (for pc) the first rates

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
        self._cells = None

    def _setup_grid(self):
        scene = self.scene
        support = scene.support_radius
        pos = self.scene.position if self._cells is None else self.positions()
        lo, cell, shape = layout_grid(scene.domain, scene.periodic, support, pos)
        n_cells = int(np.prod(shape))
        if n_cells > MAX_CELLS_PER_PARTICLE * self.n + 4096:
            raise ValueError(
                f"the neighbour grid would need {n_cells} cells of {support:g} m for {self.n} particles "
                f"(domain {scene.domain[0]} .. {scene.domain[1]}); the domain is too large for the "
                "smoothing length"
            )
        self.grid_lo, self.grid_cell, self.grid_shape = lo, cell, shape
        self._cells = tuple(ti.ndarray(ti.i32, k) for k in (n_cells, n_cells + 1, n_cells))
        self._cells[0].fill(0)
        self._graph_args = None  # arrays changed: rebind the step graph
        g = np.zeros(4, np.int32)
        g[: self.dim] = shape
        g[self.dim : 3] = 1
        g[3] = n_cells
        self._gshape.from_numpy(g)

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

    def _upload_parameters(self):
        lo, hi = self.scene.domain
        period = np.where(self.scene.periodic, hi - lo, 0.0)
        table = self.solver.param_table(self.scene, self.grid_lo, self.grid_cell, period)
        self._params.from_numpy(table.astype(self.runtime.numpy_real))
        self._mat.from_numpy(self.solver.material_table(self.scene).astype(self.runtime.numpy_real))

    def close(self):
        """Free the Taichi arrays now (they are also freed when the object is dropped)."""
        if getattr(self, "_C", None) is not None and runtime._current is self.runtime:
            for array in (*self._C, *self._S):
                runtime.free_ndarray(array)
        self._C = self._S = self._cells = None
        self._cell_of = self._params = self._mat = self._gshape = None
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

        Material constants are set per material: ``sim.set(c0=40.0)`` changes every
        material, ``sim.set_material(1, rho0=500.0)`` one. No kernel is recompiled.
        """
        by_param = {}
        for t in self.scene.terms:
            for k in t.params:
                by_param[k] = t
        material_keys = {"rho0", "c0", "gamma"}
        for key, value in values.items():
            if key == "smoothing_length":
                self.scene.smoothing_length = float(value)
            elif key in material_keys:
                for m in self.scene.materials:
                    setattr(m, key, float(value))
            elif key in by_param:
                by_param[key].values[key] = value
            else:
                raise KeyError(f"no parameter {key!r}; parameters: {', '.join(sorted(self.parameters()))}")
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
        return (*self._C, *self._S, self._cell_of, *self._cells, self._params, self._mat, self._gshape)

    def _step_arrays(self, dt: float):
        if self._graph_args is None:
            args = self._kernel_args()
            self._graph = self.solver.step_graph(self._serial_sort, args)
            self._graph_args = dict(zip(self.solver.ARG_NAMES, args))
        if self._graph is not None:
            self._graph_args["dt"] = dt
            self._graph.run(self._graph_args)
        else:
            args = self._kernel_args()
            for kernel in self.solver.kernels(self._serial_sort):
                kernel(*args, dt)

    def step(self, n: int = 1, dt: float | None = None):
        """Advance `n` steps of `dt` (default: the scene's dt)."""
        dt = self.dt if dt is None else dt
        for _ in range(n):
            self._step_arrays(dt)
            self.time += dt
            self.steps += 1

    def run(self, t_end: float | None = None, frames: int | None = None, out=None, progress: bool = False,
            dt: float | None = None, callback=None) -> RunSummary:
        """Advance to `t_end` (default: the scene's), writing `frames` VTK frames
        (plus the initial one, when starting from t = 0) to the folder `out`.

        Steps are shortened where needed so that frames land exactly on
        ``t_end * k / frames``. `callback(sim)` is called after every frame.
        """
        from .progress import Progress
        from .vtk import VTKWriter

        t_end = self.scene.t_end if t_end is None else float(t_end)
        dt = self.dt if dt is None else float(dt)
        frames = self.scene.frames if frames is None else int(frames)
        if frames < 1:
            raise ValueError("frames must be at least 1")
        t0 = self.time
        frame_times = [t0 + (t_end - t0) * (k + 1) / frames for k in range(frames)]
        writer = VTKWriter(out, self) if out is not None else None
        written = 0
        if writer is not None and self.steps == 0:
            writer.write(self)
            written += 1
        steps0 = self.steps
        start = _time.perf_counter()
        eps = 1e-9 * dt
        with Progress(t0, t_end, enabled=progress) as bar:
            for t_frame in frame_times:
                while self.time < t_frame - eps:
                    h = min(dt, t_frame - self.time)
                    # avoid a sliver of a step before the frame: split the last two evenly
                    if dt < t_frame - self.time < 1.5 * dt:
                        h = 0.5 * (t_frame - self.time)
                    self._step_arrays(h)
                    self.time += h
                    self.steps += 1
                    bar.update(self.time, self.steps - steps0)
                self.time = t_frame
                bar.update(self.time, self.steps - steps0, force=True)
                if writer is not None:
                    writer.write(self)
                    written += 1
                if callback is not None:
                    callback(self)
        ti.sync()
        wall = _time.perf_counter() - start
        return RunSummary(self.n, self.n_fluid, self.steps - steps0, self.time, wall, written,
                          str(writer.folder) if writer else None)

    # --- state as numpy, in particle-id order ------------------------------------
    def _arrays(self):
        """All stored quantities as numpy, in particle-id order (cached per step)."""
        key = (self.steps, self.time)
        if getattr(self, "_snapshot_key", None) != key:
            self.solver.update_pressure(*self._C, self._params, self._mat)
            vec, sca, ints = (a.to_numpy() for a in self._C)
            order = np.argsort(ints[self.solver.layout.q.id], kind="stable")
            self._snapshot = (vec[:, order].astype(float), sca[:, order].astype(float), ints[:, order])
            self._snapshot_key = key
        return self._snapshot

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
        """Ordered pairs of particle ids closer than the kernel support, as found by
        the neighbour grid: an (M, 2) array (each pair appears as (i, j) and (j, i))."""
        return self.solver.neighbour_pairs(self)

    @property
    def fluid(self) -> np.ndarray:
        """Boolean mask of fluid particles, in particle-id order."""
        return self.scene.kind == FLUID

    @property
    def wall(self) -> np.ndarray:
        return self.scene.kind == WALL

    def total_mass(self) -> float:
        return float(self.masses()[self.fluid].sum())

    def momentum(self) -> np.ndarray:
        m = self.masses()[self.fluid]
        return (m[:, None] * self.velocities()[self.fluid]).sum(axis=0)

    def kinetic_energy(self) -> float:
        m = self.masses()[self.fluid]
        v = self.velocities()[self.fluid]
        return float(0.5 * (m * (v * v).sum(axis=1)).sum())
