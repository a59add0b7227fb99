"""Particles from closed surfaces: points on them and lattice points inside them.

``surface_points(mesh, spacing)``: points on the surface about `spacing` apart (for
Lennard-Jones walls). ``volume_points(mesh, spacing)``: the lattice points inside
(fluid blocks), or with `depth` only those within `depth` of the surface (the layers
of dummy-wall particles a solid needs). `mesh` is anything
:func:`taisph.mesh.load_surface` takes: a file name (STL, OBJ, PLY, VTK, VTU, ...),
a meshio mesh, ``(vertices, cells)`` or a 2D polygon; an open, inconsistently
oriented or empty mesh is refused with its name and the problem.

Both are vectorised numpy, linear in the number of points made (timings in
docs/scenes.md).
"""

from __future__ import annotations

import numpy as np

from .mesh import PAIRS_PER_CHUNK, load_surface, pair_distances


def surface_points(mesh, spacing: float, dim: int | None = None) -> np.ndarray:
    """Points on the closed surface `mesh`, at most `spacing` apart along every edge.

    Every vertex once; each edge (shared by two cells) divided into
    ceil(length / spacing) equal parts, its inner division points once; inside each
    triangle the inner points of its barycentric grid (i, j, k) / n, i, j, k >= 1,
    with n = ceil(longest edge / spacing), so the grid's small triangles have sides
    of at most `spacing`. 2D: the vertices and the divided segments (a polygon).
    Every point lies on a cell, up to round-off.
    """
    spacing = _positive(spacing, "spacing")
    surface = load_surface(mesh, dim)
    vertices, cells = surface.vertices, surface.cells
    parts = [vertices[np.unique(cells)]]
    if surface.dim == 3:
        edges = np.unique(np.sort(np.concatenate([cells[:, [0, 1]], cells[:, [1, 2]], cells[:, [2, 0]]]), axis=1),
                          axis=0)
    else:
        edges = cells
    a, b = vertices[edges[:, 0]], vertices[edges[:, 1]]
    n = _divisions(np.linalg.norm(b - a, axis=1), spacing)
    edge = np.repeat(np.arange(len(edges)), n - 1)
    k = np.arange(len(edge)) - np.repeat(np.cumsum(n - 1) - (n - 1), n - 1) + 1
    t = (k / n[edge])[:, None]
    parts.append(a[edge] + t * (b[edge] - a[edge]))
    if surface.dim == 3:
        corners = surface.corners
        longest = np.max(np.linalg.norm(corners - np.roll(corners, 1, axis=1), axis=2), axis=1)
        n = _divisions(longest, spacing)
        for m in np.unique(n[n >= 3]):
            i, j = np.meshgrid(np.arange(1, m), np.arange(1, m), indexing="ij")
            keep = i + j < m
            weights = np.column_stack([i[keep], j[keep], m - i[keep] - j[keep]]) / m
            parts.append(np.einsum("wk,tkd->twd", weights, corners[n == m]).reshape(-1, 3))
    return np.concatenate(parts)


def volume_points(mesh, spacing: float, depth: float | None = None, origin=None,
                  dim: int | None = None) -> np.ndarray:
    """The points ``origin + (k + 1/2) spacing`` (k integer per axis, the lattice of
    :func:`taisph.geometry.lattice` for origin 0) inside the closed surface `mesh`,
    in lattice order (x slowest). With `depth`, only those within `depth` of the
    surface: the layers of dummy-wall particles inside a solid (depth = layers x dx).

    Algorithm: columns of the lattice along the last axis (z in 3D, y in 2D) are
    cast as rays against the cells (scan conversion, as in solid voxelisation:
    Nooruddin & Turk 2003, IEEE TVCG 9:191; Schwarz & Seidel 2010, ACM TOG 29:179).
    Each cell meets the columns inside its projection at one height and adds its
    orientation (+1 where the outward normal points along the column, -1 against)
    to the winding number of every lattice point below; points with a nonzero
    winding number are inside. A column through an edge or vertex of the projection
    is decided as if shifted by (eps, eps^2) (simulation of simplicity; Edelsbrunner
    & Muecke 1990, ACM TOG 9:66), so it crosses a watertight surface exactly once
    per sheet. 2D: segments, columns taken half-open at the segment's ends.
    Cost: O(points in the bounding box + columns crossed); the depth selection adds
    O(cells x lattice points within depth of each).
    """
    spacing = _positive(spacing, "spacing")
    surface = load_surface(mesh, dim)
    d = surface.dim
    origin = np.zeros(d) if origin is None else np.asarray(origin, float).reshape(d)
    lo, hi = surface.bounds
    kmin = np.ceil((lo - origin) / spacing - 0.5).astype(np.int64)
    kmax = np.floor((hi - origin) / spacing - 0.5).astype(np.int64)
    shape = tuple(int(v) for v in kmax - kmin + 1)
    if min(shape) <= 0:
        return np.zeros((0, d))
    winding = _column_winding(surface.corners, spacing, origin, kmin, shape)
    index = np.argwhere(winding != 0)
    points = origin + (index + kmin + 0.5) * spacing
    if depth is not None:
        depth = _positive(depth, "depth")
        points = points[_within(surface.corners, points, index, shape, depth, spacing, origin, kmin)]
    return points


