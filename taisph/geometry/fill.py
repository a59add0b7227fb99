"""Particles from closed surfaces: points on them and lattice points inside them.

``surface_points(mesh, spacing)``: points on the surface, 1/spacing^2 per area
(1/spacing per length in 2D) whatever its triangles (for Lennard-Jones walls).
``volume_points(mesh, spacing)``: the lattice points inside (fluid blocks), or with
`depth` only those within `depth` of the surface (the layers of dummy-wall particles a
solid needs). `mesh` is anything
:func:`taisph.geometry.mesh.load_surface` takes: a file name (STL, OBJ, PLY, VTK, VTU, ...),
a meshio mesh, ``(vertices, cells)`` or a 2D polygon; an open, inconsistently
oriented or empty mesh is refused with its name and the problem.

Both are vectorised numpy, linear in the number of points made (timings in
docs/scenes.md). A solid's dummy-wall layers come from ``volume_points`` (lattice
points, so their density is the lattice's whatever the triangles); ``surface_points``
samples the surface itself.
"""

from __future__ import annotations

import numpy as np

from .mesh import PAIRS_PER_CHUNK, load_surface, pair_distances


def surface_points(mesh, spacing: float, dim: int | None = None) -> np.ndarray:
    """Points on the closed surface `mesh` as many per area as the lattice of
    `spacing` has, whatever the triangles: 1/spacing^2 per area in 3D, 1/spacing per
    length in 2D; no two closer than MIN_DISTANCE_3D x spacing (3D) or
    MIN_DISTANCE_2D x spacing (2D). For Lennard-Jones walls (spacing dx/2).

    3D: Poisson-disk sampling by dart throwing from a pool of candidates, made
    deterministic. The candidates, in order of priority: (1) the corners of the
    sharp edges (an edge is sharp where its two triangles' normals differ by more
    than SHARP_ANGLE degrees; a corner is a vertex on other than two of them),
    (2) the sharp edges' other vertices and the edges divided into
    ceil(length / spacing) equal parts, (3) CANDIDATES_PER_AREA / spacing^2 points
    per area drawn uniformly on the surface (a triangle with probability
    proportional to its area, then a uniform point in it; a generator of fixed
    SEED), in random order. A candidate is kept unless a kept point lies closer
    than the minimum distance (3D Euclidean distance, across triangles and edges:
    random sequential adsorption). Over the faces, the number kept per area depends
    only on the candidates' density and the minimum distance, both per spacing, so
    not on the triangles: 16 candidates per spacing^2 with a minimum distance of
    0.78 spacing keep 1/spacing^2 (random sequential adsorption's jamming density is
    0.70 / distance^2 = 1.15 / spacing^2; Feder 1980, J. Theor. Biol. 87:237). The
    sharp edges come first so that a box keeps its edges and corners. The test is
    vectorised on a grid of cells of the minimum distance: cells of one parity
    class (index mod 2 along each axis) are never closer than that to each other,
    so the t-th candidates of all of them are decided at once (the parallel
    Poisson-disk sampling of Wei 2008, ACM TOG 27:20).

    2D: each loop of the outline divided by arc length between its corners
    (vertices where it turns by more than SHARP_ANGLE degrees; a loop without any
    from its first vertex): a stretch of length L into ceil(L / spacing) equal
    parts, so that consecutive points are at most `spacing` apart along the
    outline; then thinned by the minimum-distance rule (corners first), which only
    acts at acute corners and stretches shorter than spacing.

    The number of points per area does not depend on the triangles, slivers included
    (:func:`taisph.geometry.mesh.sliver_box`; tests/test_mesh.py holds it within
    +-15 % of 1/spacing^2; the figures, against the former sampler's, are in
    docs/scenes.md). Every point of the surface lies within about one spacing of a
    point, and surfaces closer to each other than the minimum distance (a plate
    thinner than that) share their points. Every point lies on a cell, up to
    round-off. Deterministic: the same mesh and spacing give the same points in the
    same order. Cost: 16 candidates tested for each point kept (docs/scenes.md).
    """
    spacing = _positive(spacing, "spacing")
    surface = load_surface(mesh, dim)
    if surface.dim == 2:
        return _outline_points(surface, spacing)
    return _sampled_surface(surface, spacing)


MIN_DISTANCE_3D = 0.78  # x spacing: no two points of surface_points closer (3D)
MIN_DISTANCE_2D = 0.5   # x spacing (2D)
CANDIDATES_PER_AREA = 16.0  # per spacing^2: the dart-throwing pool (with MIN_DISTANCE_3D, 1/spacing^2 kept)
SHARP_ANGLE = 30.0  # degrees between two triangles' normals (2D: turn of the outline) that make an edge (corner)
SEED = 24  # of the candidates' generator: the points are a function of the mesh and spacing only


