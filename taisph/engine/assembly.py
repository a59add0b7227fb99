"""The per-step Taichi kernels, assembled at compile time from a scene's terms.

A step is a short sequence of kernel launches, issued as one Taichi graph call
(waking the CPU thread pool costs about 0.1-0.3 ms per parallel loop on the 2-core
VMs we measure on, so work is fused into as few passes as possible):

``sort``    cell index and count per particle, serial prefix sum over the cells, then
            each particle's whole state is scattered to its cell-sorted slot. The
            integrator's predictor, periodic wrapping, the equation of state and the
            terms' per-particle ``derive`` functions run here. With neighbour lists
            (``Scene.neighbour_skin`` > 0) the scatter happens only on rebuild steps;
            otherwise the state is copied in place (:mod:`taisph.grid`).
``passes``  only if a term needs them: neighbour sums that must be complete before
            the rates (e.g. wall pressure extrapolated from the fluid, summation
            density), one launch each, in the order the terms list them.
``force``   for every fluid particle: sum the enabled terms over its neighbours
            (``ti.static`` loop over the terms), then the integrator's update writes
            the new state. Wall particles are carried over (moving rigidly).

State lives in two buffers of Taichi ndarrays (see :mod:`taisph.layout`): ``C``,
the current state, and ``S``, the cell-sorted scratch copy the later passes read.
Kernels take ndarrays as arguments, so one compiled kernel serves simulations of
every size; a :class:`Solver` is cached per compile-time configuration (dimension,
precision, kernel, integrator, equation of state, terms and their options, periodic
axes).
"""

import collections

import numpy as np
import taichi as ti

from . import integrators, runtime, smoothing
from . import timestep as stepping
from .neighbours import Grid
from .layout import FLUID, VARIABLE_H, WALL, Layout

Ctx = collections.namedtuple(
    "Ctx", "Cv Cs Ci Sv Ss Si cell_of cell_count cell_start cell_fill params mat gshape status flags x_ref nlist ncount"
)

# Below this many particles the sort pass runs serially: waking the thread pool
# costs more than the work (measured, see docs/performance.md), and a serial
# scatter keeps each cell's particles in a reproducible order.
SERIAL_SORT_BELOW = 60_000

SELECT = {"fluid": FLUID, "wall": WALL, "all": -1}

# (term, role) of every term function traced into a kernel, appended at compile time:
# proof that a term the scene does not list contributes no code (tests/test_effects.py).
TRACED: list = []


def _traced(name: str, role: str):
    TRACED.append((name, role))


class Config(collections.namedtuple("Config", "dim kernel integrator eos terms periodic lists")):
    """Everything that changes the compiled code (not parameter values)."""


