"""What a probe is: :class:`Probe` (also what a scene file's ``[[probes]]`` become),
the constructors :func:`pressure`, :func:`elevation`, :func:`force`, :func:`flow`, :func:`body`, the points of a
sensor's face (:func:`face_points`) and the one check that its points lie inside the
scene's domain (:func:`outside`, :func:`check_inside`: the :class:`Probes` writer, the
command line and scene files all refuse with it). Plain Python and numpy."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..messages import InputError

KINDS = ("pressure", "elevation", "force", "flow", "body")
MIN_FLUID_FRACTION = 0.2  # below this phi a pressure probe reads no value (a corner has 1/4; taisph.probes)
FACES = ("pressure", "flow")  # the kinds with points in every dimension (a point or a face)
POINTLESS = ("force", "body")  # the kinds without points (a wall group, a body)
# a body probe's columns (after its name and _): its reference point, orientation (2D: angle in rad;
# 3D: unit quaternion w, x, y, z), velocity, angular velocity (2D: about z) and the fluid's force
BODY_COLUMNS = {2: ("x", "y", "angle", "vx", "vy", "omega", "fx", "fy"),
                3: ("x", "y", "z", "qw", "qx", "qy", "qz", "vx", "vy", "vz", "wx", "wy", "wz", "fx", "fy", "fz")}
UP = 1  # the vertical axis: y, in 2D and 3D
# what each column of probes.csv measures, in the scene's units (SI): kind -> (quantity, unit); a flow's
# unit depends on the dimension (per unit depth in 2D), a body's columns on their ending (BODY_UNITS)
UNITS = {"pressure": ("pressure", "Pa"), "elevation": ("surface elevation", "m"), "force": ("force", "N"),
         "flow": ("flow rate", {1: "m/s", 2: "m^2/s", 3: "m^3/s"})}
BODY_UNITS = {**{c: ("body position", "m") for c in ("x", "y", "z")}, "angle": ("body orientation", "rad"),
              **{c: ("body orientation", "1") for c in ("qw", "qx", "qy", "qz")},
              **{c: ("body velocity", "m/s") for c in ("vx", "vy", "vz")},
              **{c: ("body angular velocity", "rad/s") for c in ("omega", "wx", "wy", "wz")},
              **{c: ("body force", "N") for c in ("fx", "fy", "fz")}}


@dataclass
class Probe:
    """A measurement: ``pressure`` at the point `at` (dim numbers), or averaged over
    the face from `at` to `to` (a sensor's face, :func:`face_points`: in 2D the
    segment; in 3D the axis-aligned rectangle, or segment, with opposite corners `at`
    and `to`), ``elevation``
    (free-surface height) along the vertical line through `at` (x in 2D, (x, z) in
    3D), ``force`` on the wall group `walls` (its name in a scene file, or in Python
    a name the :class:`taisph.probes.Probes` writer is given ids for, or the particle
    ids themselves: a slice, range, boolean mask or integer array), ``flow`` (volume
    flow rate) through the face from `at` to `to` (:func:`flow`), ``body``: the state of
    the body `body` (its name in the scene, :meth:`taisph.Scene.add_body`; default: the
    probe's name), :func:`body`; taken every `every` steps."""

    name: str
    kind: str
    at: tuple | None = None
    walls: object = None
    every: int = 1
    to: tuple | None = None
    body: str | None = None

    @property
    def target(self) -> str:
        """The body a body probe samples: `body`, else its name."""
        return self.name if self.body is None else self.body

    def columns(self, dim: int) -> list:
        """Its columns in probes.csv: the name; ``name_x, name_y(, name_z)`` for a force;
        ``name_x, name_y, name_angle, ...`` for a body (:data:`BODY_COLUMNS`)."""
        if self.kind == "body":
            return [f"{self.name}_{c}" for c in BODY_COLUMNS[dim]]
        return [f"{self.name}_{a}" for a in "xyz"[:dim]] if self.kind == "force" else [self.name]

    def units(self, dim: int) -> list:
        """What each of its columns (:meth:`columns`) measures: ``(column, quantity, unit)``,
        e.g. ``("P1", "pressure", "Pa")``, ``("F_x", "force", "N")``, ``("box_angle",
        "body orientation", "rad")``, ``("Q", "flow rate", "m^2/s")`` (2D: per unit depth)."""
        if self.kind == "body":
            return [(f"{self.name}_{c}", *BODY_UNITS[c]) for c in BODY_COLUMNS[dim]]
        quantity, unit = UNITS[self.kind]
        unit = unit[dim] if isinstance(unit, dict) else unit
        return [(c, quantity, unit) for c in self.columns(dim)]

    def check(self, dim: int):
        """:class:`taisph.messages.InputError` (a ValueError) naming the probe if it is
        malformed for a `dim`-D scene."""
        if not (isinstance(self.name, str) and self.name) or any(c in self.name for c in ',"\n'):
            raise InputError(f"probe name {self.name!r}: expected a non-empty name without commas or quotes")
        if self.kind not in KINDS:
            raise InputError(f"probe {self.name!r}: kind {self.kind!r}; expected one of {', '.join(KINDS)}")
        if not (isinstance(self.every, int) and not isinstance(self.every, bool) and self.every >= 1):
            raise InputError(f"probe {self.name!r}: every = {self.every!r}; expected an integer >= 1 (steps)")
        if self.kind == "force":
            if self.walls is None:
                raise InputError(f"probe {self.name!r}: a force probe needs walls (a wall group)")
            return
        if self.kind == "body":
            if not (isinstance(self.target, str) and self.target):
                raise InputError(f"probe {self.name!r}: body = {self.body!r}; a body probe names a body of the scene")
            if dim not in BODY_COLUMNS:
                raise InputError(f"probe {self.name!r}: bodies need a 2D or 3D scene")
            return
        n = dim if self.kind in FACES else dim - 1
        if self.kind == "flow" and self.to is None:
            raise InputError(f"probe {self.name!r}: a flow probe needs a face: at and to, {dim} numbers each")
        for key in ("at", "to"):
            value = getattr(self, key)
            if key == "to" and (value is None or self.kind not in FACES):
                if value is not None:
                    raise InputError(f"probe {self.name!r}: to = {value!r}; only pressure and flow probes take to")
                continue
            if not (isinstance(value, (tuple, list)) and len(value) == n and all(_finite(v) for v in value)):
                what = "a point" if self.kind == "pressure" else "the horizontal position of its vertical line"
                raise InputError(f"probe {self.name!r}: {key} = {value!r}; a {self.kind} probe in {dim}D takes "
                                 f"{what}, {n} number(s)")
        if self.kind == "flow" and (bad := face_problem(self.at, self.to, dim)):
            raise InputError(f"probe {self.name!r}: at = {self.at!r}, to = {self.to!r}: {bad}")
        if self.to is not None and dim == 3 and all(a != b for a, b in zip(self.at, self.to)):
            raise InputError(f"probe {self.name!r}: at = {self.at!r}, to = {self.to!r}: in 3D a face is a rectangle "
                             "in a coordinate plane (or a segment along an axis) with opposite corners at and to, "
                             "which must share at least one coordinate (the rectangle's plane)")


def face_problem(at, to, dim: int) -> str | None:
    """What is wrong with a flow probe's face from `at` to `to` in a `dim`-D scene, or None."""
    differ = sum(a != b for a, b in zip(at, to))
    if differ == 2 or (dim == 2 and differ == 1):  # 2D: any segment; 3D: a rectangle
        return None
    return "a flow probe's face is " + (
        "a segment of non-zero length" if dim == 2 else
        "a rectangle in a coordinate plane (at and to differ in exactly two coordinates)")


def _finite(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def pressure(name: str, at, every: int = 1, to=None) -> Probe:
    """Pressure at the point `at` (Shepard interpolation of the fluid's pressure), or
    its mean over the face from `at` to `to` (a sensor's face; dry parts count as 0):
    in 2D the segment, in 3D the rectangle in a coordinate plane with opposite corners
    `at` and `to` (they differ in two coordinates), e.g. a 9 cm square sensor on the
    wall x = 3.22 m: ``pressure("P1", at=(3.22, 0.115, 0.455), to=(3.22, 0.205, 0.545))``;
    a segment along an axis if they differ in one (:func:`face_points`)."""
    return Probe(name, "pressure", at=tuple(float(v) for v in at), every=every,
                 to=None if to is None else tuple(float(v) for v in to))


def flow(name: str, at, to, every: int = 1) -> Probe:
    """Volume flow rate through the face from `at` to `to`, Q = integral of u . n over it
    (m^2/s per unit depth in 2D, m^3/s in 3D), u the Shepard interpolation of the fluid's
    velocity at the face's points (:func:`face_points`; dry points count as 0). The normal
    n: in 2D the direction from `at` to `to` turned clockwise (a face drawn upwards counts
    flow along +x); in 3D the +axis of the coordinate the rectangle's corners share (a
    face at x = 1 counts flow along +x)."""
    return Probe(name, "flow", at=tuple(float(v) for v in at), to=tuple(float(v) for v in to), every=every)


def face_normal(at, to) -> tuple:
    """A flow face's unit normal and the measure (length or area) of each of its
    ``len(face_points(at, to, spacing))`` equal parts' whole: (normal, measure)."""
    a, b = np.asarray(at, float), np.asarray(to, float)
    if len(a) == 2:
        t = (b - a) / np.linalg.norm(b - a)
        return np.array([t[1], -t[0]]), float(np.linalg.norm(b - a))
    shared = [k for k in range(3) if a[k] == b[k]][0]
    return np.eye(3)[shared], float(np.prod([abs(b[k] - a[k]) for k in range(3) if k != shared]))


def elevation(name: str, at, every: int = 1) -> Probe:
    """Free-surface height along the vertical line through `at` (x, or (x, z) in 3D)."""
    at = (at,) if isinstance(at, (int, float)) else at
    return Probe(name, "elevation", at=tuple(float(v) for v in at), every=every)


def force(name: str, walls, every: int = 1) -> Probe:
    """Pressure force of the fluid on the wall particles `walls` (ids or a group name)."""
    return Probe(name, "force", walls=walls, every=every)


def body(name: str, body: str | None = None, every: int = 1) -> Probe:
    """The state of the body `body` (default: the body named `name`) of the scene
    (:meth:`taisph.Scene.add_body`): its position, orientation, velocity, angular
    velocity and the fluid's force on it, as ``Simulation.bodies()`` has them after the
    step, in the columns :data:`BODY_COLUMNS` (``box_x, box_y, box_angle, ...``)."""
    return Probe(name, "body", body=body, every=every)


def check_bodies(probes, bodies, source: str | None = None):
    """Refuse (InputError) the first body probe of `probes` whose body is not among the
    names `bodies`: ``[SOURCE: ]probe 'P': no body 'B'; the scene's bodies: a, b``."""
    bodies = list(bodies)
    for p in probes:
        if p.kind == "body" and p.target not in bodies:
            prefix = f"{source}: " if source else ""
            raise InputError(f"{prefix}probe {p.name!r}: no body {p.target!r}; the scene's bodies: "
                             f"{', '.join(bodies) or 'none (Scene.add_body, [[bodies]] in a scene file)'}")


def face_points(at, to, spacing: float) -> np.ndarray:
    """The points a sensor's face from `at` to `to` is sampled at, each standing for an
    equal part of it (the probe reads their mean).

    2D: the segment from `at` to `to` cut into n = ceil(length / spacing) equal parts,
    their midpoints. 3D: `at` and `to` are opposite corners of an axis-aligned box that
    is flat (they share a coordinate, :meth:`Probe.check`): along each axis where they
    differ, n = ceil(extent / spacing) equal parts; the face's points are the centres
    of the cells of that grid: a rectangle (two axes, n1 x n2 points), a segment (one)
    or the point `at` (none). The writer takes spacing = dx / 2."""
    a, b = np.asarray(at, float), np.asarray(to, float)
    if len(a) == 2:
        parts = max(1, math.ceil(np.linalg.norm(b - a) / spacing - 1e-9))
        return a + ((np.arange(parts) + 0.5) / parts)[:, None] * (b - a)
    axes = [k for k in range(len(a)) if a[k] != b[k]]
    if len(axes) == 3:
        raise InputError(f"a face from {tuple(at)} to {tuple(to)}: in 3D its corners must share a coordinate")
    ticks = [(np.arange(n) + 0.5) / n for n in (max(1, math.ceil(abs(b[k] - a[k]) / spacing - 1e-9)) for k in axes)]
    grid = np.stack(np.meshgrid(*ticks, indexing="ij"), -1).reshape(-1, len(axes)) if axes else np.zeros((1, 0))
    points = np.repeat(a[None, :], len(grid), axis=0)
    for column, k in enumerate(axes):
        points[:, k] = a[k] + grid[:, column] * (b[k] - a[k])
    return points


class OutsideDomainError(InputError):
    """A probe's point outside the scene's domain; the message names the probe, the
    point (``at`` or ``to``), the coordinate and the domain's range along it.
    Attributes: ``probe`` (its name), ``key``, ``problem`` (e.g. ``x = 5 is outside
    the domain (-0.16 .. 1.16)``)."""

    def __init__(self, message, probe=None, key=None, problem=None):
        super().__init__(message)
        self.probe, self.key, self.problem = probe, key, problem


def outside(probe: Probe, domain):
    """The first of `probe`'s points (``at``, then ``to``) with a coordinate outside
    the box `domain` = ``(lo, hi)`` (bounds included): ``(key, problem)``, e.g.
    ``("at", "x = 5 is outside the domain (-0.16 .. 1.16)")``; None if all lie inside
    or it has no point (force, body). A pressure point has a coordinate per axis, an
    elevation probe's line the horizontal ones. The one rule for the probes of the
    command line, of scene files and of :class:`taisph.probes.Probes`."""
    if probe.kind in POINTLESS:
        return None
    lo, hi = (np.asarray(v, float).reshape(-1) for v in domain)
    axes = range(len(lo)) if probe.kind in FACES else [a for a in range(len(lo)) if a != UP]
    for key in ("at", "to"):
        for a, v in zip(axes, getattr(probe, key) or ()):
            if not lo[a] <= v <= hi[a]:
                return key, f"{'xyz'[a]} = {v:g} is outside the domain ({lo[a]:g} .. {hi[a]:g})"
    return None


def check_inside(probes, domain, source=None, scene=None, walls=None,
                 min_fluid_fraction: float = MIN_FLUID_FRACTION):
    """Raise :class:`OutsideDomainError` (an InputError, so a ValueError) for the
    first of `probes` with a point outside `domain` (:func:`outside`):
    ``[SOURCE: ]probe 'P': at = (5.0, 5.0): x = 5 is outside the domain (-0.16 .. 1.16)``.
    `source` says where the probes come from (``"--probe"``, a file; or one such text
    per probe, e.g. ``"FILE: probes[2]"``). Call it before anything runs: a point outside
    the domain would only ever read nan. Given the `scene` (its particles), also
    :func:`check_placement` (`walls`: its wall groups, {name: ids}, to name the wall)."""
    for k, p in enumerate(probes):
        bad = outside(p, domain)
        if bad is not None:
            key, problem = bad
            prefix = _prefix(source, k)
            raise OutsideDomainError(f"{prefix}probe {p.name!r}: {key} = {getattr(p, key)!r}: {problem}",
                                     p.name, key, problem)
    if scene is not None:
        check_placement(probes, scene, walls, source, min_fluid_fraction)


def _prefix(source, k: int) -> str:
    """``"SOURCE: "`` for probe `k`: `source` a text for all probes or a list of one per probe."""
    if isinstance(source, (list, tuple)):
        source = source[k] if k < len(source) else None
    return f"{source}: " if source else ""


class InsideWallError(InputError):
    """A probe inside a wall or an obstacle (:func:`check_placement`); the message names the
    probe, its point (or face), the wall and where the probe came from. Attributes:
    ``probe`` (its name), ``wall`` (the wall group's name, or None), ``fraction`` (the
    walls' share of the kernel support at the point)."""

    def __init__(self, message, probe=None, wall=None, fraction=None):
        super().__init__(message)
        self.probe, self.wall, self.fraction = probe, wall, fraction


def check_placement(probes, scene, walls=None, source=None, min_fluid_fraction: float = MIN_FLUID_FRACTION):
    """Refuse (:class:`InsideWallError`) the first pressure or flow probe of `probes` whose
    point (every point of its face) lies inside a wall or an obstacle of `scene` at the
    start, where it would read nan (or no flow) all run. Inside (:mod:`taisph.probes.placement`):

    - the walls' material (the cubes of side dx around their particles) fills at least
      1 - `min_fluid_fraction` / 2 (0.9) of its kernel support (about 1 deep in a wall, 1/2
      on its face, 3/4 in a 2D corner, 7/8 in a 3D one): the fluid, which fills at most
      the rest, could never give it the fluid fraction a reading needs;
    - or no fluid can come within 1.25 dx of it (no point that near lies outside the walls'
      material and a particle spacing inside the domain): the outer layers of a tank's
      wall, whose material touches only the thin space between the tank and the domain's
      edge;
    - or it lies in a hollow of the walls that the fluid cannot reach (inside a cylinder of
      rings of wall particles), less than about 65 dx across (33 dx in 3D).

    A point in empty air (no particle near it), on the fluid's side of a wall or on its
    face (also where the wall lattice does not line up with the face and the point is a
    little inside the first layer) passes. `walls` ({name: particle ids}; default the
    scene's ``wall_groups``) names the wall; `source` as in :func:`check_inside`. Elevation
    probes (a vertical line, which may cross a wall below the water) and force and body
    probes are not checked; a body's particles (which move) do not count as walls."""
    limit = 1.0 - min_fluid_fraction / 2
    groups = {**(getattr(scene, "wall_groups", None) or {}), **(walls or {})}
    for k, p in enumerate(probes):
        if p.kind not in FACES or p.at is None or len(p.at) != scene.dim:
            continue
        points = [p.at] if p.to is None else face_points(p.at, p.to, scene.dx / 2.0)
        found = _inside(scene, points, limit)
        if found is not None:
            why, particle, fraction = found
            name = wall_name(groups, particle, len(scene.kind))
            raise InsideWallError(_inside_message(p, scene, name, particle, why, _prefix(source, k)), p.name, name,
                                  fraction)


def _inside(scene, points, limit: float):
    """``(why, wall particle, walls' share)`` if every one of `points` lies inside the walls
    (:func:`check_placement`'s rules), else None."""
    from .placement import ROOM, enclosed, fluid_room, material_fraction, nearest_wall

    why, least = None, 1.0
    for x in points:
        fraction = material_fraction(scene, x)
        least = min(least, fraction)
        if fraction >= limit:
            reason = f"the walls fill {100 * fraction:.0f} % of its kernel support"
        elif not fluid_room(scene, x):
            reason = f"no fluid can come within {ROOM:g} dx of it"
        elif enclosed(scene, x):
            reason = "in a hollow the walls close off from the fluid"
        else:
            return None
        why = why or reason
    return why, nearest_wall(scene, points[0]), least


def _inside_message(p: Probe, scene, name, particle: int, why: str, prefix: str) -> str:
    """The one line of an :class:`InsideWallError`."""
    where = f"at = {p.at!r}" if p.to is None else f"its face from at = {p.at!r} to to = {p.to!r}"
    if name:
        wall = "the walls" if name == "walls" else f"the wall {name!r}"  # (a case's group of all its walls)
    else:
        wall = "a wall"
        why = f"the wall particle nearest to it at ({', '.join(f'{v:g}' for v in scene.position[particle])}); {why}"
    reads = "no flow" if p.kind == "flow" else "nan"
    return (f"{prefix}probe {p.name!r}: {where} lies inside {wall} ({why}), so it would read {reads} all run; "
            "move it to the fluid's side of the wall (on the wall's face it reads the fluid against it)")


def wall_name(groups: dict, particle: int, n: int) -> str | None:
    """The name of the smallest wall group of `groups` ({name: ids: a slice, range, mask or
    indices of the `n` particles}) holding `particle`, or None."""
    best = None
    for name, ids in groups.items():
        try:
            index = np.arange(n)[ids] if isinstance(ids, (slice, range)) else np.asarray(ids)
            index = np.flatnonzero(index) if index.dtype == bool else index.astype(np.int64).ravel()
        except (IndexError, TypeError, ValueError):
            continue
        if particle in index and (best is None or len(index) < best[1]):
            best = (name, len(index))
    return best[0] if best else None


def parse(text: str, dim: int) -> Probe:
    """A probe from the command line's ``--probe KIND:NAME:WHERE[:EVERY]``:
    ``pressure:P1:3.22,0.16`` (a point), ``elevation:gauge:0.6:10`` (the vertical line at
    x = 0.6, every 10 steps), ``force:F:walls`` (a wall group: ``walls``, all wall
    particles of a case, or a scene file's group name), ``flow:Q:2,0,2,1`` (the face
    from (2, 0) to (2, 1): `at` then `to`), ``body:box:box:10`` (the body ``box``, its
    columns ``box_x``...). InputError (a ValueError) naming the text."""
    parts = text.split(":")
    if len(parts) not in (3, 4) or parts[0] not in KINDS or not parts[1]:
        raise InputError(f"--probe {text}: expected KIND:NAME:WHERE[:EVERY], KIND one of {', '.join(KINDS)} "
                         "(e.g. pressure:P1:3.22,0.16, elevation:gauge:0.6:10, force:F:walls, flow:Q:2,0,2,1, "
                         "body:box:box)")
    kind, name, where = parts[:3]
    every = 1
    if len(parts) == 4:
        try:
            every = int(parts[3])
        except ValueError:
            every = parts[3]
    if kind == "force":
        probe = Probe(name, kind, walls=where, every=every)
    elif kind == "body":
        probe = Probe(name, kind, body=where, every=every)
    else:
        try:
            at = tuple(float(v) for v in where.split(","))
        except ValueError:
            raise InputError(f"--probe {text}: {where!r} is not comma-separated numbers") from None
        if kind == "flow":  # at, then to
            half = len(at) // 2
            probe = Probe(name, kind, at=at[:half], to=at[half:] if len(at) == 2 * half else (), every=every)
        else:
            probe = Probe(name, kind, at=at, every=every)
    try:
        probe.check(dim)
    except ValueError as err:
        raise InputError(f"--probe {text}: {err}") from None
    return probe
