"""Uniform-grid neighbour search by counting sort, with optional periodic axes.

The grid covers the scene's domain with cells at least as large as the kernel support
radius, numbered x-fastest: ``c = cx + nx (cy + ny cz)``. Every step, in the first
kernel of the step (:mod:`taisph.engine.kernels`, functions :meth:`Grid.count`,
:meth:`Grid.scan`, :meth:`Grid.slot`):

1. each particle's cell index is computed, and the particles of each cell counted;
2. an exclusive prefix sum over the cells gives each cell's first slot (serial: a
   scan over 10^5 cells costs well under a millisecond, and Taichi 1.7's
   ``PrefixSumExecutor`` does not run on the CPU);
3. every particle is scattered - its whole state, not only its index - to its slot,
   so the state arrays are sorted by cell and a cell's particles are contiguous.

Because cells are numbered x-fastest, the three cells ``cx-1 .. cx+1`` of one row are
contiguous too: a particle's neighbours are in ``3^(dim-1)`` contiguous slot ranges
(``3^dim`` single cells when the x axis is periodic, since its rows wrap around).

Non-periodic axes: particles outside the domain (or with non-finite coordinates) are
clamped into the border cells, so no index ever leaves the arrays. Clamping keeps every
pair closer than one cell in adjacent cells, so the neighbour set stays exact; only
the speed suffers if many particles pile up outside the domain.

Periodic axes: the domain's extent ``L`` is the period; positions are wrapped into
``[lo, lo + L)`` every step, the grid has ``n = floor(L / support) >= 3`` cells of edge
``L / n`` along the axis, neighbouring cells wrap around, and separations use the
nearest image, ``r_ij -= L round(r_ij / L)``.

Neighbour lists with a skin (Verlet lists; the seed report's "further work"), when the
scene's ``neighbour_skin`` is > 0 (compile time; the skin length is a runtime value):

- at a *rebuild* the particles are sorted by cell as above, with cells of edge
  ``support + skin``, and every particle's list of the particles closer than
  ``support + skin`` is stored (``nlist[i, :ncount[i]]``) while the first neighbour
  pass of the step walks the cells; ``x_ref`` keeps the positions they were built at;
- between rebuilds the state is not reordered (the "sort" is an identity copy), and
  neighbour sums walk the list, keeping the pairs closer than ``support``;
- the sort pass measures every particle's displacement from ``x_ref`` (at the
  position the rates are evaluated at) and rebuilds when the largest, ``d_max``,
  reaches half the skin: a pair closer than ``support`` now was closer than
  ``support + 2 d_max <= support + skin`` at the rebuild, so the lists are exact;
- a particle whose list would overflow the list's capacity gets ``ncount = -1`` and
  walks the cells around its ``x_ref`` instead (exact too: its neighbours were within
  ``support + skin`` of ``x_ref``, that is in the adjacent cells); so a dense spot
  only costs speed, never a neighbour.
"""

import collections
import math

import numpy as np
import taichi as ti

from . import status as st
from .layout import WALL
from ..messages import InputError


class GridLayout(collections.namedtuple("GridLayout", "lo cell shape")):
    """Where the grid lies: its origin ``lo`` and cell edges ``cell`` (one per axis) and
    its ``shape``, the cells along each axis."""

    __slots__ = ()

    @property
    def n_cells(self) -> int:
        return math.prod(int(n) for n in self.shape)  # Python's ints: np.prod of int64 wraps around


def ball_volume(radius: float, dim: int) -> float:
    """The volume of a ball of `radius` in `dim` dimensions (a segment's length in 1D, a
    disc's area in 2D): over dx^dim, the lattice particles within that radius."""
    return {1: 2.0 * radius, 2: math.pi * radius**2, 3: 4.0 / 3.0 * math.pi * radius**3}[dim]


def layout_grid(domain, periodic, support, positions) -> GridLayout:
    """The grid for a domain, its periodic axes, the kernel support radius and the
    current (finite) positions."""
    lo_d, hi_d = (np.asarray(a, dtype=float) for a in domain)
    dim = len(lo_d)
    finite = positions[np.all(np.isfinite(positions), axis=1)]
    lo = np.empty(dim)
    cell = np.empty(dim)
    shape = []
    for d in range(dim):
        if periodic[d]:
            length = hi_d[d] - lo_d[d]
            n = int(math.floor(length / support * (1 + 1e-12)))
            if n < 3:
                raise InputError(
                    f"periodic axis {d} is {length:g} long: it needs at least 3 kernel supports "
                    f"({3 * support:g}) for the nearest-image neighbour search"
                )
            lo[d], cell[d] = lo_d[d], length / n
            shape.append(n)
        else:
            a = min(lo_d[d], finite[:, d].min() if len(finite) else lo_d[d]) - support
            b = max(hi_d[d], finite[:, d].max() if len(finite) else hi_d[d]) + support
            lo[d], cell[d] = a, support
            shape.append(max(1, int(math.ceil((b - a) / support - 1e-9))))
    return GridLayout(lo=lo, cell=cell, shape=tuple(shape))


