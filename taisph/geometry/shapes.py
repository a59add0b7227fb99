"""Geometry helpers for cases: fluid blocks on a lattice, tank walls (a row of
particles or layers of dummy particles), particles along segments and polylines
(2D), planes and side walls (3D), and the solid bodies they bound.

All helpers return numpy arrays of points ``(N, dim)``; spacing is the distance
between neighbouring wall particles (taisph's cases use dx/2, see ``dam_break``).
"""

from __future__ import annotations

import math

import numpy as np


def support_layers(support: float, dx: float) -> int:
    """The rows of particles, dx apart, that fill a kernel support of radius `support`
    (dummy walls, an open boundary's buffer): ceil(support / dx), a round-off below a
    whole number counting as it."""
    return math.ceil(support / dx - 1e-9)


def segment(a, b, spacing, include_end=True) -> np.ndarray:
    """Points from `a` to `b` (any dimension), evenly spaced at most `spacing` apart."""
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    length = float(np.linalg.norm(b - a))
    n = max(1, int(np.ceil(length / spacing - 1e-9)))
    t = np.linspace(0.0, 1.0, n + 1)
    if not include_end:
        t = t[:-1]
    return a + t[:, None] * (b - a)


def polyline(points, spacing, closed=False) -> np.ndarray:
    """Wall particles along the polyline through `points` (each vertex once)."""
    pts = [np.asarray(p, float) for p in points]
    if closed:
        pts.append(pts[0])
    parts = [segment(pts[k], pts[k + 1], spacing, include_end=False) for k in range(len(pts) - 1)]
    if not closed:
        parts.append(pts[-1][None, :])
    return np.concatenate(parts)


def extrude(profile, depth, spacing) -> np.ndarray:
    """3D wall particles: a 2D (x, y) profile of points repeated along z in [0, depth]."""
    profile = np.asarray(profile, float)
    z = segment([0.0], [depth], spacing)[:, 0]
    return np.concatenate([np.column_stack([profile, np.full(len(profile), zk)]) for zk in z])


def side_walls(region, lo, hi, depth, spacing) -> np.ndarray:
    """3D side walls at z = 0 and z = depth: lattice points of spacing `spacing` in the
    (x, y) box [lo, hi] for which ``region(x, y)`` is true (e.g. above the floor)."""
    xs = segment([lo[0]], [hi[0]], spacing)[:, 0]
    ys = segment([lo[1]], [hi[1]], spacing)[:, 0]
    x, y = (m.ravel() for m in np.meshgrid(xs, ys, indexing="ij"))
    keep = region(x, y)
    face = np.column_stack([x[keep], y[keep]])
    return np.concatenate([np.column_stack([face, np.full(len(face), z)]) for z in (0.0, depth)])


def ball(centre, radius, dx) -> np.ndarray:
    """Lattice points (spacing dx, cell-centred on the centre's lattice) inside a
    circle (2D) or sphere (3D) of `radius` around `centre`."""
    centre = np.asarray(centre, float)
    k = int(np.ceil(radius / dx)) + 1
    axis = (np.arange(-k, k) + 0.5) * dx
    mesh = np.stack([m.ravel() for m in np.meshgrid(*[axis] * len(centre), indexing="ij")], axis=1)
    inside = np.linalg.norm(mesh, axis=1) < radius
    return centre + mesh[inside]


def inside_triangle(points, a, b, c, margin=0.0) -> np.ndarray:
    """Mask of 2D points strictly inside triangle abc, at least `margin` from its edges."""
    p = np.asarray(points, float)
    tri = [np.asarray(v, float) for v in (a, b, c)]
    sign = np.sign(_cross(tri[1] - tri[0], tri[2] - tri[0]))
    ok = np.ones(len(p), bool)
    for u, v in ((tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])):
        edge = v - u
        dist = sign * _cross(edge, p - u) / np.linalg.norm(edge)
        ok &= dist > margin
    return ok


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def lattice(lo, hi, dx) -> np.ndarray:
    """Points of a regular lattice with spacing dx filling the box [lo, hi], each at
    the centre of its dx-cell (so boxes side by side tile without overlap)."""
    lo = np.asarray(lo, float)
    hi = np.asarray(hi, float)
    counts = [max(0, int(round((b - a) / dx))) for a, b in zip(lo, hi)]
    axes = [a + dx * (np.arange(k) + 0.5) for a, k in zip(lo, counts)]
    mesh = np.meshgrid(*axes, indexing="ij")
    return np.stack([m.ravel() for m in mesh], axis=1)


def box_walls(lo, hi, spacing, layers=1, vertical_axis=None, open_top=True) -> np.ndarray:
    """Wall particles on the faces of the box [lo, hi], `spacing` apart.

    The face at the top of `vertical_axis` (default: the last axis in 1D/2D, y in 3D
    is passed explicitly by the cases) is left open unless `open_top` is False.
    `layers` > 1 adds layers outside the box, `spacing` apart.
    """
    lo = np.asarray(lo, float)
    hi = np.asarray(hi, float)
    dim = len(lo)
    up = dim - 1 if vertical_axis is None else vertical_axis
    pts = []
    for layer in range(layers):
        a = lo - layer * spacing
        b = hi + layer * spacing
        if open_top:
            b[up] = hi[up]
        counts = [int(round((b[d] - a[d]) / spacing)) for d in range(dim)]
        axes = [np.linspace(a[d], b[d], counts[d] + 1) for d in range(dim)]
        mesh = np.stack([m.ravel() for m in np.meshgrid(*axes, indexing="ij")], axis=1)
        on_face = np.zeros(len(mesh), bool)
        for d in range(dim):
            on_face |= np.isclose(mesh[:, d], a[d])
            if d != up or not open_top:
                on_face |= np.isclose(mesh[:, d], b[d])
        pts.append(mesh[on_face])
    return np.concatenate(pts)


