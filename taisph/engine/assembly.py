"""Kernels assembled at compile time from a scene's terms: one :class:`Solver` per configuration.

A solver decides what is stored per particle (:mod:`.layout`), where each runtime
parameter lives in the parameter array, binds the equation of state, the terms, the
integrator, the neighbour grid, the time step and the guards to those rows, and
compiles the step's kernels (:mod:`.kernels` says what each does) with the one
kernel signature, :class:`Args`.

A solver is cached per compile-time configuration (dimension, precision, kernel,
integrator, equation of state, terms and their options, periodic axes, neighbour
lists); its kernels are compiled for the Taichi fields of a :class:`.fields.FieldSet`,
pooled per configuration and size class, so changing a parameter value or the
particle count within a size class never recompiles.
"""

import collections

import numpy as np
import taichi as ti

from . import guards, integrators, kernels, neighbours, runtime, smoothing, timestep
from .dfsph import solver as dfsph
from .dfsph import pairs
from .layout import Layout
from ..terms import open_boundary, rigid_bodies
from ..scene.solvers import dfsph_kept_terms


class Buffers(collections.namedtuple("Buffers", "v s i")):
    """One copy of the particle state: the fields of its vectors, scalars and integers,
    each ``[row, particle]`` (:mod:`.layout`)."""

    __slots__ = ()


class Args(collections.namedtuple("Args", "Cv Cs Ci Sv Ss Si cell_of cell_count cell_start cell_fill "
                                          "params mat sizes status flags x_ref nlist ncount aux_int aux_real "
                                          "tables bodies")):
    """The fields every kernel works on (:mod:`.fields`); a kernel takes ``t_target``,
    the time the step must not pass (f64). Inside kernels ``s.<name>``:

    Cv, Cs, Ci     current state: vectors, scalars, integers ``[row, particle]`` (:mod:`.layout`)
    Sv, Ss, Si     the same, cell-sorted (scratch of the step: the rates are computed from S)
    cell_of        cell of each particle; cell_count, cell_start (n_cells + 1), cell_fill: the sort
    params         runtime parameters (:meth:`Solver.param_table`); mat: material table
    sizes          grid shape and counts (indices in :mod:`.status`: GRID_SHAPE, N_CELLS, ...)
    status, flags  device clock, dt history and guard flags (:mod:`.status`)
    x_ref, nlist, ncount   neighbour lists (a dummy row without lists; :mod:`.neighbours`)
    aux_int, aux_real   outputs of auxiliary kernels (neighbour pairs, probes); dummies in a step
    tables         lookup tables of terms (open boundaries' velocity tables; one entry without)
    bodies         rigid bodies' state and motion tables, f64 (:mod:`taisph.terms.rigid_bodies`; one entry without)
    """

    __slots__ = ()
    AUX = ("aux_int", "aux_real")

    @property
    def C(self) -> Buffers:
        """The current state (Cv, Cs, Ci)."""
        return Buffers(self.Cv, self.Cs, self.Ci)

    @property
    def S(self) -> Buffers:
        """The cell-sorted state (Sv, Ss, Si)."""
        return Buffers(self.Sv, self.Ss, self.Si)

    def with_C(self, buffers: Buffers) -> "Args":
        """These fields with `buffers` in place of the current state."""
        return self._replace(Cv=buffers.v, Cs=buffers.s, Ci=buffers.i)

    def with_S(self, buffers: Buffers) -> "Args":
        """These fields with `buffers` in place of the cell-sorted state."""
        return self._replace(Sv=buffers.v, Ss=buffers.s, Si=buffers.i)

    def state_fields(self) -> tuple:
        """The fields of the state, all but the auxiliary kernels' outputs."""
        return tuple(getattr(self, name) for name in self._fields if name not in self.AUX)


class Config(collections.namedtuple("Config", "dim kernel integrator eos terms periodic lists solver")):
    """Everything that changes the compiled code (not parameter values)."""


