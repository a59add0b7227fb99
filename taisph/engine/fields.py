"""The Taichi fields a simulation's state lives in, and the kernels compiled for them.

State is held in Taichi *fields* (global, fixed-size arrays), not ndarrays: a kernel
compiled for fields knows their addresses, where an ndarray kernel loads each array's
base and shape from its arguments, which costs the dam break's force pass about a
third of its speed (docs/performance.md). Fields are fixed in size and a kernel is
compiled for the fields it reads, so a :class:`FieldSet` is allocated with room to
spare — particles, cells and neighbour-list entries rounded up to powers of two —
and kept in a pool when its simulation closes: the next simulation of the same
configuration that fits reuses the fields *and their compiled kernels*. Kernels thus
compile once per configuration and size class (a run of 30 simulations of different
sizes compiles once per power of two), and loops run over the particles in use
(``sizes[N_PARTICLES]``, :mod:`.status`), not over the capacity.
"""

from __future__ import annotations

import collections
import math

import taichi as ti

from . import runtime
from . import status as st
from .assembly import Args, Buffers

MIN_CAPACITY = 4096
MAX_FREE_PER_SOLVER = 3  # released sets kept for reuse per configuration (older ones are freed)


def _room(n: int, minimum: int = MIN_CAPACITY) -> int:
    """n rounded up to a power of two, at least `minimum`."""
    return max(minimum, 1 << max(0, math.ceil(math.log2(max(1, n)))))


class FieldSet:
    """Every field of one simulation's state (see :class:`Args`), for up to `capacity`
    particles, `cell_capacity` grid cells, `list_capacity` neighbour-list entries per
    particle (1 without lists) and `materials` rows of the material table."""

    def __init__(self, solver, rt: runtime.Runtime, capacity, cell_capacity, list_capacity, materials):
        self.solver, self.runtime = solver, rt
        self.capacity, self.cell_capacity = capacity, cell_capacity
        self.list_capacity, self.materials = list_capacity, materials
        L, dim, real = solver.layout, solver.dim, rt.real
        fb = ti.FieldsBuilder()

        def field(dtype, shape, vector=False):
            f = ti.Vector.field(dim, dtype) if vector else ti.field(dtype)
            fb.dense(ti.ij if len(shape) == 2 else ti.i, shape).place(f)
            return f

        def buffers():  # vectors, scalars, integers: one row per stored quantity
            return Buffers(v=field(real, (len(L.vectors), capacity), vector=True),
                           s=field(real, (len(L.scalars), capacity)), i=field(ti.i32, (len(L.integers), capacity)))

        rows = capacity if solver.lists else 1
        C, S, self.good = buffers(), buffers(), buffers()
        self.args = Args(
            Cv=C.v, Cs=C.s, Ci=C.i, Sv=S.v, Ss=S.s, Si=S.i,
            cell_of=field(ti.i32, (capacity,)), cell_count=field(ti.i32, (cell_capacity,)),
            cell_start=field(ti.i32, (cell_capacity + 1,)), cell_fill=field(ti.i32, (cell_capacity,)),
            params=field(real, (solver.n_params,)), mat=field(real, (materials, len(solver.material_columns))),
            sizes=field(ti.i32, (st.SIZES_SIZE,)), status=field(ti.f64, (solver.status_size,)),
            flags=field(ti.i32, (solver.flags_size,)),
            x_ref=field(real, (rows,), vector=True), nlist=field(ti.i32, (rows, list_capacity)),
            ncount=field(ti.i32, (rows,)),
            aux_int=field(ti.i32, (1, 1)), aux_real=field(real, (1, 1)),  # given as arguments to aux kernels
            store=_store(solver, field, real),
        )
        self.extra = solver.extra_fields(field, capacity, list_capacity)  # the method's own (Method.extra_fields)
        self.controls = None  # the host-side settings of the simulation using these fields (State)
        self.tree = fb.finalize()
        self.kernels = {}  # compiled for these fields, by key
        solver.field_sets.append(self)

    def fits(self, capacity, cell_capacity, list_capacity, materials) -> bool:
        return (capacity <= self.capacity and cell_capacity <= self.cell_capacity
                and list_capacity <= self.list_capacity and materials <= self.materials)

    def kernel(self, key, build):
        """The kernel `build(args)` for these fields, compiled at most once."""
        if key not in self.kernels:
            self.kernels[key] = build(self.args)
        return self.kernels[key]

    def bytes(self) -> int:
        """Memory of the fields (the capacity, not only the particles in use)."""
        total = 0
        extra = [f for part in (self.extra or ()) for f in (part if isinstance(part, tuple) else (part,))]
        for f in (*self.args.state_fields(), *self.args.store, *self.good, *extra):
            total += math.prod(f.shape) * (f.n if hasattr(f, "n") else 1) * (4 if f.dtype in (ti.i32, ti.f32) else 8)
        return total

    def destroy(self):
        if self in self.solver.field_sets:
            self.solver.field_sets.remove(self)
        self.kernels.clear()
        if runtime.is_current(self.runtime):
            self.tree.destroy()


def _store(solver, field, real):
    """The terms' own device arrays (``Term.device_arrays``), a namedtuple by name."""
    arrays = solver.device_arrays
    Store = collections.namedtuple("Store", list(arrays))
    return Store(*(field(real if spec.dtype == "real" else ti.f64, (spec.capacity,)) for _, spec in arrays.values()))


_free: dict = {}  # solver -> released FieldSets
runtime.on_reset(_free.clear)


def acquire(solver, rt, n, n_cells, list_capacity, materials) -> FieldSet:
    """A field set of `solver` with room for the given sizes: a released one that fits
    (the smallest), or a new one with room to spare."""
    free = _free.setdefault(solver, [])
    fitting = [fs for fs in free if fs.fits(n, n_cells, list_capacity, materials)]
    if fitting:
        fs = min(fitting, key=lambda f: f.capacity)
        free.remove(fs)
        return fs
    return FieldSet(solver, rt, _room(n), _room(n_cells), _room(list_capacity, 1), max(4, materials))


def release(fs: FieldSet):
    """Give `fs` back for reuse; beyond MAX_FREE_PER_SOLVER released sets the smallest
    are freed."""
    free = _free.setdefault(fs.solver, [])
    free.append(fs)
    while len(free) > MAX_FREE_PER_SOLVER:
        smallest = min(free, key=lambda f: f.capacity)
        free.remove(smallest)
        smallest.destroy()
