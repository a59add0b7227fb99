"""The per-step Taichi kernels, assembled at compile time from a scene's terms.

A step is two kernel launches (thread wake-ups are expensive: about 0.1-0.3 ms per
parallel loop on the 2-core VMs we measure on, so passes are fused):

``sort``   cell index and count per particle, serial prefix sum over the cells, then
           each particle's whole state is scattered to its cell-sorted slot. The
           integrator's predictor and the equation of state run here, per particle.
``force``  for every fluid particle: sum the enabled terms over its neighbours
           (``ti.static`` loop over the terms), then the integrator's update writes
           the new state. Wall particles are carried over (moving rigidly).

State lives in two buffers of Taichi ndarrays (see :mod:`taisph.layout`): ``C``,
the current state, and ``S``, the cell-sorted scratch copy that ``force`` reads.
Kernels take ndarrays as arguments, so one compiled kernel serves simulations of
every size; a :class:`Solver` is cached per compile-time configuration (dimension,
precision, kernel, integrator, equation of state, terms and their options).
"""


import collections
import math

import numpy as np
import taichi as ti

from . import integrators, runtime, smoothing
from .grid import Grid
from .layout import FLUID, Layout

Ctx = collections.namedtuple(
    "Ctx", "Cv Cs Ci Sv Ss Si cell_of cell_count cell_start cell_fill params mat gshape"
)

# Below this many particles the sort pass runs serially: waking the thread pool
# costs more than the work (measured, see docs/performance.md).
SERIAL_SORT_BELOW = 60_000


class Config(collections.namedtuple("Config", "dim kernel integrator eos terms")):
    """Everything that changes the compiled code (not parameter values)."""


def config_of(scene) -> Config:
    return Config(
        dim=scene.dim,
        kernel=scene.kernel,
        integrator=integrators.INTEGRATORS[scene.integrator].name,
        eos=scene.eos.compile_key(),
        terms=tuple(t.compile_key() for t in scene.terms),
    )


_cache: dict = {}
runtime.on_reset(_cache.clear)


def get(scene) -> "Solver":
    """The solver for `scene`'s configuration, compiled at most once per process."""
    rt = runtime.current()
    key = (rt, config_of(scene))
    solver = _cache.get(key)
    if solver is None:
        solver = Solver(scene, rt)
        _cache[key] = solver
    return solver


