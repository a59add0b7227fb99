"""The device state of one simulation: every Taichi array the step kernels take.

Particle state is structure-of-arrays (:mod:`.layout`), held twice: ``C``, the
current state, and ``S``, its cell-sorted copy the rates are computed from. Around it:
the neighbour grid's cell arrays, the runtime parameters and material table, the
device clock and guard flags (:mod:`.status`), the neighbour lists, and a copy of the
last state that passed the guards. :class:`State` allocates, uploads, reads back and
frees them; nothing else touches the arrays.
"""

from __future__ import annotations

import numpy as np
import taichi as ti

from . import neighbours, runtime
from . import status as st
from .assembly import Args


class State:
    def __init__(self, scene, solver, rt: runtime.Runtime):
        self.solver = solver
        self.runtime = rt
        L = solver.layout
        n = scene.n
        self.n = n

        def buffers():
            return (ti.ndarray(solver.vec, (len(L.vectors), n)), ti.ndarray(rt.real, (len(L.scalars), n)),
                    ti.ndarray(ti.i32, (len(L.integers), n)))

        self.C, self.S = buffers(), buffers()
        self.cell_of = ti.ndarray(ti.i32, n)
        self.cells = None  # (count, start, fill): sized by setup_grid
        self.params = ti.ndarray(rt.real, solver.n_params)
        self.mat = ti.ndarray(rt.real, (len(scene.materials), len(solver.material_columns)))
        self.gshape = ti.ndarray(ti.i32, 4)
        self.status = ti.ndarray(ti.f64, st.STATUS_SIZE)
        self.flags = ti.ndarray(ti.i32, st.FLAGS_SIZE)
        # neighbour lists (taisph.engine.neighbours); a dummy row when the scene has none
        self.list_capacity = neighbours.list_capacity(scene) if solver.lists else 1
        rows = n if solver.lists else 1
        self.x_ref = ti.ndarray(solver.vec, rows)
        self.nlist = ti.ndarray(ti.i32, (rows, self.list_capacity))
        self.ncount = ti.ndarray(ti.i32, rows)
        self.ncount.fill(-1)
        # outputs of auxiliary kernels (run_auxiliary); dummies in a step
        self.aux_int, self.aux_real = ti.ndarray(ti.i32, (1, 1)), ti.ndarray(rt.real, (1, 1))
        self.good = None  # copy of the last state that passed the guards (keep_good)
        self.good_time = self.good_steps = 0
        self.good_dt_stable = float("inf")
        self.grid = None  # (lo, cell edges, shape)

    def args(self, current=None) -> Args:
        """The kernel arguments; `current`: other buffers in place of C."""
        return Args(*(current or self.C), *self.S, self.cell_of, *self.cells, self.params, self.mat, self.gshape,
                    self.status, self.flags, self.x_ref, self.nlist, self.ncount, self.aux_int, self.aux_real)

    # --- upload -----------------------------------------------------------------------
    def upload_particles(self, scene):
        """Scene arrays -> C (particle ids = scene order)."""
        L = self.solver.layout
        n, d = self.n, scene.dim
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
        for arr, data in zip(self.C, (vec, sca, ints)):
            arr.from_numpy(data)

    def setup_grid(self, scene, grid=None):
        """Size the cell arrays for the grid `grid` = (lo, cell edges, shape), by default
        one laid out around the current positions."""
        if grid is None:
            positions = scene.position if self.cells is None else self.to_numpy()[0][self.solver.layout.q.position]
            grid = neighbours.layout_grid(scene.domain, scene.periodic, neighbours.list_reach(scene), positions)
        lo, cell, shape = grid
        n_cells = int(np.prod(shape))
        if n_cells > neighbours.MAX_CELLS_PER_PARTICLE * self.n + 4096:
            raise ValueError(
                f"the neighbour grid would need {n_cells} cells of {scene.support_radius:g} m for {self.n} "
                f"particles (domain {scene.domain[0]} .. {scene.domain[1]}); the domain is too large for the "
                "smoothing length"
            )
        self.grid = (np.asarray(lo), np.asarray(cell), tuple(shape))
        for array in self.cells or ():
            runtime.free_ndarray(array)
        self.cells = tuple(ti.ndarray(ti.i32, k) for k in (n_cells, n_cells + 1, n_cells))
        self.cells[0].fill(0)
        g = np.zeros(4, np.int32)
        g[: scene.dim] = shape
        g[scene.dim : 3] = 1
        g[3] = n_cells
        self.gshape.from_numpy(g)
        self.write(st.FORCE_REBUILD, 1.0)  # new cells: new lists

    def upload_parameters(self, scene, controls, dt=None):
        table = self.solver.param_table(scene, self.grid[0], self.grid[1], controls, dt)
        self.params.from_numpy(table.astype(self.runtime.numpy_real))
        self.mat.from_numpy(self.solver.material_table(scene).astype(self.runtime.numpy_real))

    def reset_status(self):
        status = np.zeros(st.STATUS_SIZE)
        status[st.DT_MIN] = status[st.DT_STABLE_MIN] = np.inf
        status[st.FORCE_REBUILD] = 1.0
        self.status.from_numpy(status)
        self.flags.from_numpy(np.zeros(st.FLAGS_SIZE, np.int32))

    # --- status ------------------------------------------------------------------------
    def read(self, index: int) -> float:
        return self.status.arr.read_float([index])

    def write(self, index: int, value: float):
        self.status.arr.write_float([index], value)

    def read_flag(self, index: int) -> int:
        return self.flags.arr.read_int([index])

    # --- download -------------------------------------------------------------------
    def to_numpy(self, buffers=None):
        """(vectors, scalars, integers) of C (or of `buffers`) in particle-id order, with
        the pressure recomputed from density by the equation of state."""
        buffers = buffers or self.C
        self.solver.pressure_kernel()(*self.args(buffers), 0.0)
        vec, sca, ints = (a.to_numpy() for a in buffers)
        order = np.argsort(ints[self.solver.layout.q.id], kind="stable")
        return vec[:, order].astype(float), sca[:, order].astype(float), ints[:, order]

    # --- the last good state ------------------------------------------------------------
    def keep_good(self, time: float, steps: int):
        """Copy C aside (device to device) before a batch of steps."""
        if self.good is None:
            self.good = tuple(ti.ndarray(self.solver.vec if i == 0 else a.dtype, a.shape)
                              for i, a in enumerate(self.C))
        for good, current in zip(self.good, self.C):
            good.copy_from(current)
        self.good_time, self.good_steps = time, steps
        self.good_dt_stable = self.read(st.DT_STABLE_MIN)

    # --- checkpoints --------------------------------------------------------------------
    def arrays(self) -> dict:
        """Everything a restart needs, as numpy: C, status, flags, the neighbour lists and
        the cells of their last rebuild (a resumed run walks the same lists in the same
        order: bit for bit in deterministic mode)."""
        arrays = {f"C{k}": a.to_numpy() for k, a in enumerate(self.C)}
        for name in ("status", "flags", "x_ref", "nlist", "ncount"):
            arrays[name] = getattr(self, name).to_numpy()
        arrays["cell_start"] = self.cells[1].to_numpy()
        return arrays

    def restore(self, arrays):
        """The inverse of :meth:`arrays` (the grid already set up)."""
        for k, arr in enumerate(self.C):
            arr.from_numpy(arrays[f"C{k}"])
        for name in ("status", "flags", "x_ref", "nlist", "ncount"):
            getattr(self, name).from_numpy(arrays[name])
        self.cells[1].from_numpy(arrays["cell_start"])

    # --- tests of the neighbour search ------------------------------------------------
    def neighbour_pairs(self, serial_sort: bool, time: float) -> np.ndarray:
        """(M, 2) particle ids (i, j) of the pairs the neighbour sums visit now."""
        sort = self.solver.step_kernels(serial_sort)[0]
        count, fill = self.solver.pair_kernels()
        # The sort starts a step: with a target time of now its dt is 0, so the state
        # (C) is untouched, but it resets the maxima the next step's dt is chosen from
        # and may rebuild the neighbour lists (in S's order, not C's). Keep the clock,
        # the maxima, the lists and the cells they refer to as they were.
        kept = [(a, a.to_numpy()) for a in (self.status, self.x_ref, self.nlist, self.ncount, *self.cells)]
        sort(*self.args(), time)  # sorts S by cell
        try:
            counts = self.run_auxiliary(count, time, aux_int=(self.n, 1))[0][:, 0]
            table = self.run_auxiliary(fill, time, aux_int=(self.n, max(1, int(counts.max(initial=0)))))[0]
        finally:
            for array, values in kept:
                array.from_numpy(values)
        ids = self.S[2].to_numpy()[self.solver.layout.q.id]
        rows = np.repeat(np.arange(self.n), counts)
        cols = np.arange(len(rows)) - np.repeat(np.cumsum(counts) - counts, counts)  # k-th neighbour of its row
        return np.stack([ids[rows], table[rows, cols]], axis=1).astype(np.int32)

    def run_auxiliary(self, kernel, time: float, aux_int=(1, 1), aux_real=(1, 1)):
        """Run an auxiliary kernel (one of the solver's, with the step signature) into
        fresh output arrays of the given shapes; returns them as numpy (int, real)."""
        dummies = self.aux_int, self.aux_real
        try:
            self.aux_int, self.aux_real = ti.ndarray(ti.i32, aux_int), ti.ndarray(self.runtime.real, aux_real)
            kernel(*self.args(), time)
            return self.aux_int.to_numpy(), self.aux_real.to_numpy()
        finally:
            self.aux_int, self.aux_real = dummies

    def free(self):
        """Free the Taichi arrays now (vector ndarrays leak otherwise: taichi#8763)."""
        if runtime.is_current(self.runtime):
            for array in (*self.C, *self.S, *(self.good or ()), self.x_ref, self.nlist, self.ncount):
                runtime.free_ndarray(array)
        self.C = self.S = self.cells = self.good = None