def _sampled_surface(surface, spacing):
    vertices, cells = surface.vertices, surface.cells
    corners = surface.corners
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    areas = 0.5 * np.linalg.norm(normals, axis=1)
    normals = normals / np.where(areas > 0, 2.0 * areas, 1.0)[:, None]
    directed = np.concatenate([cells[:, [0, 1]], cells[:, [1, 2]], cells[:, [2, 0]]])
    owner = np.tile(np.arange(len(cells)), 3)
    edges, inverse = np.unique(np.sort(directed, axis=1), axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    order = np.argsort(inverse, kind="stable")  # a closed surface: each edge exactly twice
    first, second = owner[order[0::2]], owner[order[1::2]]
    sharp = np.einsum("ij,ij->i", normals[first], normals[second]) < np.cos(np.radians(SHARP_ANGLE))
    sharp_edges = edges[sharp]
    degree = np.bincount(sharp_edges.reshape(-1), minlength=len(vertices))
    corner_points = vertices[(degree > 0) & (degree != 2)]
    ends = vertices[(degree == 2)]
    a, b = vertices[sharp_edges[:, 0]], vertices[sharp_edges[:, 1]]
    edge_points = np.concatenate([ends, _divided(a, b, spacing)])
    total = float(areas.sum())
    rng = np.random.default_rng(SEED)
    m = max(1, int(np.ceil(CANDIDATES_PER_AREA * total / spacing**2)))
    where = rng.random(m) * total  # independent of the triangles: a Poisson process on the surface
    tri = np.minimum(np.searchsorted(np.cumsum(areas), where, side="right"), len(cells) - 1)
    u, v = rng.random(m), rng.random(m)
    su = np.sqrt(u)
    weights = np.column_stack([1.0 - su, su * (1.0 - v), su * v])  # uniform on a triangle
    face_points = np.einsum("ik,ikd->id", weights, corners[tri])[rng.permutation(m)]
    return _thinned([corner_points, edge_points, face_points], MIN_DISTANCE_3D * spacing)


def _divided(a, b, spacing):
    """The inner points of the segments a -> b, each divided into ceil(length / spacing) equal parts."""
    n = _divisions(np.linalg.norm(b - a, axis=1), spacing)
    edge = np.repeat(np.arange(len(a)), n - 1)
    k = np.arange(len(edge)) - np.repeat(np.cumsum(n - 1) - (n - 1), n - 1) + 1
    t = (k / n[edge])[:, None]
    return a[edge] + t * (b[edge] - a[edge])


def _outline_points(surface, spacing):
    vertices, cells = surface.vertices, surface.cells
    following = np.full(len(vertices), -1, np.int64)
    following[cells[:, 0]] = cells[:, 1]
    used = np.zeros(len(vertices), bool)
    corners, others = [], []
    cos_sharp = np.cos(np.radians(SHARP_ANGLE))
    for start in np.unique(cells[:, 0]):
        if used[start]:
            continue
        loop = [start]
        used[start] = True
        while following[loop[-1]] != start:
            loop.append(following[loop[-1]])
            used[loop[-1]] = True
        points = vertices[loop]
        out = np.roll(points, -1, axis=0) - points
        into = points - np.roll(points, 1, axis=0)
        cos_turn = np.einsum("ij,ij->i", out, into) / (np.linalg.norm(out, axis=1) * np.linalg.norm(into, axis=1))
        sharp = np.flatnonzero(cos_turn < cos_sharp)
        first = sharp[0] if len(sharp) else 0
        points = np.roll(points, -first, axis=0)
        closed = np.concatenate([points, points[:1]])
        arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(closed, axis=0), axis=1))])
        breaks = np.concatenate([(sharp - first) % len(points), [len(points)]]) if len(sharp) else \
            np.array([0, len(points)])
        breaks = np.unique(breaks)
        corners.append(points[breaks[:-1]] if len(sharp) else np.zeros((0, 2)))
        for lo, hi in zip(breaks[:-1], breaks[1:]):
            n = int(_divisions(np.array([arc[hi] - arc[lo]]), spacing)[0])
            at = arc[lo] + (arc[hi] - arc[lo]) * np.arange(0 if not len(sharp) else 1, n) / n
            others.append(np.column_stack([np.interp(at, arc, closed[:, k]) for k in range(2)]))
    return _thinned([np.concatenate(corners), np.concatenate(others)], MIN_DISTANCE_2D * spacing)


