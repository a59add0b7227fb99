"""Keeping an open boundary's buffer a lattice when the flow through it reverses.

A zone's buffer starts as rows of the fluid's lattice and, while water only enters,
stays one (its successors are placed a whole depth behind the particles that enter).
Water that leaves through a face becomes buffer as it is: the wake of a cylinder, or a
column swallowed by an inlet whose flow turned, is no lattice. When the flow turns again
that buffer comes back in, and the fluid next to the face, or the entrant itself, reads
its crowded pairs and its holes at once: with a summed density a particle far light or
dense trips the density guard. Two rules, applied in the serial bookkeeping after each
step, hold the buffer's spacing to that of a lattice without moving any particle
(the runs that chose them: docs/open_boundaries.md, "Why each choice (measured)"):

- **thinning**: a buffer particle with an older particle of its zone within
  ``THIN * dx`` is retired (its mass left the fluid already; a lattice never has one);
- **filling**, in scenes whose density is summed (``SummationDensity``; with an evolved
  density a hole that enters is not read as a density, and filling would feed mass in):
  a point of the zone's own lattice sites (the rows of its initial buffer, fixed in
  space, all but the farthest) that is a *hole* gets a new buffer particle, a copy of
  one of the zone's (mass, material), whose velocity and density the next step imposes.
  A hole: no particle within ``FILL * dx``; a kernel sum sum_j W dx^dim below ``SPARSE``
  (1 inside a lattice); and surrounded (within 2 dx, at least ``SURROUNDED`` of the
  particles a lattice puts there), so that a free surface crossing the zone is not one
  (a site above it sees ~5 of the 12.6 particles in 2D, ~5 of 33.5 in 3D; a hole 11.6
  and 32.5). One particle missing from a lattice is a hole for the cubic spline and
  Wendland C2 at h = 1.3 dx in 2D (sums 0.73, 0.68), not with h = 2 dx or in 3D (0.81 to
  0.86), where the density sum feels it less. Water that flowed out at its own density
  but off the lattice is not refilled: its sums stay near 1. The farthest row is left to
  the successors, whose places are a whole depth behind an entrant.

Neither changes the fluid's mass: buffer particles are outside the fluid, and the mass
counters move only when a particle crosses a face.
"""

import math

import taichi as ti

from ..engine import status as st

THIN = 0.5  # of dx: closer than this, the younger of two buffer particles is retired
FILL = 0.75  # of dx: a site with no particle this near may be a hole (a lattice's farthest point: 0.71)
SPARSE = 0.8  # a hole's kernel sum, sum W dx^dim, is below this (a lattice: 1; one missing: 1 - W(0) dx^dim)
REACH = 2.0  # of dx (at most the kernel support): the disc or ball a hole must be surrounded in
SURROUNDED = 0.7  # of the particles a lattice has within REACH dx


@ti.data_oriented
class _OlderInZone:
    """Counts, into acc[0], the neighbours in zone acc[1]'s buffer with an id below acc[2]."""

    def __init__(self, q):
        self.q = q

    @ti.func
    def visit(self, s: ti.template(), i, j, rij, r2, acc: ti.template()):
        if s.Si[self.q.open_zone, j] == acc[1] and s.Si[self.q.id, j] < acc[2]:
            acc[0] += 1


@ti.data_oriented
class _Around:
    """Visitor of a site: into acc[0] the kernel sum sum_j W(r) dx^dim over every
    particle in its support (1 inside a lattice), into acc[1] the particles within
    REACH dx, into acc[2] those within FILL dx (acc[3]: dx)."""

    def __init__(self, q, kern, p_inv_h, p_w_norm, dim):
        self.q, self.kern, self.p_inv_h, self.p_w_norm, self.dim = q, kern, p_inv_h, p_w_norm, dim

    @ti.func
    def visit(self, s: ti.template(), i, j, rij, r2, acc: ti.template()):
        spacing = acc[3]
        acc[0] += s.params[self.p_w_norm] * self.kern.f(ti.sqrt(r2) * s.params[self.p_inv_h]) * spacing ** self.dim
        if r2 < (REACH * spacing) ** 2:
            acc[1] += 1.0
        if r2 < (FILL * spacing) ** 2:
            acc[2] += 1.0


