"""Where a probe's point lies among a scene's walls at the start (plain numpy on the host;
:func:`taisph.probes.check_placement` refuses a probe inside a wall with it, before
anything runs).

The walls' *material* is the union of the cubes (squares in 2D) of side dx centred on the
fixed wall particles (a body's particles, which move, are left out): each particle's share
of the wall. Three measures:

- :func:`material_fraction`: the share of a point's kernel support the material fills,
  weighted by the kernel, int W(x - y) [y in the material] dy: about 1 deep in a wall, 1/2
  on a flat wall's face, 3/4 in a 2D corner, 7/8 in a 3D one. The fluid, however it flows,
  fills at most the rest, so a point where the walls fill more than 1 - f can never read
  a fluid fraction f. (Measured on the material, not as sum V_w W over the wall particles:
  walls of particles closer than dx, as the seed's, would count double.)
- :func:`fluid_room`: whether fluid could come within 1.25 dx of the point: some point that
  near lies outside the material and a particle spacing inside the domain (along its
  non-periodic axes). A point deeper in a wall reads at most the tail of the kernel; the
  outer layers of a tank's wall, whose material touches only the thin space between the
  tank and the domain's edge, are such points.
- :func:`enclosed`: the point lies in a hollow of the walls no fluid can reach (inside a
  cylinder made of rings of wall particles).
"""

from __future__ import annotations

import numpy as np

from ..engine.layout import WALL
from ..engine.smoothing import make

TOLERANCE = 1e-9  # relative: round-off in the distances to wall particles


def fixed_walls(scene) -> np.ndarray:
    """A mask of `scene`'s wall particles that do not belong to a body."""
    mask = np.asarray(scene.kind) == WALL
    for body in getattr(scene, "bodies", None) or ():
        mask[np.asarray(body.ids, np.int64)] = False
    return mask


def _walls_near(scene, point, reach: float) -> np.ndarray:
    """The positions of the fixed wall particles whose cubes come within `reach` of `point`."""
    walls = np.asarray(scene.position, float)[fixed_walls(scene)]
    return walls[np.all(np.abs(walls - point) <= reach + 0.5 * scene.dx, axis=1)]


def material_fraction(scene, point, per_dx: int = 4) -> float:
    """The kernel-weighted share of `point`'s kernel support the walls' material fills,
    by the midpoint rule on a lattice of `per_dx` points per dx (exact for a flat face,
    within about 1 % elsewhere)."""
    point = np.asarray(point, float)
    kernel, h, dx, dim = make(scene.kernel, scene.dim), float(scene.smoothing_length), float(scene.dx), scene.dim
    reach = kernel.support * h
    walls = _walls_near(scene, point, reach)
    if len(walls) == 0:
        return 0.0
    step = dx / per_dx
    n = int(np.ceil(reach / step))
    ticks = (np.arange(-n, n) + 0.5) * step
    offsets = np.stack(np.meshgrid(*[ticks] * dim, indexing="ij"), -1).reshape(-1, dim)
    weight = kernel.f_numpy(np.linalg.norm(offsets, axis=1) / h)
    offsets, weight = offsets[weight > 0], weight[weight > 0]
    inside = np.zeros(len(offsets), bool)
    for start in range(0, len(walls), 256):  # (samples x walls) in slices of walls
        gap = np.max(np.abs((point + offsets)[:, None, :] - walls[None, start : start + 256, :]), axis=2)
        inside |= (gap < 0.5 * dx).any(axis=1)
    return float((weight * inside).sum() / weight.sum())


ROOM = 1.25  # dx: how near a fluid particle must be able to sit (fluid_room)


def fluid_room(scene, point, reach: float = ROOM, per_dx: int = 8) -> bool:
    """Whether fluid could come within `reach` dx of `point`: some point of a lattice of
    `per_dx` points per dx within that distance lies outside the walls' material (farther
    than dx/2 from every fixed wall particle in the max norm) and at least dx inside the
    domain along its non-periodic axes."""
    point = np.asarray(point, float)
    dx, dim = float(scene.dx), scene.dim
    step = dx / per_dx
    n = int(np.ceil(reach * dx / step))
    ticks = (np.arange(-n, n) + 0.5) * step
    offsets = np.stack(np.meshgrid(*[ticks] * dim, indexing="ij"), -1).reshape(-1, dim)
    y = point + offsets[np.linalg.norm(offsets, axis=1) <= reach * dx]
    lo, hi = (np.asarray(v, float) for v in scene.domain)
    margin = np.where(np.asarray(scene.periodic, bool), -np.inf, dx)
    y = y[np.all((y >= lo + margin) & (y <= hi - margin), axis=1)]
    walls = _walls_near(scene, point, reach * dx)
    for start in range(0, len(walls), 256):
        if len(y) == 0:
            break
        gap = np.max(np.abs(y[:, None, :] - walls[None, start : start + 256, :]), axis=2)
        y = y[gap.min(axis=1) > 0.5 * dx * (1 + TOLERANCE)]
    return len(y) > 0


WINDOW = {1: 32, 2: 32, 3: 16}  # cells (of side dx) each way from a point that enclosed() looks at


def enclosed(scene, point, window: int | None = None) -> bool:
    """Whether `point` lies in a hollow of the walls that no fluid can reach: on a grid of
    cells of side dx centred on it, a flood from its cell through the cells that hold no
    fixed wall particle (a cell holding a fluid particle always lets it through) reaches
    neither a cell holding a particle of another kind (fluid, or a body's: it moves) nor the
    edge of the ``2 window + 1`` cells across it looks at. False where its own cell holds a
    wall particle, or in open air. Walls of particles at most dx apart leave no gap between
    their cells."""
    dx, dim = float(scene.dx), scene.dim
    window = WINDOW[dim] if window is None else window
    point = np.asarray(point, float).reshape(dim)
    origin = point - (window + 0.5) * dx
    cells = np.floor((np.asarray(scene.position, float) - origin) / dx).astype(np.int64)
    inside = np.all((cells >= 0) & (cells <= 2 * window), axis=1)
    walls = fixed_walls(scene)
    shape = (2 * window + 1,) * dim
    blocked, source = np.zeros(shape, bool), np.zeros(shape, bool)
    blocked[tuple(cells[inside & walls].T)] = True
    source[tuple(cells[inside & ~walls].T)] = True
    passable = ~blocked | source
    start = (window,) * dim
    if not passable[start]:
        return False
    edge = np.ones(shape, bool)
    edge[(slice(1, -1),) * dim] = False
    reached = np.zeros(shape, bool)
    reached[start] = True
    while True:
        if (reached & (source | edge)).any():
            return False
        grown = reached.copy()
        for axis in range(dim):  # the cells that share a face with a reached one
            lo, hi = [slice(None)] * dim, [slice(None)] * dim
            lo[axis], hi[axis] = slice(1, None), slice(None, -1)
            grown[tuple(lo)] |= reached[tuple(hi)]
            grown[tuple(hi)] |= reached[tuple(lo)]
        grown &= passable
        if np.array_equal(grown, reached):
            return True
        reached = grown


def nearest_wall(scene, point) -> int:
    """The index of the fixed wall particle nearest to `point` (-1 if there is none)."""
    ids = np.flatnonzero(fixed_walls(scene))
    if len(ids) == 0:
        return -1
    r = np.linalg.norm(np.asarray(scene.position, float)[ids] - np.asarray(point, float), axis=1)
    return int(ids[np.argmin(r)])