def _thinned(groups, distance) -> np.ndarray:
    """The points of `groups` (arrays of candidates, in order of priority; within a
    group, earlier first) kept by dart throwing: a candidate is kept unless a kept
    point lies closer than `distance`.

    Cells of side `distance` hold at most 2^dim kept points (one per half-cell: its
    diagonal is shorter than `distance`). Cells whose indices have the same parity
    along every axis are at least `distance` apart, so the t-th candidates of all
    cells of one parity class are decided at once, each against the kept points of
    its 3^dim neighbour cells; the classes and groups in turn."""
    sizes = [len(g) for g in groups]
    d = groups[-1].shape[1]
    points = np.concatenate([np.asarray(g, float).reshape(-1, d) for g in groups])
    if len(points) == 0:
        return points
    index = np.floor((points - points.min(axis=0)) / distance).astype(np.int64) + 1
    shape = tuple(int(n) for n in index.max(axis=0) + 2)  # a free layer around: neighbour keys stay valid
    key = np.ravel_multi_index(tuple(index.T), shape)
    by_key = np.argsort(key, kind="stable")  # candidates by cell, in priority order within each
    sorted_key = key[by_key]
    first = np.concatenate([[True], sorted_key[1:] != sorted_key[:-1]])
    cell_keys = sorted_key[first]
    n_cells = len(cell_keys)
    cell = np.empty(len(points), np.int64)
    cell[by_key] = np.cumsum(first) - 1
    neighbours = _neighbour_cells(cell_keys, shape)
    parity = sum((axis % 2) << k for k, axis in enumerate(np.unravel_index(cell_keys, shape)))
    batch = (np.repeat(np.arange(len(groups)), sizes) << d) + parity[cell]  # group, then parity class
    order = by_key[np.argsort(batch[by_key].astype(np.int16), kind="stable")]
    bounds = np.searchsorted(batch[order], np.arange(len(groups) << d), side="left").tolist() + [len(order)]
    per_cell = 2**d
    slots = np.empty(((n_cells + 1) * per_cell, d))  # the kept points of each cell (+ an empty cell)
    filled = np.zeros(n_cells + 1, np.int64)
    kept = np.zeros(len(points), bool)
    limit = distance**2 * (1.0 - 1e-12)
    chunk = max(1, PAIRS_PER_CHUNK // 3**d)
    for lo, hi in zip(bounds[:-1], bounds[1:]):
        if lo == hi:
            continue
        mine = order[lo:hi]
        start = np.flatnonzero(np.concatenate([[True], cell[mine[1:]] != cell[mine[:-1]]]))
        count = np.diff(np.append(start, len(mine)))
        owners = cell[mine[start]]
        for t in range(int(count.max())):
            busy = np.flatnonzero(count > t)
            for s in range(0, len(busy), chunk):
                part = busy[s:s + chunk]
                trial, home = mine[start[part] + t], owners[part]
                around = neighbours[home]
                counts = filled[around]
                row, column = np.nonzero(counts)  # (trial, neighbour cell) pairs holding kept points
                k = counts[row, column]
                if len(k):  # every kept point of each trial's neighbour cells, ragged
                    pair = np.repeat(row, k)
                    slot = np.arange(len(pair)) - np.repeat(np.cumsum(k) - k, k)
                    gap = slots[np.repeat(around[row, column] * per_cell, k) + slot] - points[trial][pair]
                    gap = np.einsum("ij,ij->i", gap, gap)
                    free = np.bincount(pair[gap < limit], minlength=len(trial)) == 0
                    trial, home = trial[free], home[free]
                slots[home * per_cell + filled[home]] = points[trial]
                filled[home] += 1
                kept[trial] = True
    return points[kept]


def _neighbour_cells(cell_keys, shape) -> np.ndarray:
    """For each cell (sorted raveled keys of a grid of `shape`), the positions in
    `cell_keys` of its 3^dim neighbours and itself, len(cell_keys) where absent.
    The keys along the last axis are consecutive: one search per row of neighbours."""
    d = len(shape)
    n = len(cell_keys)
    rows = np.stack(np.meshgrid(*([np.arange(-1, 2)] * (d - 1)), indexing="ij"), -1).reshape(-1, d - 1)
    strides = np.array([int(np.prod(shape[k + 1:])) for k in range(d)], np.int64)
    out = np.empty((n, 3 ** d), np.int32)
    padded = np.append(cell_keys, -1)
    for r, offset in enumerate(rows @ strides[:-1]):
        at = np.searchsorted(cell_keys, cell_keys + offset - 1)  # sorted queries
        for j in range(3):
            wanted = cell_keys + offset - 1 + j
            here = padded[at] == wanted
            out[:, 3 * r + j] = np.where(here, at, n)
            at = at + here
    return out


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
    if depth is not None and len(points):  # (no point inside, e.g. thinner than a float's spacing: none near)
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