def config_of(scene) -> Config:
    return Config(
        dim=scene.dim,
        kernel=scene.kernel,
        integrator=integrators.INTEGRATORS[scene.integrator].name,
        eos=scene.eos.compile_key(),
        terms=tuple(t.compile_key() for t in scene.terms),
        periodic=tuple(bool(p) for p in scene.periodic),
        lists=scene.neighbour_skin > 0,
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


@ti.data_oriented
class _ForceSum:
    """Neighbour visitor of the force pass: kernel gradient once, then every pair term."""

    def __init__(self, solver, pair_terms):
        self.q = solver.layout.q
        self.kern = solver.kernel
        self.terms = pair_terms
        self.p_inv_h = solver.param_rows["inv_h"]
        self.p_grad_norm = solver.param_rows["grad_norm"]
        self.h_row = getattr(self.q, VARIABLE_H, -1)
        self.h_varies = self.h_row >= 0  # compile time: is h per particle?

    @ti.func
    def visit(self, s: ti.template(), i, j, rij, r2, rates: ti.template()):
        r = ti.sqrt(r2)
        grad = rij
        if ti.static(not self.h_varies):
            grad = (s.params[self.p_grad_norm] * self.kern.g(r * s.params[self.p_inv_h])) * rij
        else:
            # variable h: the mean of both particles' kernel gradients (Hernquist &
            # Katz 1989), antisymmetric in i, j, so pair forces stay equal and opposite
            hi, hj = s.Ss[self.h_row, i], s.Ss[self.h_row, j]
            grad = (0.5 * (self.kern.grad_factor_h(r, hi) + self.kern.grad_factor_h(r, hj))) * rij
        for t in ti.static(self.terms):
            ti.static(_traced(t.name, "pair"))
            t.pair(s, i, j, rij, r, grad, rates)


@ti.data_oriented
class _PassSum:
    """Neighbour visitor of a pre-force pass: kernel value and gradient, then the pass."""

    def __init__(self, solver, neighbour_pass):
        self.q = solver.layout.q
        self.kern = solver.kernel
        self.p = neighbour_pass
        self.p_inv_h = solver.param_rows["inv_h"]
        self.p_w_norm = solver.param_rows["w_norm"]
        self.p_grad_norm = solver.param_rows["grad_norm"]
        self.h_row = getattr(self.q, VARIABLE_H, -1)
        self.h_varies = self.h_row >= 0

    @ti.func
    def visit(self, s: ti.template(), i, j, rij, r2, acc: ti.template()):
        r = ti.sqrt(r2)
        w = r
        grad = rij
        if ti.static(not self.h_varies):
            q = r * s.params[self.p_inv_h]
            w = s.params[self.p_w_norm] * self.kern.f(q)
            grad = (s.params[self.p_grad_norm] * self.kern.g(q)) * rij
        else:  # variable h: particle i's own smoothing length (a gather sum)
            hi = s.Ss[self.h_row, i]
            w = self.kern.w_h(r, hi)
            grad = self.kern.grad_factor_h(r, hi) * rij
        ti.static(_traced(self.p.owner, "pass"))
        self.p.pair(s, i, j, rij, r, w, grad, acc)


class Solver:
    def __init__(self, scene, rt: runtime.Runtime):
        self.dim = dim = scene.dim
        self.real = real = rt.real
        self.kernel = smoothing.make(scene.kernel, dim)
        self.sigma = self.kernel.sigma(dim)

        # --- what is stored --------------------------------------------------
        integrated = []
        for t in scene.terms:
            integrated.extend(t.integrates.items())
        self.integrated = tuple(integrated)
        self.has_shift = any(t.has_shift for t in scene.terms)
        integ = integrators.make(scene.integrator, self.integrated, self.has_shift)
        extra_v, extra_s = integ.quantities()
        vectors = list(extra_v)
        scalars = list(extra_s) + list(scene.eos.scalars)
        integers = []
        for t in scene.terms:
            vectors += t.vectors
            scalars += t.scalars
            integers += t.integers
        self.layout = layout = Layout(vectors, scalars, integers)
        self.outputs = tuple(dict.fromkeys([*scene.eos.outputs, *(o for t in scene.terms for o in t.outputs)]))

        # --- runtime parameter table ----------------------------------------
        rows = {}
        size = 0
        for name, width in (("smoothing_length", 1), ("inv_h", 1), ("w_norm", 1), ("grad_norm", 1),
                            ("support2", 1), ("grid_lo", dim), ("grid_inv_cell", dim), ("period", dim)):
            rows[name] = size
            size += width
        for name, width in stepping.PARAMS:
            rows[name] = size
            size += dim if width == "dim" else width
        for t in scene.terms:
            for name, default in t.params.items():
                if name in rows:
                    raise ValueError(f"parameter {name!r} is declared twice (by {type(t).__name__})")
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
        self.terms = [t.bound(layout, rows, mcols, self.eos, rate_rows, self.kernel) for t in scene.terms]
        self.passes = []
        for t in self.terms:
            for p in t.passes():
                p.owner = t.name
                self.passes.append(p)
        self.integrator = integ.bind(layout)
        self.lists = scene.neighbour_skin > 0
        # walls within a short range only (e.g. Lennard-Jones walls): lists keep fewer
        self.wall_ranges = [t.wall_reach() for t in scene.terms]
        walls_short = self.lists and "support" not in self.wall_ranges
        self.grid = Grid(dim, real, rows["grid_lo"], rows["grid_inv_cell"], rows["period"], scene.periodic,
                         self.lists, rows["list_skin"], rows["list_reach2"],
                         (layout.q.kind, rows["list_wall_reach2"]) if walls_short else None)
        self.stepping = stepping.Stepping(dim, real, layout, rows, self.eos, scene.periodic)
        # rates.acc: dv/dt; rates.d[k]: rate of the k-th integrated scalar (a Taichi
        # vector needs length >= 1, hence the max); rates.shift: a correction to the
        # velocity that moves the particles (XSPH), only if a term provides one.
        fields = dict(acc=ti.types.vector(dim, real), d=ti.types.vector(max(1, len(self.integrated)), real))
        if self.has_shift:
            fields["shift"] = ti.types.vector(dim, real)
        self.Rates = ti.types.struct(**fields)
        self.vec = ti.types.vector(dim, real)
        self._kernels = {}

    # ------------------------------------------------------------------------
    def param_table(self, scene, grid_lo, grid_cell, period, controls) -> np.ndarray:
        """Runtime parameter values of `scene`, laid out as the kernels read them;
        `controls` holds the time-step and guard settings (:mod:`taisph.stepping`)."""
        r = self.param_rows
        dim = self.dim
        h = scene.smoothing_length
        table = np.zeros(self.n_params)
        table[r["smoothing_length"]] = h
        table[r["inv_h"]] = 1.0 / h
        table[r["w_norm"]] = self.sigma / h**dim
        table[r["grad_norm"]] = self.sigma / h ** (dim + 2)
        table[r["support2"]] = (self.kernel.support * h) ** 2
        table[r["grid_lo"] : r["grid_lo"] + dim] = grid_lo
        table[r["grid_inv_cell"] : r["grid_inv_cell"] + dim] = 1.0 / np.asarray(grid_cell)
        table[r["period"] : r["period"] + dim] = period
        for name, value in controls.items():
            value = np.atleast_1d(value)
            table[r[name] : r[name] + len(value)] = value
        for t in scene.terms:
            for name, value in t.param_values(dim).items():
                k = r[name]
                table[k : k + len(value)] = value
        return table

    def material_table(self, scene) -> np.ndarray:
        return np.array([self.eos.material_row(m) for m in scene.materials], dtype=float)

    def kernels(self, serial_sort: bool):
        """The kernels of one step, in order: sort, the passes, force."""
        key = ("step", serial_sort)
        if key not in self._kernels:
            self._kernels[key] = (
                self._build_sort(serial_sort),
                *[self._build_pass(p) for p in self.passes],
                self._build_force(),
            )
        return self._kernels[key]

    ARG_NAMES = Ctx._fields

    def step_graph(self, serial_sort: bool, args):
        """A Taichi graph running one step in a single call from Python.

        A plain kernel call costs about 13 us of Python argument handling per ndarray
        argument (13 per kernel here); a graph binds them in C++. Returns None if the
        backend cannot build graphs (then the kernels are called directly)."""
        key = ("graph", serial_sort)
        if key not in self._kernels:
            G = ti.graph
            try:
                symbols = []
                for name, array in zip(self.ARG_NAMES, args):
                    dtype = self.vec if name in ("Cv", "Sv", "x_ref") else array.dtype
                    symbols.append(G.Arg(G.ArgKind.NDARRAY, name, dtype=dtype, ndim=len(array.shape)))
                t_target = G.Arg(G.ArgKind.SCALAR, "t_target", ti.f64)
                builder = G.GraphBuilder()
                for kernel in self.kernels(serial_sort):
                    builder.dispatch(kernel, *symbols, t_target)
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
        sort = self.kernels(serial_sort=sim._serial_sort)[0]
        args = sim._kernel_args()
        # The sort starts a step: with a target time of now its dt is 0, so the state
        # (C) is untouched, but it resets the maxima the next step's dt is chosen from
        # and may rebuild the neighbour lists (in S's order, not C's). Keep the clock,
        # the maxima, the lists and the cells they refer to as they were.
        kept = [(a, a.to_numpy()) for a in (sim._status, sim._x_ref, sim._nlist, sim._ncount, *sim._cells)]
        sort(*args, sim.time)  # sorts S by cell
        n = sim.n
        counts = ti.ndarray(ti.i32, n)
        count(*args, counts)
        c = counts.to_numpy()
        offsets = np.concatenate([[0], np.cumsum(c)]).astype(np.int32)
        off_nd = ti.ndarray(ti.i32, n + 1)
        off_nd.from_numpy(offsets)
        out = ti.ndarray(ti.i32, (max(1, int(offsets[-1])), 2))
        fill(*args, off_nd, out)
        for array, values in kept:
            array.from_numpy(values)
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
        """Kernel argument types; F1 is the f64 status array (time must not be f32)."""
        real = self.real
        return dict(
            V=ti.types.ndarray(dtype=self.vec, ndim=2),
            S=ti.types.ndarray(dtype=real, ndim=2),
            I=ti.types.ndarray(dtype=ti.i32, ndim=2),
            I1=ti.types.ndarray(dtype=ti.i32, ndim=1),
            R1=ti.types.ndarray(dtype=real, ndim=1),
            F1=ti.types.ndarray(dtype=ti.f64, ndim=1),
            V1=ti.types.ndarray(dtype=self.vec, ndim=1),
            I2=ti.types.ndarray(dtype=ti.i32, ndim=2),
        )

    def _build_sort(self, serial: bool):
        a = self._annotations()
        V, S, I, I1, R1, V1, I2 = a["V"], a["S"], a["I"], a["I1"], a["R1"], a["V1"], a["I2"]
        real = self.real
        q = self.layout.q
        nv, ns, ni = len(self.layout.vectors), len(self.layout.scalars), len(self.layout.integers)
        grid, integ, eos, steps = self.grid, self.integrator, self.eos, self.stepping
        derive_terms = [t for t in self.terms if t.has_derive]
        F1 = a["F1"]

        @ti.kernel
        def sort(Cv: V, Cs: S, Ci: I, Sv: V, Ss: S, Si: I, cell_of: I1, cell_count: I1,
                 cell_start: I1, cell_fill: I1, params: R1, mat: S, gshape: I1, status: F1, flags: I1, x_ref: V1, nlist: I2, ncount: I1, t_target: ti.f64):
            s = ti.static(Ctx(Cv, Cs, Ci, Sv, Ss, Si, cell_of, cell_count, cell_start, cell_fill, params, mat, gshape, status, flags, x_ref, nlist, ncount))
            n = Cv.shape[1]
            ti.loop_config(serialize=True)
            for _ in range(1):
                steps.begin_step(s, t_target)
            dt = ti.cast(status[stepping.DT], real)
            ti.loop_config(serialize=serial)
            for i in range(n):
                # x: where this step's rates are evaluated
                x = grid.wrap(s, integ.predicted_position(s, i, dt))
                grid.note_displacement(s, i, x)
                c = grid.linear(s, grid.coords(s, x))
                cell_of[i] = c
                ti.atomic_add(cell_count[c], 1)
            ti.loop_config(serialize=True)
            for _ in range(1):
                if grid.decide_rebuild(s):
                    running = 0
                    for c in range(gshape[3]):
                        cell_start[c] = running
                        cell_fill[c] = running
                        running += cell_count[c]
                        cell_count[c] = 0
                    cell_start[gshape[3]] = running
                else:  # keep the cells of the last rebuild (the lists' fallback)
                    for c in range(gshape[3]):
                        cell_count[c] = 0
            rebuild = grid.rebuilding(s)
            ti.loop_config(serialize=serial)
            for i in range(n):
                slot = i  # between rebuilds the order stays that of the last rebuild
                if rebuild:
                    slot = ti.atomic_add(cell_fill[cell_of[i]], 1)
                for k in ti.static(range(nv)):
                    Sv[k, slot] = Cv[k, i]
                for k in ti.static(range(ns)):
                    Ss[k, slot] = Cs[k, i]
                for k in ti.static(range(ni)):
                    Si[k, slot] = Ci[k, i]
                integ.predict(s, i, slot, dt)
                if ti.static(grid.any_periodic):
                    Sv[q.position, slot] = grid.wrap(s, Sv[q.position, slot])
                if ti.static(grid.lists):
                    if rebuild:
                        x_ref[slot] = Sv[q.position, slot]
                eos.derive(s, slot)
                for t in ti.static(derive_terms):
                    ti.static(_traced(t.name, "derive"))
                    t.derive(s, slot)

        return sort

    def _build_pass(self, neighbour_pass):
        a = self._annotations()
        V, S, I, I1, R1, V1, I2 = a["V"], a["S"], a["I"], a["I1"], a["R1"], a["V1"], a["I2"]
        real = self.real
        q = self.layout.q
        grid, eos = self.grid, self.eos
        derive_terms = [t for t in self.terms if t.has_derive]
        visitor = _PassSum(self, neighbour_pass)
        F1 = a["F1"]
        select = SELECT[neighbour_pass.select]
        p_support2 = self.param_rows["support2"]

        @ti.kernel
        def neighbour_pass_kernel(Cv: V, Cs: S, Ci: I, Sv: V, Ss: S, Si: I, cell_of: I1, cell_count: I1,
                                  cell_start: I1, cell_fill: I1, params: R1, mat: S, gshape: I1, status: F1, flags: I1, x_ref: V1, nlist: I2, ncount: I1, t_target: ti.f64):
            s = ti.static(Ctx(Cv, Cs, Ci, Sv, Ss, Si, cell_of, cell_count, cell_start, cell_fill, params, mat, gshape, status, flags, x_ref, nlist, ncount))
            support2 = params[p_support2]
            for i in range(Sv.shape[1]):
                if ti.static(select < 0) or Si[q.kind, i] == select:
                    acc = neighbour_pass.init(s, i)
                    grid.for_each_neighbour(s, i, Sv[q.position, i], support2, visitor, acc)
                    neighbour_pass.finish(s, i, acc)
                    if ti.static(neighbour_pass.rederive):
                        eos.derive(s, i)
                        for t in ti.static(derive_terms):
                            t.derive(s, i)

        return neighbour_pass_kernel

    def _build_force(self):
        a = self._annotations()
        V, S, I, I1, R1, V1, I2 = a["V"], a["S"], a["I"], a["I1"], a["R1"], a["V1"], a["I2"]
        real, dim = self.real, self.dim
        q = self.layout.q
        nv, ns, ni = len(self.layout.vectors), len(self.layout.scalars), len(self.layout.integers)
        grid, integ = self.grid, self.integrator
        visitor = _ForceSum(self, [t for t in self.terms if t.has_pair])
        steps = self.stepping
        F1 = a["F1"]
        body_terms = [t for t in self.terms if t.has_body]
        Rates = self.Rates
        p_support2 = self.param_rows["support2"]

        @ti.kernel
        def force(Cv: V, Cs: S, Ci: I, Sv: V, Ss: S, Si: I, cell_of: I1, cell_count: I1,
                  cell_start: I1, cell_fill: I1, params: R1, mat: S, gshape: I1, status: F1, flags: I1, x_ref: V1, nlist: I2, ncount: I1, t_target: ti.f64):
            s = ti.static(Ctx(Cv, Cs, Ci, Sv, Ss, Si, cell_of, cell_count, cell_start, cell_fill, params, mat, gshape, status, flags, x_ref, nlist, ncount))
            support2 = params[p_support2]
            dt = ti.cast(status[stepping.DT], real)
            for i in range(Sv.shape[1]):
                for k in ti.static(range(nv)):
                    Cv[k, i] = Sv[k, i]
                for k in ti.static(range(ns)):
                    Cs[k, i] = Ss[k, i]
                for k in ti.static(range(ni)):
                    Ci[k, i] = Si[k, i]
                if Si[q.kind, i] == FLUID:
                    rates = Rates(acc=ti.Vector.zero(real, dim))  # other members zero-initialised
                    for t in ti.static(body_terms):
                        ti.static(_traced(t.name, "body"))
                        t.body(s, i, rates)
                    grid.for_each_neighbour(s, i, Sv[q.position, i], support2, visitor, rates)
                    integ.update(s, i, rates, dt)
                    steps.track(s, i, rates)
                elif Si[q.kind, i] == WALL:
                    integ.advance_wall(s, i, dt)
                # removed particles: carried over unchanged

        return force

    def _build_pairs(self):
        a = self._annotations()
        V, S, I, I1, R1, V1, I2 = a["V"], a["S"], a["I"], a["I1"], a["R1"], a["V1"], a["I2"]
        q = self.layout.q
        grid = self.grid
        p_support2 = self.param_rows["support2"]
        F1 = a["F1"]
        # the context of `fill` also carries where the pairs go
        PairCtx = collections.namedtuple("PairCtx", Ctx._fields + ("pair_out",))

        @ti.data_oriented
        class Count:
            def __init__(self, q):
                self.q = q

            @ti.func
            def visit(self, s: ti.template(), i, j, rij, r2, acc: ti.template()):
                acc += 1

        @ti.data_oriented
        class Fill(Count):
            @ti.func
            def visit(self, s: ti.template(), i, j, rij, r2, acc: ti.template()):
                s.pair_out[acc, 0] = s.Si[self.q.id, i]
                s.pair_out[acc, 1] = s.Si[self.q.id, j]
                acc += 1

        counter, filler = Count(q), Fill(q)

        @ti.kernel
        def count(Cv: V, Cs: S, Ci: I, Sv: V, Ss: S, Si: I, cell_of: I1, cell_count: I1,
                  cell_start: I1, cell_fill: I1, params: R1, mat: S, gshape: I1, status: F1, flags: I1, x_ref: V1, nlist: I2, ncount: I1, counts: I1):
            s = ti.static(Ctx(Cv, Cs, Ci, Sv, Ss, Si, cell_of, cell_count, cell_start, cell_fill, params, mat, gshape, status, flags, x_ref, nlist, ncount))
            for i in range(Sv.shape[1]):
                k = 0
                grid.for_each_neighbour(s, i, Sv[q.position, i], params[p_support2], counter, k)
                counts[i] = k

        @ti.kernel
        def fill(Cv: V, Cs: S, Ci: I, Sv: V, Ss: S, Si: I, cell_of: I1, cell_count: I1,
                 cell_start: I1, cell_fill: I1, params: R1, mat: S, gshape: I1, status: F1, flags: I1, x_ref: V1, nlist: I2, ncount: I1,
                 offsets: I1, out: I2):
            s = ti.static(PairCtx(Cv, Cs, Ci, Sv, Ss, Si, cell_of, cell_count, cell_start, cell_fill, params, mat, gshape, status, flags, x_ref, nlist, ncount, out))
            for i in range(Sv.shape[1]):
                k = offsets[i]
                grid.for_each_neighbour(s, i, Sv[q.position, i], params[p_support2], filler, k)

        return count, fill

    def _build_pressure(self):
        a = self._annotations()
        V, S, I, R1 = a["V"], a["S"], a["I"], a["R1"]
        eos = self.eos
        derive_terms = [t for t in self.terms if t.has_derive]

        @ti.kernel
        def pressure(Cv: V, Cs: S, Ci: I, params: R1, mat: S):
            # here the "sorted" arrays of the context are the current ones, C
            s = ti.static(Ctx(Cv, Cs, Ci, Cv, Cs, Ci, None, None, None, None, params, mat, None, None, None, None, None, None))
            for i in range(Cs.shape[1]):
                eos.derive(s, i)
                for t in ti.static(derive_terms):
                    t.derive(s, i)

        return pressure