def config_of(scene) -> Config:
    solver = getattr(scene, "solver", "wcsph")
    terms = dfsph_kept_terms(scene) if solver == "dfsph" else scene.terms
    return Config(
        dim=scene.dim,
        kernel=scene.kernel,
        integrator="dfsph" if solver == "dfsph" else integrators.INTEGRATORS[scene.integrator].name,
        eos=scene.eos.compile_key(),
        terms=tuple(t.compile_key() for t in terms),
        periodic=tuple(bool(p) for p in scene.periodic),
        lists=scene.neighbour_skin > 0,
        solver=solver,
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


KERNEL_PARAMS = (("smoothing_length", 1), ("inv_h", 1), ("w_norm", 1), ("grad_norm", 1), ("support2", 1))


class Solver:
    def __init__(self, scene, rt: runtime.Runtime):
        self.dim = dim = scene.dim
        self.real = real = rt.real
        self.kernel = smoothing.make(scene.kernel, dim)
        self.sigma = self.kernel.sigma(dim)
        # DFSPH (engine/dfsph/solver.py): the scene's non-pressure terms, no equation of state, its own step
        self.dfsph = getattr(scene, "solver", "wcsph") == "dfsph"
        terms = self.active_terms(scene)
        eos = dfsph.Incompressible() if self.dfsph else scene.eos

        # --- what is stored --------------------------------------------------
        integrated = []
        for t in terms:
            integrated.extend(t.integrates.items())
        self.integrated = tuple(integrated)
        self.has_shift = any(t.has_shift for t in terms)
        integ = integrators.make("euler" if self.dfsph else scene.integrator, self.integrated, self.has_shift)
        extra_v, extra_s = integ.quantities()
        vectors = list(extra_v)
        scalars = list(extra_s) + list(eos.scalars)
        integers = []
        derived = list(eos.derived)
        for t in terms:
            vectors += t.vectors
            scalars += t.scalars
            integers += t.integers
            derived += t.derived
        if self.dfsph:
            v, sc, der = dfsph.rows(self.has_shift, any(t.with_walls for t in terms))
            vectors, scalars, derived = vectors + v, scalars + sc, derived + der
        self.layout = layout = Layout(vectors, scalars, integers, derived, pressure_derived=not self.dfsph)
        self.outputs = tuple(dict.fromkeys([*eos.outputs, *(o for t in terms for o in t.outputs)]))

        # --- runtime parameter table: engine parameters, then the terms' -----
        rows = {}
        size = 0
        for name, width in (KERNEL_PARAMS + neighbours.PARAMS + timestep.PARAMS + guards.PARAMS
                            + (dfsph.PARAMS if self.dfsph else ())):
            rows[name] = size
            size += dim if width == "dim" else width
        for t in terms:
            for name, default in t.params.items():
                if name in rows:
                    raise ValueError(f"parameter {name!r} is declared twice (by {type(t).__name__})")
                rows[name] = size
                size += dim if default == "vector" else 1
        self.param_rows = rows
        self.n_params = size
        self.material_columns = eos.columns
        mcols = collections.namedtuple("MaterialColumns", eos.columns)(*range(len(eos.columns)))

        # --- compile-time assembly -------------------------------------------
        self.eos = eos.bind(layout, mcols)
        rate_rows = collections.namedtuple("RateRows", [r for _, r in self.integrated] or ["none"])(
            *range(max(1, len(self.integrated)))
        )
        self.terms = [t.bound(layout, rows, mcols, self.eos, rate_rows, self.kernel) for t in terms]
        self.passes = []
        for t in self.terms:
            for p in t.passes():
                p.owner = t.name
                self.passes.append(p)
        self.integrator = integ.bind(layout)
        self.lists = scene.neighbour_skin > 0
        # walls within a short range only (e.g. Lennard-Jones walls): lists keep fewer
        walls_short = self.lists and "support" not in [t.wall_reach() for t in terms]
        self.grid = neighbours.Grid(dim, real, rows, scene.periodic, self.lists,
                                    layout.q.kind if walls_short else None)
        viscosity_rows = [rows[t.viscosity_param] for t in terms if t.viscosity_param]
        if self.dfsph:  # artificial viscosity's equivalent (engine/dfsph/solver.py)
            viscosity_rows.append(rows["dfsph_nu_art"])
        self.timestep = timestep.TimeStep(rows, self.eos, viscosity_rows)
        self.guards = guards.Guards(dim, layout, rows, self.eos, scene.periodic,
                                    compression_only=self.dfsph or not getattr(scene.eos, "tension", True))
        # rates.acc: dv/dt; rates.d[k]: rate of the k-th integrated scalar (a Taichi
        # vector needs length >= 1, hence the max); rates.shift: a correction to the
        # velocity that moves the particles (XSPH), only if a term provides one.
        fields = dict(acc=ti.types.vector(dim, real), d=ti.types.vector(max(1, len(self.integrated)), real))
        if self.has_shift:
            fields["shift"] = ti.types.vector(dim, real)
        kinds = dict(scalar=real, vector=ti.types.vector(dim, real), matrix=ti.types.matrix(dim, dim, real))
        for t in terms:  # sums a term gathers in pair() and reads in finish() (terms/base.py)
            fields.update({name: kinds[kind] for name, kind in t.accumulators.items()})
        self.Rates = ti.types.struct(**fields)
        self.vec = ti.types.vector(dim, real)
        self.field_sets = []  # the FieldSets allocated for this configuration (taisph.engine.fields)
        # open boundaries (taisph.terms.open_boundary): their term, a bound copy, or None
        self.open = next((t for t in self.terms if t.name == "open_boundaries"), None)
        self.table_capacity = open_boundary.TABLE_CAPACITY if self.open is not None else 1
        # moving and floating bodies (taisph.terms.rigid_bodies): their term, a bound copy, or None
        self.bodies = next((t for t in self.terms if t.name == "rigid_bodies"), None)
        self.body_capacity = rigid_bodies.CAPACITY if self.bodies is not None else 1

    def active_terms(self, scene) -> list:
        """The scene's terms compiled into this solver's kernels (DFSPH: its non-pressure ones)."""
        return dfsph_kept_terms(scene) if self.dfsph else list(scene.terms)

    def extra_fields(self, field, capacity, list_capacity):
        """Fields a solver needs beyond :class:`Args` (DFSPH: its pair list and error sums), or None."""
        if not self.dfsph:
            return None
        return dfsph.Extra(pairs=pairs.allocate(field, capacity, list_capacity, self.real),
                           part=field(ti.f64, (dfsph.CHUNKS, 2)), result=field(ti.f64, (4,)))

    # ------------------------------------------------------------------------
    def param_table(self, scene, grid_lo, grid_cell, controls, dt=None) -> np.ndarray:
        """Runtime parameter values of `scene`, laid out as the kernels read them;
        `controls` (:class:`taisph.engine.timestep.Controls`) holds the time-step and
        guard settings, `dt` a one-off fixed step."""
        dim = self.dim
        h = scene.smoothing_length
        values = dict(smoothing_length=h, inv_h=1.0 / h, w_norm=self.sigma / h**dim,
                      grad_norm=self.sigma / h ** (dim + 2), support2=(self.kernel.support * h) ** 2)
        values.update(neighbours.parameter_values(scene, grid_lo, grid_cell))
        values.update(timestep.parameter_values(controls, dt))
        values.update(guards.parameter_values(scene, controls))
        if self.dfsph:
            values.update(dfsph.parameter_values(scene, controls))
        for t in self.active_terms(scene):
            values.update(t.param_values(dim))
        table = np.zeros(self.n_params)
        for name, value in values.items():
            value = np.atleast_1d(value)
            table[self.param_rows[name] : self.param_rows[name] + len(value)] = value
        return table

    def material_table(self, scene) -> np.ndarray:
        return np.array([self.eos.material_row(m) for m in scene.materials], dtype=float)

    def make_kernel(self, body):
        """A builder of the kernel running ``body(s, t_target)`` (a ``ti.func`` whose
        top-level loops run in parallel) on a set of fields: ``build(args)`` returns a
        Taichi kernel taking only ``t_target``, the fields `args` (:class:`Args`) bound
        by closure, so a launch passes no arrays (see :mod:`.fields`)."""

        def build(args):
            s = args

            @ti.kernel
            def kernel(t_target: ti.f64):
                body(s, t_target)

            return kernel

        return build

    def make_aux_kernel(self, body):
        """Like :meth:`make_kernel`, for auxiliary kernels: the kernel also takes two
        ndarrays, ``aux_int`` (i32) and ``aux_real``, any shape, which the body writes
        (``s.aux_int``, ``s.aux_real``); see :meth:`taisph.engine.state.State.run_auxiliary`."""
        real = self.real

        def build(args):
            s = args

            @ti.kernel
            def kernel(aux_int: ti.types.ndarray(dtype=ti.i32, ndim=2), aux_real: ti.types.ndarray(dtype=real, ndim=2),
                       t_target: ti.f64):
                body(ti.static(s._replace(aux_int=aux_int, aux_real=aux_real)), t_target)

            return kernel

        return build

    def step_kernels(self, fields, serial_sort: bool) -> tuple:
        """The kernels of one step on `fields` (a FieldSet), in order: sort, the terms'
        ``after_sort`` launches (open boundaries' buffer values), the passes, force, the
        terms' ``after_force`` launches (bodies' motion, open boundaries' bookkeeping)
        (DFSPH: one callable, :class:`taisph.engine.dfsph.solver.Stepper`, which iterates its solves)."""
        if self.dfsph:
            return fields.kernel(("dfsph", serial_sort), lambda args: (dfsph.Stepper(self, fields, serial_sort),))

        def build(args):  # only on the first call for these fields: the step's hot path is the cache lookup
            # terms with launches of their own (open boundaries, bodies); bodies move before the
            # open boundaries' bookkeeping compacts the arrays
            before = [t.after_sort(self) for t in self.terms if hasattr(t, "after_sort")]
            after = [t.after_force(self) for t in sorted((t for t in self.terms if hasattr(t, "after_force")),
                                                         key=lambda t: t.name != "rigid_bodies")]
            bodies = [kernels.sort_body(self, serial_sort), *before,
                      *[kernels.pass_body(self, p) for p in self.passes], kernels.force_body(self), *after]
            return tuple(self.make_kernel(b)(args) for b in bodies)

        return fields.kernel(("step", serial_sort), build)

    def pressure_kernel(self, fields, good: bool = False):
        """Fills the pressure row (and derived rows) of the current state, or of the
        copy of the last good state."""
        def build(args):
            if good:
                args = args.with_C(fields.good)
            return self.make_kernel(kernels.pressure_body(self))(args)

        return fields.kernel(("pressure", good), build)

    def copy_kernel(self, fields):
        """Copies the current state to the last-good copy (particles in use only)."""
        return fields.kernel("keep_good", lambda args: self.make_kernel(
            kernels.copy_body(self, args.C, fields.good))(args))

    def pair_kernels(self, fields):
        """(count, list) kernels of the neighbour pairs (:func:`kernels.pairs_body`)."""
        return fields.kernel("pairs", lambda args: (self.make_aux_kernel(kernels.pairs_body(self, False))(args),
                                                    self.make_aux_kernel(kernels.pairs_body(self, True))(args)))

    def compiled_count(self) -> int:
        """How many Taichi kernel instances were compiled for this solver's field sets
        (for tests)."""
        total = 0
        for fields in self.field_sets:
            for ks in fields.kernels.values():
                for k in ks if isinstance(ks, tuple) else (ks,):
                    if hasattr(k, "_primal"):
                        total += len(k._primal.compiled_kernels)
        return total

