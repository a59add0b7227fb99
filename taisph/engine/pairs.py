"""A per-step pair list: each particle's neighbours and the scalar of its kernel gradient.

DFSPH (:mod:`.dfsph`) sums over the same neighbours 2 x (iterations + 1) times per
step with the positions unchanged. Walking the cells and evaluating grad W in every
pass cost 0.96-1.14 ms per pass at 20k particles (2D, 2 threads, issue 14); so the
step's first pass walks the cells once and stores, for every fluid particle i and
neighbour j (fluid or wall) closer than the support radius,

    nbr[i, k] = j,     coef[i, k] = m_j F(r_ij),    with  m_j grad_i W_ij = coef[i, k] r_ij,

and every later pass walks the list, recomputing r_ij = x_i - x_j from the positions.
Storing the scalar instead of the vector m_j grad W_ij (dim reals) costs the same
time per pass (20k particles, two passes per iteration, same process, three
alternating blocks: 0.30-0.32 ms per pass with the scalar, 0.27-0.86 ms with the
vector, 0.31-0.35 with the vector in f32) and 12 bytes per entry instead of 20 (f64,
2D): 32 entries per particle, 388 bytes with the count.

The list has a fixed number of entries per particle (:func:`capacity`, ~1.3 times the
particles a full kernel support holds on the lattice, the field set's
``list_capacity``). A particle with more neighbours (particles crushed together,
which the incompressible solver should never allow) keeps the first ones and trips
a guard, ``CROWDED``, whose message says so: its sums would otherwise be wrong.
"""


import collections
import math

import taichi as ti

PairFields = collections.namedtuple("PairFields", "nbr coef count")


def capacity(scene) -> int:
    """Entries per particle: 1.3 times the lattice particles within the support
    radius (a ball of it over dx^dim), plus 4, rounded up to a multiple of 4."""
    support = scene.support_radius
    ball = {1: 2.0 * support, 2: math.pi * support**2, 3: 4.0 / 3.0 * math.pi * support**3}[scene.dim]
    k = math.ceil(1.3 * ball / scene.dx**scene.dim) + 4
    return 4 * math.ceil(k / 4)


def allocate(field, capacity_particles: int, entries: int, real) -> PairFields:
    """The list's fields for `capacity_particles` particles of `entries` entries each
    (``field(dtype, shape)`` places a field in the caller's FieldsBuilder)."""
    return PairFields(field(ti.i32, (capacity_particles, entries)), field(real, (capacity_particles, entries)),
                      field(ti.i32, (capacity_particles,)))


def bytes_per_particle(entries: int, real_bytes: int) -> int:
    return 4 + entries * (4 + real_bytes)


@ti.data_oriented
class PairList:
    """Inside kernels: store a pair while the cells are walked, walk a particle's pairs."""

    def __init__(self, fields: PairFields, grid, position_row):
        self.f = fields
        self.grid = grid
        self.position = position_row

    @ti.func
    def store(self, s: ti.template(), i, k, j, coef):
        """The k-th pair of i (k counted by the caller); kept if the list has room."""
        if k < s.sizes[5]:
            self.f.nbr[i, k] = j
            self.f.coef[i, k] = coef

    @ti.func
    def close(self, s: ti.template(), i, k) -> bool:
        """Record i's pair count k; False if the list had no room for all of them."""
        capacity = s.sizes[5]
        self.f.count[i] = ti.min(k, capacity)
        return k <= capacity

    @ti.func
    def for_each(self, s: ti.template(), i, xi, visitor: ti.template(), acc: ti.template()):
        """``visitor.visit(s, i, j, rij, r2, coef, acc)`` for every stored pair of i (at
        xi), like :meth:`taisph.engine.neighbours.Grid.for_each_neighbour` and with the
        pair's stored coefficient m_j F(r_ij)."""
        for k in range(self.f.count[i]):
            j = self.f.nbr[i, k]
            rij = self.grid.separation(s, xi, s.Sv[self.position, j])
            visitor.visit(s, i, j, rij, rij.norm_sqr(), self.f.coef[i, k], acc)