def grid_cells(lo, hi, support: float):
    """The cells of :func:`layout_grid`'s grid over particles in `lo` .. `hi` (no periodic axis): a Python int."""
    spans = [(float(b) - float(a)) / support + 2.0 for a, b in zip(lo, hi)]
    return math.prod(max(1, math.ceil(v - 1e-9)) for v in spans) if all(map(math.isfinite, spans)) else math.inf


def grid_problem(n_cells, n_particles: int, support: float) -> str:
    """'' if `n_cells` grid cells are in proportion to `n_particles`, else what is wrong (the readers' check too)."""
    if n_cells <= (allowed := MAX_CELLS_PER_PARTICLE * n_particles + 4096):
        return ""
    return (f"the neighbour grid would need {n_cells:.3g} cells of {support:g} m for {n_particles} particles (at most "
            f"{allowed}): the domain is too large for the smoothing length")


PARAMS = (  # runtime parameters, name and width ("dim": one per axis)
    ("grid_lo", "dim"),  # the grid's origin
    ("grid_inv_cell", "dim"),  # 1 / cell edge
    ("period", "dim"),  # period of each periodic axis (0 otherwise)
    ("list_skin", 1),  # neighbour list skin (length); the lists hold pairs closer than
    ("list_reach2", 1),  # (support + skin)^2
    ("list_wall_reach2", 1),  # (wall range + skin)^2, if no term needs walls farther
)

# Grids with more cells than this per particle are refused: the domain is too large
# for the smoothing length (a typo in a unit, usually) and memory would explode.
MAX_CELLS_PER_PARTICLE = 64


def list_reach(scene) -> float:
    """Cell edge and list range: the support radius plus the skin (a fraction of it);
    a periodic axis needs 3 cells, which may shorten the skin."""
    support = scene.support_radius
    reach = support * (1.0 + scene.neighbour_skin)
    lo, hi = (np.asarray(a, float) for a in scene.domain)
    for d in range(scene.dim):
        if scene.periodic[d]:
            reach = max(support, min(reach, (hi[d] - lo[d]) / 3.0))
    return reach


def list_capacity(scene) -> int:
    """Entries per particle's neighbour list: 1.5 times the particles within
    support + skin of a particle in a lattice of spacing dx, plus a margin.
    A particle with more (a compressed spot, a wall of closer particles) walks
    the cells instead; its neighbours are still all found."""
    reach = scene.support_radius * (1.0 + scene.neighbour_skin)
    return int(min(scene.n, math.ceil(1.5 * ball_volume(reach, scene.dim) / scene.dx**scene.dim) + 8))


def wall_range(scene) -> float:
    """How far any term looks at wall neighbours, when none needs the full support
    (e.g. the Lennard-Jones cut-off); the support radius otherwise."""
    reach = 0.0
    for t in scene.terms:
        r = t.wall_reach()
        if r == "support":
            return scene.support_radius
        if r is not None:
            reach = max(reach, float(t.values[r]))
    return reach


def parameter_values(scene, grid_lo, grid_cell) -> dict:
    """Values of :data:`PARAMS` for `scene` and its grid."""
    lo, hi = scene.domain
    skin = list_reach(scene) - scene.support_radius
    return dict(
        grid_lo=grid_lo,
        grid_inv_cell=1.0 / np.asarray(grid_cell),
        period=np.where(scene.periodic, hi - lo, 0.0),
        list_skin=skin,
        list_reach2=(scene.support_radius + skin) ** 2,
        list_wall_reach2=(wall_range(scene) + skin) ** 2,
    )


