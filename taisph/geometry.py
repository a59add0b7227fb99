"""Wall geometry helpers for cases: particles along segments and polylines (2D),
planes and side walls (3D), and the solid bodies they bound.

All helpers return numpy arrays of points ``(N, dim)``; spacing is the distance
between neighbouring wall particles (taisph's cases use dx/2, see ``dam_break``).
"""

from __future__ import annotations

import numpy as np


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
