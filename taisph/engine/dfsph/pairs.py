"""A per-step pair list: each particle's neighbours and the scalar of its kernel gradient.

DFSPH (:mod:`.solver`) sums over the same neighbours 2 x (iterations + 1) times per
step with the positions unchanged, and walking the cells and evaluating grad W in
every pass costs three times a walk of a list (docs/dfsph.md, "Pair list"); so the
step's first pass walks the cells once and stores, for every fluid particle i and
neighbour j (fluid or wall) closer than the support radius,

    nbr[i, k] = j,     coef[i, k] = m_j F(r_ij),    with  m_j grad_i W_ij = coef[i, k] r_ij,

and every later pass walks the list, recomputing r_ij = x_i - x_j from the positions.
The scalar rather than the vector m_j grad W_ij: as fast, and 12 bytes per entry
instead of 20 (f64, 2D).

The list has a fixed number of entries per particle (:func:`capacity`, ~1.3 times the
particles a full kernel support holds on the lattice, the field set's
``list_capacity``). A particle with more neighbours (particles crushed together,
which the incompressible solver should never allow) keeps the first ones and trips
a guard, ``CROWDED``, whose message says so: its sums would otherwise be wrong.
"""


import collections
import math

import taichi as ti

from .. import status as st
from ..neighbours import ball_volume

PairFields = collections.namedtuple("PairFields", "nbr coef count")


def capacity(scene) -> int:
    """Entries per particle: 1.3 times the lattice particles within the support
    radius (a ball of it over dx^dim), plus 4, rounded up to a multiple of 4."""
    k = math.ceil(1.3 * ball_volume(scene.support_radius, scene.dim) / scene.dx**scene.dim) + 4
    return 4 * math.ceil(k / 4)


def allocate(field, capacity_particles: int, entries: int, real) -> PairFields:
    """The list's fields for `capacity_particles` particles of `entries` entries each
    (``field(dtype, shape)`` places a field in the caller's FieldsBuilder)."""
    return PairFields(nbr=field(ti.i32, (capacity_particles, entries)), coef=field(real, (capacity_particles, entries)),
                      count=field(ti.i32, (capacity_particles,)))


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
        if k < s.sizes[st.LIST_CAPACITY]:
            self.f.nbr[i, k] = j
            self.f.coef[i, k] = coef

    @ti.func
    def close(self, s: ti.template(), i, k) -> bool:
        """Record i's pair count k; False if the list had no room for all of them."""
        capacity = s.sizes[st.LIST_CAPACITY]
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
