"""Uniform-grid neighbour search by counting sort.

The grid covers the scene's domain with cubic cells of edge ``cell`` (at least the
kernel support radius), numbered x-fastest: ``c = cx + nx (cy + ny cz)``. Every step
(:func:`taisph.solver`):

1. each particle's cell index is computed, and the particles of each cell counted;
2. an exclusive prefix sum over the cells gives each cell's first slot (serial: a
   scan over 10^5 cells costs well under a millisecond, and Taichi 1.7's
   ``PrefixSumExecutor`` does not run on the CPU);
3. every particle is scattered - its whole state, not only its index - to its slot,
   so the state arrays are sorted by cell and a cell's particles are contiguous.

Because cells are numbered x-fastest, the three cells ``cx-1 .. cx+1`` of one row are
contiguous too: a particle's neighbours are in ``3^(dim-1)`` contiguous slot ranges.

Particles outside the domain (or with non-finite coordinates) are clamped into the
border cells, so no index ever leaves the arrays. Clamping keeps every pair closer
than one cell in adjacent cells, so the neighbour set stays exact; only the speed
suffers if many particles pile up outside the domain.
"""


import math

import numpy as np
import taichi as ti


def grid_shape(lo, hi, cell: float) -> tuple[int, ...]:
    """Number of cells per axis covering the box [lo, hi] with cells of edge `cell`."""
    lo = np.asarray(lo, dtype=float)
    hi = np.asarray(hi, dtype=float)
    return tuple(max(1, int(math.ceil((b - a) / cell - 1e-9))) for a, b in zip(lo, hi))


@ti.data_oriented
class Grid:
    """Cell arithmetic inside kernels. ``s.params[p_lo + d]`` is the grid origin,
    ``s.params[p_inv_cell]`` the inverse cell edge; ``s.gshape`` holds
    ``(n0, n1, n2, n_cells)``."""

    def __init__(self, dim: int, real, p_lo: int, p_inv_cell: int):
        self.dim = dim
        self.real = real
        self.p_lo = p_lo
        self.p_inv_cell = p_inv_cell

    @ti.func
    def coords(self, s: ti.template(), x):
        c = ti.Vector.zero(ti.i32, self.dim)
        inv = s.params[self.p_inv_cell]
        for d in ti.static(range(self.dim)):
            # Compare in floating point before casting: a float-to-int cast of a
            # huge or NaN coordinate is undefined, a clamped float is not.
            f = ti.floor((x[d] - s.params[self.p_lo + d]) * inv)
            clamped = ti.cast(0.0, self.real)  # also for NaN, which fails f >= 0
            if f >= 0.0:
                clamped = ti.min(f, ti.cast(s.gshape[d] - 1, self.real))
            c[d] = ti.cast(clamped, ti.i32)
        return c

    @ti.func
    def linear(self, s: ti.template(), c):
        index = c[self.dim - 1]
        for k in ti.static(range(self.dim - 1)):
            d = self.dim - 2 - k
            index = index * s.gshape[d] + c[d]
        return index

    @ti.func
    def row_range(self, s: ti.template(), c, row: ti.template()):
        """Slots [begin, end) of the cells (cx-1..cx+1, cy+dy, cz+dz) where
        (dy, dz) is the `row`-th of the 3^(dim-1) offsets; empty off the grid."""
        begin = 0
        end = 0
        inside = True
        other = c
        for d in ti.static(range(1, self.dim)):
            offset = ti.static((row // 3 ** (d - 1)) % 3 - 1)
            other[d] = c[d] + offset
            if other[d] < 0 or other[d] >= s.gshape[d]:
                inside = False
        if inside:
            other[0] = ti.max(c[0] - 1, 0)
            first = self.linear(s, other)
            other[0] = ti.min(c[0] + 1, s.gshape[0] - 1)
            last = self.linear(s, other)
            begin = s.cell_start[first]
            end = s.cell_start[last + 1]
        return begin, end