class BufferUpkeep:
    """The two rules of the module docstring for the zones of an
    :class:`~taisph.terms.open_boundary.OpenBoundaries` term bound to a solver."""

    def __init__(self, term, solver, copy):
        self.rows, self.dim, self.q, self.grid, self.copy = term.rows, term.dim, term.q, solver.grid, copy
        self.p_support2 = term.p_support2
        self.older = _OlderInZone(term.q)
        self.around = _Around(term.q, solver.kernel, solver.param_rows["inv_h"], solver.param_rows["w_norm"],
                              term.dim)

    @ti.func
    def crowded(self, s: ti.template(), zone, x, particle_id) -> bool:
        """Has buffer particle `particle_id` of `zone` (1-based) at x an older one of its
        zone within THIN dx? (Reads the step's sorted state, whose positions are a
        fraction of dx behind.)"""
        spacing = s.params[self.rows[0].spacing]
        crowd = ti.Vector([0, zone, particle_id])
        self.grid.for_each_neighbour(s, -1, x, (THIN * spacing) ** 2, self.older, crowd)
        return crowd[0] > 0

    @ti.func
    def fill(self, s: ti.template(), z: ti.template(), template, first, capacity) -> int:
        """New buffer particles of zone z (0-based, static) at its empty sites, copies of
        particle `template` of ``C``, into slots from `first`; returns how many (those
        without room are counted in ``NO_ROOM``)."""
        r = ti.static(self.rows[z])
        dim = ti.static(self.dim)
        origin = ti.Vector([s.params[r.origin + d] for d in ti.static(range(dim))])
        normal = ti.Vector([s.params[r.normal + d] for d in ti.static(range(dim))])
        axis1 = ti.Vector([s.params[r.axis1 + d] for d in ti.static(range(dim))])
        axis2 = ti.Vector([s.params[r.axis2 + d] for d in ti.static(range(dim))])
        spacing = s.params[r.spacing]
        n1 = ti.cast(s.params[r.length1] / spacing + 0.5, ti.i32)
        n2 = 1
        if ti.static(dim == 3):
            n2 = ti.cast(s.params[r.length2] / spacing + 0.5, ti.i32)
        rows = ti.cast(s.params[r.depth] / spacing + 0.5, ti.i32) - 1  # not the farthest: the successors'
        reach2 = ti.min((REACH * spacing) ** 2, s.params[self.p_support2])
        ball = math.pi * reach2 / spacing**2  # particles of a lattice within the reach (2D)
        if ti.static(dim == 3):
            ball = 4.0 / 3.0 * math.pi * ti.pow(reach2, 1.5) / spacing**3
        surrounded = SURROUNDED * ball
        made = 0
        for a in range(n1):
            for b in range(n2):
                for k in range(rows):
                    site = origin + (a + 0.5) * spacing * axis1 - (k + 0.5) * spacing * normal
                    if ti.static(dim == 3):
                        site += (b + 0.5) * spacing * axis2
                    found = ti.Vector([0.0, 0.0, 0.0, spacing])
                    self.grid.for_each_neighbour(s, -1, site, s.params[self.p_support2], self.around, found)
                    if found[0] < SPARSE and found[1] >= surrounded and found[2] == 0.0:
                        made += self.place(s, template, first + made, capacity, site, z + 1)
        return made

    @ti.func
    def place(self, s: ti.template(), source, slot, capacity, position, zone) -> int:
        """A new buffer particle of `zone` (1-based) at `position`: a copy of particle
        `source` of ``C`` into `slot`, with the next id; 1, or 0 without room (counted in
        ``NO_ROOM``: the run stops saying how many it could not create)."""
        placed = 0
        if slot < capacity:
            self.copy(s.C, source, s.C, slot)
            s.Cv[self.q.position, slot] = position
            s.Ci[self.q.open_zone, slot] = zone
            s.Ci[self.q.id, slot] = s.flags[st.NEXT_ID]
            s.flags[st.NEXT_ID] += 1
            placed = 1
        else:
            s.flags[st.NO_ROOM] += 1
        return placed