class Solver:
    def __init__(self, scene, rt: runtime.Runtime):
        self.dim = dim = scene.dim
        self.real = real = rt.real
        self.kernel = smoothing.make(scene.kernel, dim)

        # --- what is stored --------------------------------------------------
        integrated = []
        for t in scene.terms:
            integrated.extend(t.integrates.items())
        self.integrated = tuple(integrated)
        integ = integrators.make(scene.integrator, self.integrated)
        extra_v, extra_s = integ.quantities()
        vectors = list(extra_v)
        scalars = list(extra_s) + list(scene.eos.scalars)
        integers = []
        for t in scene.terms:
            vectors += t.vectors
            scalars += t.scalars
            integers += t.integers
        self.layout = layout = Layout(vectors, scalars, integers)

        # --- runtime parameter table ----------------------------------------
        rows = {"smoothing_length": 0, "grid_lo": 1, "grid_inv_cell": 1 + dim}
        size = 2 + dim
        for t in scene.terms:
            for name, default in t.params.items():
                if name in rows:
                    raise ValueError(f"parameter {name!r} is declared by two terms")
                rows[name] = size
                size += dim if default == "vector" else 1
        self.param_rows = rows
        self.n_params = size
        self.material_columns = scene.eos.columns
        mcols = collections.namedtuple("MaterialColumns", scene.eos.columns)(*range(len(scene.eos.columns)))

        # --- compile-time assembly -------------------------------------------
        self.eos = scene.eos.bind(layout, mcols)
        rate_rows = collections.namedtuple("RateRows", [r for _, r in self.integrated] or ["none"])(
            *range(max(1, len(self.integrated)))
        )
        self.terms = [t.bound(layout, rows, mcols, self.eos, rate_rows) for t in scene.terms]
        self.integrator = integ.bind(layout)
        self.grid = Grid(dim, real, rows["grid_lo"], rows["grid_inv_cell"])
        # rates.acc: dv/dt; rates.d[k]: rate of the k-th integrated scalar (a Taichi
        # vector needs length >= 1, hence the max).
        self.Rates = ti.types.struct(
            acc=ti.types.vector(dim, real), d=ti.types.vector(max(1, len(self.integrated)), real)
        )
        self.vec = ti.types.vector(dim, real)
        self._kernels = {}

    # ------------------------------------------------------------------------
    def param_table(self, scene) -> np.ndarray:
        """Runtime parameter values of `scene`, laid out as the kernels read them."""
        table = np.zeros(self.n_params)
        table[self.param_rows["smoothing_length"]] = scene.smoothing_length
        for t in scene.terms:
            for name, value in t.param_values(self.dim).items():
                r = self.param_rows[name]
                table[r : r + len(value)] = value
        return table

    def material_table(self, scene) -> np.ndarray:
        return np.array([self.eos.material_row(m) for m in scene.materials], dtype=float)

    def kernels(self, serial_sort: bool):
        key = ("step", serial_sort)
        if key not in self._kernels:
            self._kernels[key] = (self._build_sort(serial_sort), self._build_force())
        return self._kernels[key]

    ARG_NAMES = ("Cv", "Cs", "Ci", "Sv", "Ss", "Si", "cell_of", "cell_count", "cell_start", "cell_fill",
                 "params", "mat", "gshape")

    def step_graph(self, serial_sort: bool, args):
        """A Taichi graph running one step (sort, force) in a single call from Python.

        A plain kernel call costs about 13 us of Python argument handling per ndarray
        argument (28 per step here); a graph binds them in C++. Returns None if the
        backend cannot build graphs (then the kernels are called directly)."""
        key = ("graph", serial_sort)
        if key not in self._kernels:
            sort, force = self.kernels(serial_sort)
            G = ti.graph
            try:
                symbols = []
                for name, array in zip(self.ARG_NAMES, args):
                    dtype = self.vec if name in ("Cv", "Sv") else array.dtype
                    symbols.append(G.Arg(G.ArgKind.NDARRAY, name, dtype=dtype, ndim=len(array.shape)))
                dt = G.Arg(G.ArgKind.SCALAR, "dt", self.real)
                builder = G.GraphBuilder()
                builder.dispatch(sort, *symbols, dt)
                builder.dispatch(force, *symbols, dt)
                self._kernels[key] = builder.compile()
            except Exception:  # pragma: no cover - backend without graph support
                self._kernels[key] = None
        return self._kernels[key]

    def update_pressure(self, Cv, Cs, Ci, params, mat):
        """Fill the pressure row of the current state from its density (for output)."""
        if "pressure" not in self._kernels:
            self._kernels["pressure"] = self._build_pressure()
        self._kernels["pressure"](Cv, Cs, Ci, params, mat)

    def neighbour_pairs(self, sim) -> np.ndarray:
        """(M, 2) particle ids (i, j), i != j, |x_i - x_j| < support radius, found by
        the grid traversal the force pass uses (for tests of the neighbour search)."""
        if "pairs" not in self._kernels:
            self._kernels["pairs"] = self._build_pairs()
        count, fill = self._kernels["pairs"]
        sort, _ = self.kernels(serial_sort=sim._serial_sort)
        args = sim._kernel_args()
        sort(*args, 0.0)  # sorts S by cell; dt = 0 leaves the state unchanged
        n = sim.n
        counts = ti.ndarray(ti.i32, n)
        count(*args, counts)
        c = counts.to_numpy()
        offsets = np.concatenate([[0], np.cumsum(c)]).astype(np.int32)
        off_nd = ti.ndarray(ti.i32, n + 1)
        off_nd.from_numpy(offsets)
        out = ti.ndarray(ti.i32, (max(1, int(offsets[-1])), 2))
        fill(*args, off_nd, out)
        return out.to_numpy()[: offsets[-1]]

    def compiled_count(self) -> int:
        """How many Taichi kernel instances this solver has compiled (for tests)."""
        total = 0
        for ks in self._kernels.values():
            for k in ks if isinstance(ks, tuple) else (ks,):
                if hasattr(k, "_primal"):
                    total += len(k._primal.compiled_kernels)
        return total

    # ------------------------------------------------------------------------
    def _annotations(self):
        real = self.real
        return dict(
            V=ti.types.ndarray(dtype=self.vec, ndim=2),
            S=ti.types.ndarray(dtype=real, ndim=2),
            I=ti.types.ndarray(dtype=ti.i32, ndim=2),
            I1=ti.types.ndarray(dtype=ti.i32, ndim=1),
            R1=ti.types.ndarray(dtype=real, ndim=1),
        )

    def _build_sort(self, serial: bool):
        a = self._annotations()
        V, S, I, I1, R1 = a["V"], a["S"], a["I"], a["I1"], a["R1"]
        real = self.real
        q = self.layout.q
        nv, ns, ni = len(self.layout.vectors), len(self.layout.scalars), len(self.layout.integers)
        grid, integ, eos = self.grid, self.integrator, self.eos
        derive_terms = [t for t in self.terms if t.has_derive]

        @ti.kernel
        def sort(Cv: V, Cs: S, Ci: I, Sv: V, Ss: S, Si: I, cell_of: I1, cell_count: I1,
                 cell_start: I1, cell_fill: I1, params: R1, mat: S, gshape: I1, dt: real):
            s = ti.static(Ctx(Cv, Cs, Ci, Sv, Ss, Si, cell_of, cell_count, cell_start, cell_fill, params, mat, gshape))
            n = Cv.shape[1]
            ti.loop_config(serialize=serial)
            for i in range(n):
                c = grid.linear(s, grid.coords(s, integ.predicted_position(s, i, dt)))
                cell_of[i] = c
                ti.atomic_add(cell_count[c], 1)
            ti.loop_config(serialize=True)
            for _ in range(1):
                running = 0
                for c in range(gshape[3]):
                    cell_start[c] = running
                    cell_fill[c] = running
                    running += cell_count[c]
                    cell_count[c] = 0
                cell_start[gshape[3]] = running
            ti.loop_config(serialize=serial)
            for i in range(n):
                slot = ti.atomic_add(cell_fill[cell_of[i]], 1)
                for k in ti.static(range(nv)):
                    Sv[k, slot] = Cv[k, i]
                for k in ti.static(range(ns)):
                    Ss[k, slot] = Cs[k, i]
                for k in ti.static(range(ni)):
                    Si[k, slot] = Ci[k, i]
                integ.predict(s, i, slot, dt)
                eos.derive(s, slot)
                for t in ti.static(derive_terms):
                    t.derive(s, slot)

        return sort

    def _build_pairs(self):
        a = self._annotations()
        V, S, I, I1, R1 = a["V"], a["S"], a["I"], a["I1"], a["R1"]
        real, dim = self.real, self.dim
        q = self.layout.q
        grid = self.grid
        support = self.kernel.support
        p_h = self.param_rows["smoothing_length"]
        PairOut = ti.types.ndarray(dtype=ti.i32, ndim=2)

        @ti.func
        def visit(s: ti.template(), i, out: ti.template(), offset, record: ti.template()):
            support2 = (support * s.params[p_h]) ** 2
            xi = s.Sv[q.position, i]
            c = grid.coords(s, xi)
            k = offset
            for row in ti.static(range(3 ** (dim - 1))):
                begin, end = grid.row_range(s, c, row)
                for j in range(begin, end):
                    if j != i and (xi - s.Sv[q.position, j]).norm_sqr() < support2:
                        if ti.static(record):
                            out[k, 0] = s.Si[q.id, i]
                            out[k, 1] = s.Si[q.id, j]
                        k += 1
            return k - offset

        @ti.kernel
        def count(Cv: V, Cs: S, Ci: I, Sv: V, Ss: S, Si: I, cell_of: I1, cell_count: I1,
                  cell_start: I1, cell_fill: I1, params: R1, mat: S, gshape: I1, counts: I1):
            s = ti.static(Ctx(Cv, Cs, Ci, Sv, Ss, Si, cell_of, cell_count, cell_start, cell_fill, params, mat, gshape))
            for i in range(Sv.shape[1]):
                counts[i] = visit(s, i, counts, 0, False)

        @ti.kernel
        def fill(Cv: V, Cs: S, Ci: I, Sv: V, Ss: S, Si: I, cell_of: I1, cell_count: I1,
                 cell_start: I1, cell_fill: I1, params: R1, mat: S, gshape: I1, offsets: I1, out: PairOut):
            s = ti.static(Ctx(Cv, Cs, Ci, Sv, Ss, Si, cell_of, cell_count, cell_start, cell_fill, params, mat, gshape))
            for i in range(Sv.shape[1]):
                visit(s, i, out, offsets[i], True)

        return count, fill

    def _build_pressure(self):
        a = self._annotations()
        V, S, I, R1 = a["V"], a["S"], a["I"], a["R1"]
        q, eos = self.layout.q, self.eos

        @ti.kernel
        def pressure(Cv: V, Cs: S, Ci: I, params: R1, mat: S):
            s = ti.static(Ctx(Cv, Cs, Ci, Cv, Cs, Ci, None, None, None, None, params, mat, None))
            for i in range(Cs.shape[1]):
                eos.derive(s, i)  # here s.S* are the current arrays C

        return pressure

    def _build_force(self):
        a = self._annotations()
        V, S, I, I1, R1 = a["V"], a["S"], a["I"], a["I1"], a["R1"]
        real, dim = self.real, self.dim
        q = self.layout.q
        nv, ns, ni = len(self.layout.vectors), len(self.layout.scalars), len(self.layout.integers)
        grid, integ, kern = self.grid, self.integrator, self.kernel
        pair_terms = [t for t in self.terms if t.has_pair]
        body_terms = [t for t in self.terms if t.has_body]
        sigma = kern.sigma(dim)
        support = kern.support
        Rates = self.Rates
        p_h = self.param_rows["smoothing_length"]

        @ti.kernel
        def force(Cv: V, Cs: S, Ci: I, Sv: V, Ss: S, Si: I, cell_of: I1, cell_count: I1,
                  cell_start: I1, cell_fill: I1, params: R1, mat: S, gshape: I1, dt: real):
            s = ti.static(Ctx(Cv, Cs, Ci, Sv, Ss, Si, cell_of, cell_count, cell_start, cell_fill, params, mat, gshape))
            n = Sv.shape[1]
            h = params[p_h]
            inv_h = 1.0 / h
            grad_norm = sigma * inv_h ** (dim + 2)
            support2 = (support * h) ** 2
            for i in range(n):
                for k in ti.static(range(nv)):
                    Cv[k, i] = Sv[k, i]
                for k in ti.static(range(ns)):
                    Cs[k, i] = Ss[k, i]
                for k in ti.static(range(ni)):
                    Ci[k, i] = Si[k, i]
                if Si[q.kind, i] == FLUID:
                    rates = Rates(acc=ti.Vector.zero(real, dim))  # zero-initialised
                    for t in ti.static(body_terms):
                        t.body(s, i, rates)
                    xi = Sv[q.position, i]
                    c = grid.coords(s, xi)
                    for row in ti.static(range(3 ** (dim - 1))):
                        begin, end = grid.row_range(s, c, row)
                        for j in range(begin, end):
                            rij = xi - Sv[q.position, j]
                            r2 = rij.norm_sqr()
                            if r2 < support2 and j != i:
                                r = ti.sqrt(r2)
                                grad = (grad_norm * kern.g(r * inv_h)) * rij
                                for t in ti.static(pair_terms):
                                    t.pair(s, i, j, rij, r, grad, rates)
                    integ.update(s, i, rates, dt)
                else:
                    integ.advance_wall(s, i, dt)

        return force