def wall_layers(lo, hi, dx, layers, vertical_axis=None, open_top=True, periodic=None) -> np.ndarray:
    """Wall particles for dummy-particle walls: `layers` layers of lattice points, `dx`
    apart, around the fluid box [lo, hi] (the fluid filling it with :func:`lattice`).

    The particles are cell centres of the same lattice as the fluid's, so the first
    layer sits dx/2 outside each face and the wall continues the fluid lattice
    without a gap. The top face (of `vertical_axis`, default the last axis) is left
    open unless `open_top` is False; the side walls then end at hi. Axes flagged in
    `periodic` get no walls (the box extent there is the period)."""
    lo = np.asarray(lo, float)
    hi = np.asarray(hi, float)
    dim = len(lo)
    up = dim - 1 if vertical_axis is None else vertical_axis
    periodic = (False,) * dim if periodic is None else tuple(bool(p) for p in periodic)
    a = np.where(periodic, lo, lo - layers * dx)
    b = np.where(periodic, hi, hi + layers * dx)
    if open_top and not periodic[up]:
        b[up] = hi[up]
    pts = lattice(a, b, dx)
    inside = np.all((pts > lo) & (pts < hi), axis=1)
    return pts[~inside]


def solid_layers(lo, hi, dx, layers) -> np.ndarray:
    """Wall particles for a solid box obstacle with dummy-particle walls: the lattice
    points (cell centres, spacing dx) of the box [lo, hi] within `layers` cells of its
    faces. The outer layer sits dx/2 inside each face, the next ones dx apart inward,
    so fluid outside the box (on the same lattice) meets the wall without a gap, as
    :func:`wall_layers` around a tank; a box at most 2 `layers` cells thick is filled."""
    lo = np.asarray(lo, float)
    hi = np.asarray(hi, float)
    pts = lattice(lo, hi, dx)
    core = np.all((pts > lo + layers * dx) & (pts < hi - layers * dx), axis=1)
    return pts[~core]


def container_layers(outline, dx, layers) -> np.ndarray:
    """Wall particles for dummy-particle walls (2D) around a container whose walls follow
    the open polyline `outline` (its vertices in order, the fluid on the left going from
    the first to the last, as for a tank drawn from the top of its left wall down, along
    the floor and up the right wall): `layers` layers of points dx apart behind each
    segment, on a lattice of that segment's own direction, so that a sloping wall (an
    incline) is as smooth as a level one (the fluid's lattice would make a staircase).

    Each segment's lattice has rows (k + 1/2) dx behind it (k < layers) and columns dx
    apart centred on it, reaching `layers` dx past its ends where another segment joins
    (the outline's two open ends stop at their vertex). A point is kept where this
    segment is the nearest (the first of equals) and within layers dx; at a joint the
    later segment's points closer than 0.7 dx to the earlier ones' are dropped. Along an
    axis-aligned outline the points are those of :func:`wall_layers` on the same lattice,
    but for the outer corner points of a right-angled corner farther than layers dx from
    it (beyond a kernel's support)."""
    pts = np.asarray(outline, float)
    a, b = pts[:-1], pts[1:]
    length = np.linalg.norm(b - a, axis=1)
    if len(a) < 1 or np.any(length <= 0):
        raise ValueError("container_layers: the outline needs two or more distinct vertices in a row")
    t = (b - a) / length[:, None]
    n = np.column_stack([-t[:, 1], t[:, 0]])  # towards the fluid (its left)
    depth = -(np.arange(layers) + 0.5) * dx
    kept = []
    for k in range(len(a)):
        cols = int(np.ceil(length[k] / dx - 1e-9))
        start = 0.5 * (length[k] - cols * dx)  # columns centred on the segment
        before = layers if k > 0 else 0
        after = layers if k < len(a) - 1 else 0
        s = start + (np.arange(-before, cols + after) + 0.5) * dx
        S, D = (m.ravel() for m in np.meshgrid(s, depth, indexing="ij"))
        cand = a[k] + S[:, None] * t[k] + D[:, None] * n[k]
        dist = np.stack([_segment_distance(cand, a[m], b[m]) for m in range(len(a))], axis=1)
        nearest = np.argmin(dist - 1e-9 * np.arange(len(a)), axis=1)  # ties: the first segment
        cand = cand[(nearest == k) & (dist[:, k] <= layers * dx + 1e-9)]
        if k > 0:  # thin the joint with the segments before
            joint = np.linalg.norm(cand - a[k], axis=1) < (layers + 1) * dx
            earlier = np.concatenate(kept)
            near = earlier[np.linalg.norm(earlier - a[k], axis=1) < (layers + 2) * dx]
            if len(near) and joint.any():
                gap = np.linalg.norm(cand[joint][:, None, :] - near[None, :, :], axis=2).min(axis=1)
                drop = np.zeros(len(cand), bool)
                drop[np.flatnonzero(joint)[gap < 0.7 * dx]] = True
                cand = cand[~drop]
        kept.append(cand)
    return np.concatenate(kept)


def _segment_distance(p, a, b):
    """Distance of points `p` to the segment from `a` to `b`."""
    ab = b - a
    u = np.clip(((p - a) @ ab) / (ab @ ab), 0.0, 1.0)
    return np.linalg.norm(p - (a + u[:, None] * ab), axis=1)
