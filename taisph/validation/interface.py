"""The shape of one phase's region from SPH particles: a colour field on a grid, its
level-1/2 contour by marching squares, and the circularity of Hysing et al. (2009).

Hysing et al. (2009, Int. J. Numer. Meth. Fluids 60:1259) measure a rising
bubble's shape by its circularity

    c = P_a / P_b = 2 sqrt(pi A) / P,

the perimeter P_a = 2 pi sqrt(A / pi) of the circle with the bubble's area A over the
bubble's perimeter P_b = P: 1 for a circle, < 1 for any other shape. Here A is the sum
of the phase's particle volumes V_j = m_j / rho_j (what the particles carry, free of any
grid), and P the length of the level-1/2 contour of the phase's colour field
(:func:`colour_field`, :func:`contour_length`).

Pure numpy, so the measure runs wherever the particles' arrays can be read (a frame's
file or a live :class:`taisph.Simulation`, :func:`bubble_circularity`).

    >>> from taisph.validation.interface import bubble_circularity
    >>> c, area, perimeter = bubble_circularity(sim)      # doctest: +SKIP
"""

from __future__ import annotations

import math

import numpy as np

# 2D M4 cubic spline (Monaghan & Lattanzio 1985; Monaghan 1992 eq. 2.6), the engine's
# "spline" (taisph.engine.smoothing.CubicSpline), written out here so that the measure
# needs numpy only. Support 2h.
SIGMA_2D = 10.0 / (7.0 * math.pi)
SUPPORT = 2.0
# nodes evaluated at a time: keeps the (node, particle) pair arrays (~60 rows a node) in cache
NODE_CHUNK = 1 << 14


def cubic_spline_2d(r, h: float):
    """W(r, h) = 10 / (7 pi h^2) f(r / h), with f(q) = 1 - 3/2 q^2 + 3/4 q^3 (q < 1),
    1/4 (2 - q)^3 (1 <= q < 2), 0 beyond: written as f = 1/4 (2 - q)_+^3 - (1 - q)_+^3,
    the same polynomial pieces without a branch (and products, not powers: several times
    faster on large arrays)."""
    q = np.asarray(r, float) * (1.0 / h)
    far, near = np.maximum(2.0 - q, 0.0), np.maximum(1.0 - q, 0.0)
    return SIGMA_2D / (h * h) * (0.25 * far * far * far - near * near * near)


def grid_axis(lo: float, hi: float, spacing: float) -> np.ndarray:
    """Nodes lo, lo + s, ..., hi with n = round((hi - lo) / spacing) steps of s = (hi - lo) / n:
    both ends are nodes, so along a periodic axis the last node is the first one's image
    and the contour closes across the boundary with no cell counted twice."""
    n = max(1, int(round((hi - lo) / spacing)))
    return lo + (hi - lo) * np.arange(n + 1) / n


class _Cells:
    """Square-ish cells of at least `reach` on a side over the box: a particle within
    `reach` of a point lies in the point's cell or one of the 8 around it (or their
    periodic images). Points outside a non-periodic box go to its edge cells, which
    keeps that true for them."""

    def __init__(self, lo, hi, reach: float, periodic):
        self.lo, self.span, self.periodic = lo, hi - lo, tuple(bool(p) for p in periodic)
        self.n = np.maximum(1, np.floor(self.span / reach)).astype(int)
        self.size = self.span / self.n

    def index(self, x: np.ndarray, axis: int) -> np.ndarray:
        k = np.floor((x - self.lo[axis]) / self.size[axis]).astype(np.int64)
        return k % self.n[axis] if self.periodic[axis] else np.clip(k, 0, self.n[axis] - 1)

    def offsets(self, axis: int) -> list:
        """-1, 0, 1, but along a periodic axis of fewer than 3 cells only the distinct
        cells (two offsets that wrap to one cell would count its particles twice)."""
        n = self.n[axis]
        return sorted({o % n for o in (-1, 0, 1)}) if self.periodic[axis] else [-1, 0, 1]

    def neighbour(self, k: np.ndarray, offset: int, axis: int) -> tuple:
        """(cell index, valid) of the cell `offset` from `k` along `axis`."""
        j = k + offset
        if self.periodic[axis]:
            return j % self.n[axis], np.ones(j.shape, bool)
        return np.clip(j, 0, self.n[axis] - 1), (j >= 0) & (j < self.n[axis])


def _prepared(positions, volumes, is_phase, lo, hi, periodic):
    """The finite particles (a removed particle's position is NaN), wrapped into the box
    along periodic axes: (x, V, V c)."""
    x = np.asarray(positions, float).reshape(-1, 2)
    keep = np.isfinite(x).all(axis=1)
    x, v = x[keep].copy(), np.asarray(volumes, float).reshape(-1)[keep]
    c = np.asarray(is_phase, bool).reshape(-1)[keep]
    for axis in range(2):
        if periodic[axis]:
            x[:, axis] = lo[axis] + np.mod(x[:, axis] - lo[axis], hi[axis] - lo[axis])
    return x, v, v * c