def _positive(value, what):
    value = float(value)
    if not (np.isfinite(value) and value > 0):
        raise ValueError(f"{what} must be a positive number, got {value!r}")
    return value


def _divisions(length, spacing):
    return np.maximum(1, np.ceil(length / spacing - 1e-9)).astype(np.int64)


def _column_winding(corners, h, origin, kmin, shape) -> np.ndarray:
    """Winding number of every lattice point (array of `shape`), from the crossings
    of the columns (along the last axis) with the cells."""
    d = corners.shape[2]
    nz = shape[-1]
    n_columns = int(np.prod(shape[:-1]))
    flat = corners[..., :-1]  # the cells projected across the columns
    if d == 3:
        x, y = flat[..., 0], flat[..., 1]
        area2 = (x[:, 1] - x[:, 0]) * (y[:, 2] - y[:, 0]) - (x[:, 2] - x[:, 0]) * (y[:, 1] - y[:, 0])
        orientation = np.sign(area2)
        lo_cols = np.ceil((flat.min(axis=1) - origin[:-1]) / h - 0.5).astype(np.int64)
        hi_cols = np.floor((flat.max(axis=1) - origin[:-1]) / h - 0.5).astype(np.int64)
    else:
        x = flat[..., 0]
        orientation = -np.sign(x[:, 1] - x[:, 0])  # a segment running -x is a top (for a CCW outline)
        lo_cols = np.ceil((x.min(axis=1, keepdims=True) - origin[0]) / h - 0.5).astype(np.int64)
        hi_cols = np.ceil((x.max(axis=1, keepdims=True) - origin[0]) / h - 0.5).astype(np.int64) - 1  # half-open
    sizes = np.where(orientation[:, None] != 0, np.maximum(hi_cols - lo_cols + 1, 0), 0)
    jumps = np.zeros(n_columns * (nz + 1))
    for cell, col in _cell_boxes(lo_cols, sizes):
        p = origin[:-1] + (col + 0.5) * h
        if d == 3:
            hit, height = _triangle_hits(corners[cell], p, orientation[cell])
        else:
            a, b = corners[cell, 0], corners[cell, 1]
            hit = np.ones(len(cell), bool)
            height = a[:, 1] + (p[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1]) / (b[:, 0] - a[:, 0])
        col, height, sign = col[hit] - kmin[:-1], height[hit], orientation[cell][hit]
        column = np.ravel_multi_index(tuple(col.T), shape[:-1]) if d == 3 else col[:, 0]
        below = np.clip(np.ceil((height - origin[-1]) / h - 0.5).astype(np.int64) - kmin[-1], 0, nz)
        size = len(jumps)
        jumps += np.bincount(column * (nz + 1), weights=sign, minlength=size)  # +s for the points below
        jumps -= np.bincount(column * (nz + 1) + below, weights=sign, minlength=size)
    winding = np.cumsum(jumps.reshape(n_columns, nz + 1), axis=1)[:, :nz]
    return np.rint(winding).astype(np.int32).reshape(shape)