@ti.data_oriented
class Grid:
    """Cell arithmetic, counting sort and neighbour walks inside kernels.

    ``s.params[p_lo + d]`` is the grid origin, ``s.params[p_inv_cell + d]`` the inverse
    cell edge and ``s.params[p_period + d]`` the period of axis d; ``s.sizes`` holds the
    grid's shape and counts (:mod:`.status`: GRID_SHAPE, N_CELLS, ...). ``periodic`` (a
    tuple of bools) and ``lists`` are compile-time; ``kind_row`` (the row of the particle kind) is given when the lists
    keep walls only within the range the terms need them (``list_wall_reach2``).
    """

    def __init__(self, dim, real, param_rows, periodic, lists=False, kind_row=None):
        self.lists = bool(lists)  # compile time: neighbour lists with a skin
        self.has_short_walls = kind_row is not None
        self.kind_row = kind_row
        self.p_skin = param_rows["list_skin"]
        self.p_reach2 = param_rows["list_reach2"]
        self.p_wall_reach2 = param_rows["list_wall_reach2"]
        self.dim = dim
        self.real = real
        self.p_lo = param_rows["grid_lo"]
        self.p_inv_cell = param_rows["grid_inv_cell"]
        self.p_period = param_rows["period"]
        self.periodic = tuple(bool(p) for p in periodic)
        self.any_periodic = any(self.periodic)
        # slot ranges per particle: merged rows, or single cells if x wraps around
        self.n_ranges = 3**dim if self.periodic[0] else 3 ** (dim - 1)

    @ti.func
    def wrap(self, s: ti.template(), x):
        """Position moved into the periodic box along periodic axes."""
        y = x
        for d in ti.static(range(self.dim)):
            if ti.static(self.periodic[d]):
                lo = s.params[self.p_lo + d]
                period = s.params[self.p_period + d]
                y[d] = lo + (x[d] - lo) - period * ti.floor((x[d] - lo) / period)
                if y[d] >= lo + period:  # rounding of the line above
                    y[d] = lo
        return y

    @ti.func
    def separation(self, s: ti.template(), xi, xj):
        """x_i - x_j, by the nearest image along periodic axes."""
        rij = xi - xj
        for d in ti.static(range(self.dim)):
            if ti.static(self.periodic[d]):
                period = s.params[self.p_period + d]
                rij[d] -= period * ti.round(rij[d] / period)
        return rij

    @ti.func
    def coords(self, s: ti.template(), x):
        c = ti.Vector.zero(ti.i32, self.dim)
        for d in ti.static(range(self.dim)):
            # Compare in floating point before casting: a float-to-int cast of a
            # huge or NaN coordinate is undefined, a clamped float is not.
            f = ti.floor((x[d] - s.params[self.p_lo + d]) * s.params[self.p_inv_cell + d])
            clamped = ti.cast(0.0, self.real)  # also for NaN, which fails f >= 0
            if f >= 0.0:
                clamped = ti.min(f, ti.cast(s.sizes[st.GRID_SHAPE + d] - 1, self.real))
            c[d] = ti.cast(clamped, ti.i32)
        return c

    @ti.func
    def linear(self, s: ti.template(), c):
        index = c[self.dim - 1]
        for k in ti.static(range(self.dim - 1)):
            d = self.dim - 2 - k
            index = index * s.sizes[st.GRID_SHAPE + d] + c[d]
        return index

    @ti.func
    def slot_range(self, s: ti.template(), c, k):
        """Slots [begin, end) of the k-th of the n_ranges neighbour cell ranges of cell c
        (k a runtime index); empty where it falls off a non-periodic grid."""
        begin = 0
        end = 0
        inside = True
        other = c
        first_axis = ti.static(0 if self.periodic[0] else 1)
        for d in ti.static(range(first_axis, self.dim)):
            offset = (k // ti.static(3 ** (d - first_axis))) % 3 - 1
            other[d] = c[d] + offset
            if ti.static(self.periodic[d]):
                n = s.sizes[st.GRID_SHAPE + d]
                if other[d] < 0:
                    other[d] += n
                elif other[d] >= n:
                    other[d] -= n
            elif other[d] < 0 or other[d] >= s.sizes[st.GRID_SHAPE + d]:
                inside = False
        if inside:
            if ti.static(self.periodic[0]):
                cell = self.linear(s, other)
                begin = s.cell_start[cell]
                end = s.cell_start[cell + 1]
            else:
                other[0] = ti.max(c[0] - 1, 0)
                first = self.linear(s, other)
                other[0] = ti.min(c[0] + 1, s.sizes[st.GRID_SHAPE] - 1)
                last = self.linear(s, other)
                begin = s.cell_start[first]
                end = s.cell_start[last + 1]
        return begin, end

    # --- counting sort (the first kernel of a step) ----------------------------------
    @ti.func
    def count(self, s: ti.template(), i, x):
        """Step 1: particle i (at x) is in cell c; count it."""
        c = self.linear(s, self.coords(s, x))
        s.cell_of[i] = c
        ti.atomic_add(s.cell_count[c], 1)

    @ti.func
    def scan(self, s: ti.template()):
        """Step 2 (serial): each cell's first slot, an exclusive prefix sum of the counts
        (on a rebuild; between rebuilds the cells of the last rebuild are kept, as the
        lists' fallback). Resets the counts for the next step."""
        if self.decide_rebuild(s):
            running = 0
            for c in range(s.sizes[st.N_CELLS]):
                s.cell_start[c] = running
                s.cell_fill[c] = running
                running += s.cell_count[c]
                s.cell_count[c] = 0
            s.cell_start[s.sizes[st.N_CELLS]] = running
        else:
            for c in range(s.sizes[st.N_CELLS]):
                s.cell_count[c] = 0

    @ti.func
    def slot(self, s: ti.template(), i, rebuild):
        """Step 3: the cell-sorted slot particle i's state is scattered to (between list
        rebuilds the order stays that of the last rebuild)."""
        slot = i
        if rebuild:
            slot = ti.atomic_add(s.cell_fill[s.cell_of[i]], 1)
        return slot

    @ti.func
    def note_displacement(self, s: ti.template(), i, x):
        """Track the largest displacement of particle i (now at x, in the memory order
        of the last rebuild) from where the lists were built."""
        if ti.static(self.lists):
            d2 = ti.cast(self.separation(s, x, s.x_ref[i]).norm_sqr(), ti.f64)
            if d2 > s.status[st.MAX_DISP2]:  # read first: rarely grows
                ti.atomic_max(s.status[st.MAX_DISP2], d2)

    @ti.func
    def decide_rebuild(self, s: ti.template()) -> bool:
        """(Serial.) Rebuild the lists this step? Always without lists."""
        rebuild = True
        if ti.static(self.lists):
            skin = ti.cast(s.params[self.p_skin], ti.f64)
            rebuild = s.status[st.FORCE_REBUILD] > 0.0 or 4.0 * s.status[st.MAX_DISP2] >= skin * skin
            s.status[st.REBUILD] = 1.0 if rebuild else 0.0
            s.status[st.FORCE_REBUILD] = 0.0
            if rebuild:
                s.status[st.REBUILDS] += 1.0
        return rebuild

    @ti.func
    def rebuilding(self, s: ti.template()) -> bool:
        rebuild = True
        if ti.static(self.lists):
            rebuild = s.status[st.REBUILD] > 0.0
        return rebuild

    @ti.func
    def for_each_neighbour(self, s: ti.template(), i, xi, support2, visitor: ti.template(), acc: ti.template()):
        """Call ``visitor.visit(s, i, j, rij, r2, acc)`` for every particle j != i with
        |x_i - x_j|^2 < support2 (x_i = xi), in a fixed order (so sums are reproducible).

        With neighbour lists: walks i's list, or on a rebuild step walks the cells and
        stores the list on the way (the visitor's code is inlined once per cell range
        either way: one loop serves both, only where j comes from differs)."""
        if ti.static(not self.lists):
            c = self.coords(s, xi)
            # a runtime loop over the cell ranges: the visitor's code is inlined once
            # (unrolled, 9 times in 3D: compiles 4x longer, runs no faster; docs/performance.md)
            for k in range(self.n_ranges):
                begin, end = self.slot_range(s, c, k)
                for j in range(begin, end):
                    rij = self.separation(s, xi, s.Sv[visitor.q.position, j])
                    r2 = rij.norm_sqr()
                    if r2 < support2 and j != i:
                        visitor.visit(s, i, j, rij, r2, acc)
        else:
            build = s.status[st.REBUILD] > 0.0
            count = s.ncount[i]
            from_list = count >= 0 and not build
            reach2 = s.params[self.p_reach2]
            capacity = s.sizes[st.LIST_CAPACITY]  # entries per list (the field may have room for more)
            c = self.coords(s, s.x_ref[i])  # == xi on a rebuild step
            stored = 0
            n_loops = self.n_ranges
            if from_list:
                n_loops = 1
            for k in range(n_loops):
                begin, end = 0, count
                if not from_list:
                    begin, end = self.slot_range(s, c, k)
                for m in range(begin, end):
                    j = m
                    if from_list:
                        j = s.nlist[i, m]
                    rij = self.separation(s, xi, s.Sv[visitor.q.position, j])
                    r2 = rij.norm_sqr()
                    keep = r2 < reach2 and j != i
                    if ti.static(self.has_short_walls):
                        if s.Si[self.kind_row, j] == WALL:
                            keep = keep and r2 < s.params[self.p_wall_reach2]
                    if build and keep:
                        if stored < capacity:
                            s.nlist[i, stored] = j
                        stored += 1
                    if r2 < support2 and j != i:
                        visitor.visit(s, i, j, rij, r2, acc)
            if build:
                s.ncount[i] = stored if stored <= capacity else -1