def _pairs(count: np.ndarray, start: np.ndarray) -> tuple:
    """(node, particle) rows of every particle of every node's chosen cell, vectorised:
    node k's cell holds the sorted particles start[k] .. start[k] + count[k] - 1."""
    node = np.repeat(np.arange(count.size), count)
    first = start - (np.cumsum(count) - count)  # a node's first particle less its first row
    return node, first[node] + np.arange(node.size)


class _Particles:
    """The finite particles sorted by cell, coordinates as 1D arrays (gathers from 1D
    arrays are an order of magnitude faster than row gathers from an (N, 2) array)."""

    def __init__(self, positions, volumes, is_phase, cells: _Cells, hi):
        x, v, vc = _prepared(positions, volumes, is_phase, cells.lo, hi, cells.periodic)
        linear = cells.index(x[:, 1], 1) * cells.n[0] + cells.index(x[:, 0], 0)
        order = np.argsort(linear, kind="stable")
        self.x, self.y = x[order, 0].copy(), x[order, 1].copy()
        self.v, self.vc = v[order], vc[order]
        self.count = np.bincount(linear, minlength=int(cells.n.prod()))
        self.start = np.cumsum(self.count) - self.count


def _gather(px, py, cells: _Cells, parts: _Particles, h: float) -> tuple:
    """(sum_j V_j c_j W, sum_j V_j W) at the points (px, py), over the particles of each
    point's 3 x 3 block of cells, one cell offset at a time over all the points at once."""
    kx, ky = cells.index(px, 0), cells.index(py, 1)
    numerator, denominator = np.zeros(len(px)), np.zeros(len(px))
    reach2 = (SUPPORT * h) ** 2
    for oy in cells.offsets(1):
        cy, valid_y = cells.neighbour(ky, oy, 1)
        for ox in cells.offsets(0):
            cx, valid_x = cells.neighbour(kx, ox, 0)
            cell = cy * cells.n[0] + cx
            node, j = _pairs(np.where(valid_x & valid_y, parts.count[cell], 0), parts.start[cell])
            d = [px[node] - parts.x[j], py[node] - parts.y[j]]
            for axis in range(2):
                if cells.periodic[axis]:  # nearest image: the period exceeds 4h (checked by the caller)
                    d[axis] -= cells.span[axis] * np.round(d[axis] / cells.span[axis])
            r2 = d[0] * d[0] + d[1] * d[1]
            near = r2 < reach2  # about a third of a 3 x 3 block lies within 2h: the kernel on those only
            node, j = node[near], j[near]
            w = cubic_spline_2d(np.sqrt(r2[near]), h)
            numerator += np.bincount(node, w * parts.vc[j], minlength=len(px))
            denominator += np.bincount(node, w * parts.v[j], minlength=len(px))
    return numerator, denominator


def colour_field(positions, volumes, is_phase, spacing: float, smoothing_length: float, lo, hi,
                 periodic=(False, False)) -> tuple:
    """The phase's colour field on a grid: (gx, gy, field), field[j, i] at (gx[i], gy[j]).

    Shepard-normalised SPH interpolation (Shepard 1968; Monaghan 1992) of the
    indicator c_j (1 for particles of the phase, 0 for the others):

        C(x) = sum_j V_j c_j W(x - x_j, h) / sum_j V_j W(x - x_j, h),

    W the 2D cubic spline (:func:`cubic_spline_2d`, support 2h), 0 where no particle is
    within 2h. The normalisation makes C = 1 (0) wherever every particle in reach is (is
    not) of the phase, however few the particles are: near walls, where only the fluid
    particles are given, the field does not fade. The grid covers the box lo..hi with
    both ends as nodes (:func:`grid_axis`, steps within half a `spacing` of it); along a
    periodic axis (periodic[axis], the box's extent the period) distances are taken to
    the nearest image, which needs the period to exceed 4h.

    Particles are sorted into cells of at least 2h; each grid node gathers the particles
    of its cell's 3 x 3 block (:func:`_gather`), in chunks of :data:`NODE_CHUNK` nodes.
    """
    lo, hi = np.asarray(lo, float).reshape(2), np.asarray(hi, float).reshape(2)
    h, periodic = float(smoothing_length), tuple(bool(p) for p in periodic)
    reach = SUPPORT * h
    for axis in range(2):
        if periodic[axis] and hi[axis] - lo[axis] <= 2.0 * reach:
            raise ValueError(f"colour_field: periodic axis {axis} spans {hi[axis] - lo[axis]:g}, "
                             f"not more than 4h = {2.0 * reach:g} (nearest images would not be unique)")
    gx, gy = grid_axis(lo[0], hi[0], spacing), grid_axis(lo[1], hi[1], spacing)
    cells = _Cells(lo, hi, reach, periodic)
    parts = _Particles(positions, volumes, is_phase, cells, hi)
    px, py = np.meshgrid(gx, gy)
    px, py = px.ravel(), py.ravel()
    field = np.zeros(px.size)
    for s in range(0, px.size, NODE_CHUNK):
        numerator, denominator = _gather(px[s:s + NODE_CHUNK], py[s:s + NODE_CHUNK], cells, parts, h)
        field[s:s + NODE_CHUNK] = np.divide(numerator, denominator, out=np.zeros_like(numerator),
                                            where=denominator > 0)
    return gx, gy, field.reshape(len(gy), len(gx))