def _triangle_hits(tri, p, orientation):
    """For triangle/column pairs: does the column (x, y) = p cross the triangle
    (edge functions, decided on ties by the (eps, eps^2) shift), and at which z."""
    inside = np.ones(len(p), bool)
    edge_values = []
    for u, v in ((1, 2), (2, 0), (0, 1)):  # the edge opposite vertex 0, 1, 2
        a, b = tri[:, u, :2], tri[:, v, :2]
        swap = (a[:, 0] > b[:, 0]) | ((a[:, 0] == b[:, 0]) & (a[:, 1] > b[:, 1]))
        ca = np.where(swap[:, None], b, a)  # the same endpoint first for both triangles of an edge:
        cb = np.where(swap[:, None], a, b)  # the same rounding, so a column is never on both or neither side
        e = (cb[:, 0] - ca[:, 0]) * (p[:, 1] - ca[:, 1]) - (cb[:, 1] - ca[:, 1]) * (p[:, 0] - ca[:, 0])
        tie = np.where(ca[:, 1] != cb[:, 1], np.sign(ca[:, 1] - cb[:, 1]), 1.0)
        side = np.where(e != 0, np.sign(e), tie)
        inside &= np.where(swap, -side, side) == orientation
        edge_values.append(np.where(swap, -e, e))
    w = np.stack(edge_values, axis=1)  # barycentric weights times twice the projected area
    total = w.sum(axis=1)
    z = np.einsum("ij,ij->i", w, tri[:, :, 2]) / np.where(total != 0, total, 1.0)
    return inside, z


def _within(corners, points, index, shape, depth, h, origin, kmin) -> np.ndarray:
    """Mask of `points` (at lattice `index`) within `depth` of any cell: each cell
    is tested against the lattice points in its bounding box grown by `depth`."""
    d = corners.shape[2]
    lookup = np.full(shape, -1, np.int64)
    lookup[tuple(index.T)] = np.arange(len(index))
    lo = np.maximum(np.ceil((corners.min(axis=1) - depth - origin) / h - 0.5).astype(np.int64) - kmin, 0)
    hi = np.minimum(np.floor((corners.max(axis=1) + depth - origin) / h - 0.5).astype(np.int64) - kmin,
                    np.array(shape) - 1)
    sizes = np.maximum(hi - lo + 1, 0)
    near = np.zeros(len(points), bool)
    if d == 3:
        normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        length = np.linalg.norm(normals, axis=1, keepdims=True)
        normals = np.where(length > 0, normals / np.where(length > 0, length, 1.0), 0.0)
    for cell, at in _cell_boxes(lo, sizes):
        which = lookup[tuple(at.T)]
        keep = (which >= 0) & ~near[np.maximum(which, 0)]
        which, cell = which[keep], cell[keep]
        if d == 3:  # farther than depth from the cell's plane: farther from the cell
            keep = np.abs(np.einsum("ij,ij->i", points[which] - corners[cell, 0], normals[cell])) <= depth
            which, cell = which[keep], cell[keep]
        near[which[pair_distances(points[which], corners[cell]) <= depth]] = True
    return near


def _cell_boxes(lo, sizes):
    """Yield ``(cell, index)`` pairs in chunks of at most PAIRS_PER_CHUNK: for each cell
    k, the lattice indices of its box ``lo[k] + [0, sizes[k])`` (last axis fastest)."""
    counts = np.prod(sizes, axis=1)
    ends = np.cumsum(counts)
    first = 0
    while first < len(counts):
        last = max(first + 1, int(np.searchsorted(ends, (ends[first - 1] if first else 0) + PAIRS_PER_CHUNK)))
        cells = np.arange(first, min(last, len(counts)))
        first = cells[-1] + 1
        cell = np.repeat(cells, counts[cells])
        if len(cell) == 0:
            continue
        local = np.arange(len(cell)) - np.repeat(np.cumsum(counts[cells]) - counts[cells], counts[cells])
        index = np.empty((len(cell), sizes.shape[1]), np.int64)
        for axis in range(sizes.shape[1] - 1, -1, -1):
            index[:, axis] = lo[cell, axis] + local % sizes[cell, axis]
            local //= sizes[cell, axis]
        yield cell, index
