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

from . import guards, integrators, kernels, neighbours, runtime, smoothing, solvers, timestep
from . import status as st
from .layout import Layout


class Buffers(collections.namedtuple("Buffers", "v s i")):
    """One copy of the particle state: the fields of its vectors, scalars and integers,
    each ``[row, particle]`` (:mod:`.layout`)."""

    __slots__ = ()


class Args(collections.namedtuple("Args", "Cv Cs Ci Sv Ss Si cell_of cell_count cell_start cell_fill "
                                          "params mat sizes status flags x_ref nlist ncount aux_int aux_real "
                                          "store")):
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
    store          the terms' own device arrays, by name (``Term.device_arrays``): ``s.store.<name>``
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
        """The fields of the state, all but the auxiliary kernels' outputs and the terms' own arrays."""
        return tuple(getattr(self, name) for name in self._fields if name not in self.AUX + ("store",))


class Config(collections.namedtuple("Config", "dim kernel integrator eos terms periodic lists solver")):
    """Everything that changes the compiled code (not parameter values)."""


def config_of(scene) -> Config:
    method = solvers.of(scene)
    return Config(
        dim=scene.dim,
        kernel=scene.kernel,
        integrator=integrators.INTEGRATORS[method.integrator(scene)].name,
        eos=scene.eos.compile_key(),
        terms=tuple(t.compile_key() for t in method.terms(scene)),
        periodic=tuple(bool(p) for p in scene.periodic),
        lists=scene.neighbour_skin > 0,
        solver=method.name,
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
# the scene's number of materials: the material table has at least that many rows (field sets are
# reused by scenes with fewer), so a loop over the materials stops there (Term.material_count)
SCENE_PARAMS = (("materials", 1),)


class Solver:
    """One compile-time configuration: what is stored, the parameter table, and the bound
    equation of state, terms, integrator, grid, time step and guards, for the method of
    the scene's solver (:mod:`.solvers`; ``self.method``)."""

    def __init__(self, scene, rt: runtime.Runtime):
        self.dim = scene.dim
        self.real = rt.real
        self.kernel = smoothing.make(scene.kernel, self.dim)
        self.sigma = self.kernel.sigma(self.dim)
        self.method = method = solvers.of(scene)
        terms = method.terms(scene)
        eos = method.eos(scene)
        integ = self._lay_out(scene, terms, eos)
        mcols = self._parameter_table(terms, eos)
        self._bind(scene, terms, eos, integ, mcols)
        self.field_sets = []  # the FieldSets allocated for this configuration (taisph.engine.fields)
        self._plug_in_subsystems()

    def _lay_out(self, scene, terms, eos):
        """What is stored per particle (the layout): the integrator's rows, the equation of
        state's, the terms', the method's. Returns the integrator (unbound)."""
        integrated = []
        for t in terms:
            integrated.extend(t.integrates.items())
        self.integrated = tuple(integrated)
        self.has_shift = any(t.has_shift for t in terms)
        integ = integrators.make(self.method.integrator(scene), self.integrated, self.has_shift)
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
        v, sc, der = self.method.rows(terms, self.has_shift)
        vectors, scalars, derived = vectors + list(v), scalars + list(sc), derived + list(der)
        self.layout = Layout(vectors, scalars, integers, derived, pressure_derived=self.method.pressure_derived)
        self.outputs = tuple(dict.fromkeys([*eos.outputs, *(o for t in terms for o in t.outputs)]))
        return integ

    def _parameter_table(self, terms, eos):
        """Where each runtime parameter lives: the engine's, the method's, then the terms'.
        Returns the material table's columns (a namedtuple of their indices)."""
        rows = {}
        size = 0
        for name, width in (KERNEL_PARAMS + SCENE_PARAMS + neighbours.PARAMS + timestep.PARAMS + guards.PARAMS
                            + tuple(self.method.params)):
            rows[name] = size
            size += self.dim if width == "dim" else width
        for t in terms:
            for name, default in t.params.items():
                if name in rows:
                    raise ValueError(f"parameter {name!r} is declared twice (by {type(t).__name__})")
                rows[name] = size
                size += self.dim if default == "vector" else 1
        self.param_rows = rows
        self.n_params = size
        # the equation of state's columns, then the material constants terms read (material_columns)
        extra = [c for t in terms for c in t.material_columns if c not in eos.columns]
        self.term_material_columns = tuple(dict.fromkeys(extra))
        self.material_columns = tuple(eos.columns) + self.term_material_columns
        return collections.namedtuple("MaterialColumns", self.material_columns)(*range(len(self.material_columns)))

    def _bind(self, scene, terms, eos, integ, mcols):
        """Bind the equation of state, the terms, the integrator, the grid, the time step and
        the guards to the layout and the parameter rows (compile-time assembly)."""
        dim, real, layout, rows = self.dim, self.real, self.layout, self.param_rows
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
        viscosity_rows += [rows[name] for name in self.method.viscosity_params]
        self.timestep = timestep.TimeStep(rows, self.eos, viscosity_rows, [t for t in self.terms if t.has_step_limit])
        self.guards = guards.Guards(dim, layout, rows, self.eos, scene.periodic,
                                    compression_only=self.method.compression_only
                                    or not getattr(scene.eos, "tension", True))
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

    def _plug_in_subsystems(self):
        """What the terms that are whole subsystems declare (:mod:`taisph.terms.base`): the
        rows of the particles they impose, who creates particles, their device arrays and
        their status slots (indices given to each bound term as ``slot`` and ``flag``)."""
        self.imposed_rows = tuple(getattr(self.layout.q, t.imposed_row) for t in self.terms if t.imposed_row)
        self.creators = tuple(t for t in self.terms if t.creates_particles)
        self.device_arrays = {}  # name -> (owning term's name, DeviceArray)
        for t in self.terms:
            for name, spec in t.device_arrays.items():
                if name in self.device_arrays:
                    raise ValueError(f"device array {name!r} is declared twice (by {type(t).__name__})")
                self.device_arrays[name] = (t.name, spec)
        self.status_size, self._status_slots = st.slots(self.terms, "status_slots", st.STATUS_SIZE)
        self.flags_size, self._flag_slots = st.slots(self.terms, "flag_slots", st.FLAGS_SIZE)
        for t in self.terms:
            for attr, where in (("slot", self._status_slots), ("flag", self._flag_slots)):
                names = where.get(t.name, {})
                setattr(t, attr, collections.namedtuple("Slots", list(names) or ["none"])(*names.values() or [-1]))

    def status_slot(self, term: str, name: str) -> int:
        """Index of term `term`'s status slot `name` (``Term.status_slots``)."""
        return self._status_slots[term][name]

    def ordered(self, stage: str) -> list:
        """The bound terms with a launch of their own at `stage`, in the scene's order
        except where a term declares it ``runs_after`` others (a stable topological order)."""
        pending = [t for t in self.terms if t.launches(stage)]
        names = {t.name for t in pending}
        done, order = set(), []
        while pending:
            ready = next((t for t in pending if not (set(t.runs_after) & names) - done), None)
            if ready is None:
                raise ValueError(f"terms' runs_after form a cycle: {', '.join(t.name for t in pending)}")
            pending.remove(ready)
            done.add(ready.name)
            order.append(ready)
        return order

    def active_terms(self, scene) -> list:
        """The scene's terms compiled into this solver's kernels (``Method.terms``)."""
        return self.method.terms(scene)

    def extra_fields(self, field, capacity, list_capacity):
        """Fields the method needs beyond :class:`Args` (``Method.extra_fields``), or None."""
        return self.method.extra_fields(self, field, capacity, list_capacity)

    # ------------------------------------------------------------------------
    def param_table(self, scene, grid_lo, grid_cell, controls, dt=None) -> np.ndarray:
        """Runtime parameter values of `scene`, laid out as the kernels read them;
        `controls` (:class:`taisph.engine.timestep.Controls`) holds the time-step and
        guard settings, `dt` a one-off fixed step."""
        dim = self.dim
        h = scene.smoothing_length
        values = dict(smoothing_length=h, inv_h=1.0 / h, w_norm=self.sigma / h**dim,
                      grad_norm=self.sigma / h ** (dim + 2), support2=(self.kernel.support * h) ** 2,
                      materials=float(len(scene.materials)))
        values.update(neighbours.parameter_values(scene, grid_lo, grid_cell))
        values.update(timestep.parameter_values(controls, dt))
        values.update(guards.parameter_values(scene, controls, self.method.max_speed(scene)))
        values.update(self.method.parameter_values(scene, controls))
        for t in self.active_terms(scene):
            values.update(t.param_values(dim))
        table = np.zeros(self.n_params)
        for name, value in values.items():
            value = np.atleast_1d(value)
            table[self.param_rows[name] : self.param_rows[name] + len(value)] = value
        return table

    def material_table(self, scene) -> np.ndarray:
        return np.array([list(self.eos.material_row(m)) + [float(getattr(m, c)) for c in self.term_material_columns]
                         for m in scene.materials], dtype=float)

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
        """The kernels of one step on `fields` (a FieldSet), in order (``Method.step_kernels``:
        :mod:`taisph.engine.wcsph.method` says what they are for the weakly compressible
        solver), each called as ``kernel(t_target)``."""
        return self.method.step_kernels(self, fields, serial_sort)

    def stepper(self, fields, serial_sort: bool):
        """The host-side stepper of the step on `fields`, for a method that iterates on the
        host (``Method.stepper``: its run statistics), else None."""
        return self.method.stepper(self, fields, serial_sort)

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