def _crossing(f0, f1, level):
    """t in [0, 1] at which the straight line from f0 to f1 takes the value `level`
    (0 where it does not cross, so that no division by zero is made)."""
    crosses = (f0 > level) != (f1 > level)
    return np.where(crosses, (level - f0) / np.where(crosses, f1 - f0, 1.0), 0.0)


def contour_segments(gx, gy, field, level: float = 0.5) -> tuple:
    """The marching-squares contour of `field` at `level` (Lorensen & Cline 1987, in 2D):
    (start, end), each (M, 2), one row per segment, in coordinates relative to
    (gx[0], gy[0]) (the area's cross products then lose no digits to a far origin).

    Inside means field > level. A cell edge whose ends lie on either side is crossed at
    the linear interpolation of its two values. Each segment runs from the crossing where
    the cell's boundary, walked counter-clockwise (bottom, right, top, left), leaves the
    inside to the one where it enters it again: the inside lies on the segment's left,
    which :func:`enclosed_area` uses. A saddle cell (opposite corners inside, the other
    two outside) is resolved by the average of its four corners, the value at its centre
    of the bilinear interpolant: above `level`, the inside corners are joined through the
    centre (each exit pairs with the next entry counter-clockwise), else they are cut
    apart (each exit with the previous entry).
    """
    f = np.asarray(field, float)
    x, y = np.asarray(gx, float) - gx[0], np.asarray(gy, float) - gy[0]
    th, tv = _crossing(f[:, :-1], f[:, 1:], level), _crossing(f[:-1, :], f[1:, :], level)
    hx = x[:-1] + th * np.diff(x)  # crossing of the edge (j, i)-(j, i+1), at y[j]
    vy = y[:-1, None] + tv * np.diff(y)[:, None]  # of the edge (j, i)-(j+1, i), at x[i]
    shape = (len(y) - 1, len(x) - 1)
    X, Y = np.broadcast_to(x[:-1], shape), np.broadcast_to(y[:-1, None], shape)
    X1, Y1 = np.broadcast_to(x[1:], shape), np.broadcast_to(y[1:, None], shape)
    # the crossings on the bottom, right, top and left edges: (4, cells, 2)
    points = np.stack([np.stack([hx[:-1], Y], -1), np.stack([X1, vy[:, 1:]], -1),
                       np.stack([hx[1:], Y1], -1), np.stack([X, vy[:, :-1]], -1)]).reshape(4, -1, 2)
    inside = f > level
    corners = np.stack([inside[:-1, :-1], inside[:-1, 1:], inside[1:, 1:], inside[1:, :-1]]).reshape(4, -1)
    after = np.roll(corners, -1, axis=0)  # each edge's end corner, counter-clockwise
    leaves, enters = corners & ~after, ~corners & after
    saddle = leaves.sum(axis=0) == 2
    simple = np.flatnonzero(leaves.any(axis=0) & ~saddle)
    starts, ends = [leaves[:, simple].argmax(axis=0)], [enters[:, simple].argmax(axis=0)]
    rows = [simple, np.flatnonzero(saddle), np.flatnonzero(saddle)]
    if rows[1].size:
        centre = (f[:-1, :-1] + f[:-1, 1:] + f[1:, 1:] + f[1:, :-1]).reshape(-1)[rows[1]] / 4.0 > level
        first = np.where(corners[0, rows[1]], 0, 1)  # the first exit: bottom if the lower-left corner is in
        step = np.where(centre, 1, -1)
        starts += [first, first + 2]
        ends += [(first + step) % 4, (first + 2 + step) % 4]
    cell, start, end = np.concatenate(rows), np.concatenate(starts), np.concatenate(ends)
    return points[start, cell], points[end, cell]


def contour_length(gx, gy, field, level: float = 0.5) -> float:
    """Total length of the level-`level` contour (:func:`contour_segments`): the sum of its
    straight segments. Only crossings inside the grid count: where the region reaches a
    non-periodic edge of the grid, that stretch of the edge is not part of the length."""
    start, end = contour_segments(gx, gy, field, level)
    return float(np.hypot(*(end - start).T).sum())


def _boundary_term(gx, gy, field, level: float) -> float:
    """1/2 sum (u x v) over the stretches [u, v] of the grid's own edges, walked
    counter-clockwise, where field > level (a stretch ends at the edge's linear crossing)."""
    f = np.asarray(field, float)
    x, y = np.asarray(gx, float) - gx[0], np.asarray(gy, float) - gy[0]
    nx, ny = len(x), len(y)
    loop_x = np.concatenate([x, np.full(ny - 1, x[-1]), x[-2::-1], np.zeros(ny - 2)])
    loop_y = np.concatenate([np.zeros(nx), y[1:], np.full(nx - 1, y[-1]), y[-2:0:-1]])
    loop_f = np.concatenate([f[0, :], f[1:, -1], f[-1, -2::-1], f[-2:0:-1, 0]])
    p0 = np.stack([loop_x, loop_y], -1)
    p1, f0, f1 = np.roll(p0, -1, axis=0), loop_f, np.roll(loop_f, -1)
    cross_at = p0 + _crossing(f0, f1, level)[:, None] * (p1 - p0)
    in0, in1 = f0 > level, f1 > level
    u = np.where(in0[:, None], p0, cross_at)
    v = np.where(in1[:, None], p1, cross_at)
    keep = in0 | in1
    return 0.5 * float((u[keep, 0] * v[keep, 1] - u[keep, 1] * v[keep, 0]).sum())


def enclosed_area(gx, gy, field, level: float = 0.5) -> float:
    """Area of the polygons that the marching-squares contour (:func:`contour_segments`)
    bounds together with the grid's edges: in each cell, the polygon of its corners with
    field > level and its edges' crossings. By Green's theorem, A = 1/2 oint (x dy - y dx)
    over the region's boundary walked counter-clockwise: the cells' shared edges cancel,
    leaving the oriented contour segments and, where the region reaches them, the grid's
    own edges (which is what makes a region across a periodic boundary, whose contour
    is open on the grid, come out right: the grid's two ends there are each other's
    images, see :func:`grid_axis`)."""
    start, end = contour_segments(gx, gy, field, level)
    area = 0.5 * float((start[:, 0] * end[:, 1] - start[:, 1] * end[:, 0]).sum())
    return area + _boundary_term(gx, gy, field, level)


def circularity(positions, volumes, is_phase, spacing: float, smoothing_length: float, lo, hi,
                periodic=(False, False)) -> tuple:
    """(c, A, P) of the phase's region: Hysing et al.'s (2009) circularity
    c = 2 sqrt(pi A) / P, the area A = sum_j V_j over the phase's particles and the
    perimeter P, the length of the colour field's level-1/2 contour (:func:`colour_field`
    on a grid of `spacing`, :func:`contour_length`). c is NaN when no contour is found.
    A lattice's staircase edge leaves short wiggles on the contour, which lengthen P by
    an amount set by h / dx (tests/test_interface_shape.py measures it on lattice shapes)."""
    x = np.asarray(positions, float).reshape(-1, 2)
    phase = np.asarray(is_phase, bool).reshape(-1) & np.isfinite(x).all(axis=1)
    area = float(np.asarray(volumes, float).reshape(-1)[phase].sum())
    gx, gy, field = colour_field(x, volumes, is_phase, spacing, smoothing_length, lo, hi, periodic)
    perimeter = contour_length(gx, gy, field, 0.5)
    c = 2.0 * math.sqrt(math.pi * area) / perimeter if perimeter > 0 else math.nan
    return c, area, perimeter


def bubble_circularity(sim, material: int = 1, spacing: float | None = None) -> tuple:
    """(c, A, P) (:func:`circularity`) of `material`'s region in a 2D taisph Simulation:
    its fluid particles (walls and open boundaries' buffers left out, so the colour field
    is normalised over the fluid alone), volumes m / rho, over the scene's domain and
    periodic axes with its smoothing length; grid `spacing` dx / 4 by default."""
    fluid = sim.fluid
    x = sim.positions()[fluid]
    volume = sim.masses()[fluid] / sim.density()[fluid]
    is_phase = sim.materials()[fluid] == material
    scene = sim.scene
    lo, hi = scene.domain
    periodic = tuple(scene.periodic) if scene.periodic is not None else (False, False)
    spacing = scene.dx / 4.0 if spacing is None else spacing
    return circularity(x, volume, is_phase, spacing, scene.smoothing_length, lo, hi, periodic)
