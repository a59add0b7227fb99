"""Bodies of a scene: groups of wall particles that move as one, either on a prescribed
trajectory (a wave maker, a gate) or floating, pushed by the fluid
(:mod:`taisph.terms.rigid_bodies` moves them; docs/bodies.md).

:meth:`taisph.Scene.add_body` calls :func:`add`, which checks the body against the scene,
computes its mass properties, tabulates a prescribed trajectory and registers the body's
term. Everything refused is refused here, before anything is built, naming the body,
the key and the value.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..engine.layout import FLUID, WALL
from ..messages import InputError

MOTIONS = ("prescribed", "floating")
FIXABLE = {2: ("x", "y", "rotation"), 3: ("x", "y", "z", "rx", "ry", "rz", "rotation")}
TABLE_DT = 1e-3  # s: a prescribed trajectory's sampling (interpolation error (omega dt)^2/8 ~ 2e-5 at T = 1 s)
MAX_SAMPLES = 14000  # per body: the table's length (the field holds rigid_bodies.CAPACITY numbers)


@dataclass
class Body:
    """One body (see :meth:`taisph.Scene.add_body`). ``ids``: its particles (scene
    indices); ``centre``: the reference point (centre of mass of a floating body, pivot of
    a prescribed one); ``inertia``: about the centre (2D: a number; 3D: 3 x 3, body frame);
    ``table``: a prescribed body's (samples, 3 (dim + 1)) table of offset, angle, their
    rates and accelerations, and its time step."""

    name: str
    ids: np.ndarray
    motion: str
    mass: float = 0.0
    centre: np.ndarray = None
    inertia: object = 0.0
    velocity: np.ndarray = None
    angular_velocity: object = 0.0
    fixed: tuple = ()
    table: tuple = None
    axis3: tuple = (0.0, 0.0, 1.0)
    trajectory: str = ""  # what the prescribed motion is, for descriptions
    hinge: tuple = None  # a hinged body's pivot (its centre then), else None
    centre_of_mass: tuple = ()  # a hinged body's centre of mass from its hinge, body frame
    extra: dict = field(default_factory=dict)

    def describe(self) -> str:
        if self.motion == "prescribed":
            return f"body {self.name}: {len(self.ids)} particles, prescribed ({self.trajectory})"
        fixed = f", fixed {', '.join(self.fixed)}" if self.fixed else ""
        if self.hinge is not None:
            fixed = f", hinged at ({', '.join(f'{c:.4g}' for c in self.hinge)})"
        return (f"body {self.name}: {len(self.ids)} particles, floating, mass {self.mass:.6g} kg, centre "
                f"({', '.join(f'{c:.4g}' for c in self.centre)}){fixed}")


def _ids(scene, name, particles) -> tuple:
    """(indices, positions) of the particles `particles` names: a slice, indices or a mask of
    walls already added, or (N, dim) positions to add as walls (indices None: added last,
    once everything is checked, so that a refused body leaves the scene as it was)."""
    if isinstance(particles, slice):
        ids = np.arange(scene.n)[particles]
    else:
        arr = np.asarray(particles)
        if arr.dtype == bool:
            if arr.shape != (scene.n,):
                raise InputError(f"body {name!r}: particles: a mask must have one entry per particle ({scene.n}), "
                                 f"got shape {arr.shape}")
            ids = np.flatnonzero(arr)
        elif np.issubdtype(arr.dtype, np.floating) and arr.ndim == 2:
            if arr.shape[1] != scene.dim:
                raise InputError(f"body {name!r}: particles: positions must have {scene.dim} columns, got {arr.shape}")
            if len(arr) == 0:
                raise InputError(f"body {name!r}: particles: the body has no particles")
            if not np.all(np.isfinite(arr)):
                raise InputError(f"body {name!r}: particles: positions must be finite")
            return None, arr
        elif np.issubdtype(arr.dtype, np.integer):
            ids = arr.ravel().astype(np.int64)
        else:
            raise InputError(f"body {name!r}: particles must be a slice, particle indices, a mask or "
                             f"(N, {scene.dim}) positions, got {particles!r:.80}")
    if len(ids) == 0:
        raise InputError(f"body {name!r}: particles: the body has no particles")
    if ids.min() < 0 or ids.max() >= scene.n:
        raise InputError(f"body {name!r}: particles: index {int(ids.max())} is not a particle of the scene "
                         f"({scene.n} particles)")
    if np.any(scene.kind[ids] != WALL):
        raise InputError(f"body {name!r}: particles: {int(np.count_nonzero(scene.kind[ids] != WALL))} of them are "
                         "not wall particles (a body is made of walls: add them with add_walls)")
    ids = np.unique(ids)
    return ids, scene.position[ids]


def _positive(name, key, value) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"body {name!r}: {key} must be a number, got {value!r}") from None
    if not (math.isfinite(v) and v > 0.0):
        raise InputError(f"body {name!r}: {key} must be positive and finite, got {value!r}")
    return v


def _vector(name, key, value, n) -> np.ndarray:
    arr = np.atleast_1d(np.asarray(value, float)) if value is not None else np.zeros(n)
    if arr.shape != (n,) or not np.all(np.isfinite(arr)):
        raise InputError(f"body {name!r}: {key} must be {n} finite number(s), got {value!r}")
    return arr


def _nearest(points, others, reach) -> float:
    """The smallest distance from `points` to `others` (inf beyond `reach` or without any)."""
    if len(others) == 0:
        return math.inf
    lo, hi = points.min(axis=0) - reach, points.max(axis=0) + reach
    near = others[np.all((others >= lo) & (others <= hi), axis=1)]
    best = math.inf
    for a in range(0, len(points), 512):  # blocks of 512 x 4096 pairs: ~50 MB, whatever the sizes
        for b in range(0, len(near), 4096):
            d = np.linalg.norm(points[a:a + 512, None, :] - near[None, b:b + 4096, :], axis=2)
            best = min(best, float(d.min(initial=math.inf)))
    return best


def mass_properties(dim, dx, x, mass, centre=None) -> tuple:
    """(centre, inertia) of `mass` spread evenly over the particles at `x`, each the centre
    of a cell dx^dim: the centre their mean, the inertia the particles' sum plus each
    cell's own (dx^2/6 per unit mass: exact for a body filled on the lattice)."""
    centre = x.mean(axis=0) if centre is None else centre
    r = x - centre
    m = mass / len(x)
    own = m * dx**2 / 6.0
    if dim == 2:
        return centre, float(m * np.sum(r * r) + own * len(x))
    inertia = m * (np.sum(r * r) * np.eye(3) - r.T @ r) + own * len(x) * np.eye(3)
    return centre, inertia


def _hinge(body, name, d, hinge, axis) -> None:
    """Make the floating `body` turn about `hinge` (a point; in 3D about the coordinate axis
    `axis`): its reference point moves to the hinge, its inertia with it (parallel axes:
    I_p = I_c + M (|r|^2 E - r r^T), r the centre of mass from the hinge), its translations
    and other rotations are held, and the centre of mass is kept for gravity's torque."""
    pivot = _vector(name, "hinge", hinge, d)
    if "rotation" in body.fixed:
        raise InputError(f"body {name!r}: a hinged body turns about its hinge: fixed must not hold its rotation")
    held = ("x", "y")
    if d == 3:
        along = np.flatnonzero(np.abs(axis) > 1e-12)
        if len(along) != 1:
            raise InputError(f"body {name!r}: axis {np.round(axis, 6).tolist()}: a 3D hinge turns about a "
                             "coordinate axis (x, y or z), give axis = [1, 0, 0], [0, 1, 0] or [0, 0, 1]")
        held = ("x", "y", "z") + tuple(r for k, r in enumerate(("rx", "ry", "rz")) if k != along[0])
        if ("rx", "ry", "rz")[along[0]] in body.fixed:
            raise InputError(f"body {name!r}: fixed holds {('rx', 'ry', 'rz')[along[0]]!r}, the hinge's own axis")
    r = body.centre - pivot
    if d == 2:
        body.inertia = float(body.inertia + body.mass * r @ r)
    else:
        body.inertia = np.asarray(body.inertia, float) + body.mass * (r @ r * np.eye(3) - np.outer(r, r))
    body.fixed = tuple(dict.fromkeys(body.fixed + held))
    body.centre, body.hinge, body.centre_of_mass = pivot, tuple(pivot), tuple(r)


def _table(scene, name, trajectory, axis, until) -> tuple:
    """(table, dt, what): a prescribed trajectory sampled every dt over [0, until]."""
    d = scene.dim
    samples = int(min(MAX_SAMPLES, math.ceil(until / TABLE_DT) + 1))
    samples = max(samples, 3)
    t = np.linspace(0.0, until, samples)
    dt = t[1] - t[0]
    table = np.zeros((samples, 3, d + 1))  # (sample, derivative order, offset + angle)
    if hasattr(trajectory, "position") and hasattr(trajectory, "kind"):  # a wave maker (scene.wave_makers.Motion)
        col = slice(0, d) if trajectory.kind == "translation" else slice(d, d + 1)
        direction = axis if trajectory.kind == "translation" else np.ones(1)
        for k, f in enumerate((trajectory.position, trajectory.velocity, trajectory.acceleration)):
            table[:, k, col] = np.asarray(f(t), float)[:, None] * direction
        what = getattr(trajectory, "description", trajectory.kind)
    else:
        if callable(trajectory):
            try:
                values = np.array([np.asarray(trajectory(float(tk)), float).ravel() for tk in t])
            except Exception as error:
                raise InputError(f"body {name!r}: trajectory({t[0]:g}) failed: {error}") from error
            what = f"function {getattr(trajectory, '__name__', 'trajectory')}(t)"
        else:
            data = np.asarray(trajectory, float)
            if data.ndim != 2 or data.shape[1] != d + 2 or len(data) < 2:
                raise InputError(f"body {name!r}: trajectory: a table needs rows (t, {', '.join('xyz'[:d])}, angle) "
                                 f"with {d + 2} columns and at least 2 rows, got shape {data.shape}")
            back = np.flatnonzero(np.diff(data[:, 0]) <= 0)
            if len(back):
                raise InputError(f"body {name!r}: trajectory: the times must increase; row {back[0] + 2} has "
                                 f"t = {data[back[0] + 1, 0]:g} after t = {data[back[0], 0]:g}")
            values = np.stack([np.interp(t, data[:, 0], data[:, 1 + c]) for c in range(d + 1)], axis=1)
            what = f"table of {len(data)} rows to t = {data[-1, 0]:g} s"
        if values.shape != (samples, d + 1):
            raise InputError(f"body {name!r}: trajectory(t) must return {d + 1} numbers (offset "
                             f"{', '.join('xyz'[:d])} and angle), got {values.shape[1:]}")
        table[:, 0] = values
        table[:, 1] = np.gradient(values, dt, axis=0, edge_order=2)
        table[:, 2] = np.gradient(table[:, 1], dt, axis=0, edge_order=2)
    if not np.all(np.isfinite(table)):
        bad = int(np.flatnonzero(~np.all(np.isfinite(table.reshape(samples, -1)), axis=1))[0])
        raise InputError(f"body {name!r}: trajectory is not finite at t = {t[bad]:g} s")
    return table.reshape(samples, -1), dt, what


def _rotation(d, angle, axis3):
    if d == 2:
        c, s = math.cos(angle), math.sin(angle)
        return np.array([[c, -s], [s, c]])
    k = np.asarray(axis3)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def _check_sweep(scene, body, x):
    """A prescribed body (particles at `x`) must stay inside the domain over its whole trajectory."""
    d = scene.dim
    table, _ = body.table
    r0 = x - body.centre
    lo, hi = scene.domain
    for row in table[:: max(1, len(table) // 500)]:
        x = body.centre + row[:d] + r0 @ _rotation(d, row[d], body.axis3).T
        if np.any(x < lo - 1e-12) or np.any(x > hi + 1e-12):
            raise InputError(f"body {body.name!r}: trajectory takes it out of the domain (offset "
                             f"{np.round(row[:d], 6).tolist()}, angle {row[d]:.4g} rad): a stroke larger than the "
                             f"tank ({lo.tolist()} .. {hi.tolist()})")


def add(scene, name, particles, motion="floating", density=None, mass=None, centre=None, inertia=None,
        velocity=None, angular_velocity=None, fixed=(), trajectory=None, axis=None, until=None,
        hinge=None) -> Body:
    """:meth:`taisph.Scene.add_body`: the body `name` made of the wall particles `particles`
    (a slice or indices of walls already added, e.g. what :meth:`~taisph.Scene.add_walls`
    returned, or (N, dim) positions, added as walls once the body is checked), moving as
    one rigid body (:mod:`taisph.terms.rigid_bodies`); its name becomes a wall group
    (force probes) and it is given to the scene's ``rigid_bodies`` term.

    ``motion="floating"``: pushed by the fluid, gravity and contacts. Give `density`
    (kg/m^3, of the particles' volume N dx^dim) or `mass` (kg; per metre in 2D); `centre`
    (of mass) and `inertia` (2D: a number; 3D: principal moments or a 3 x 3 matrix, body
    frame) default to the particles' (:func:`mass_properties`); `velocity` and
    `angular_velocity` (2D: rad/s; 3D: a vector) at t = 0; `fixed`: degrees of freedom
    held ("x", "y", "z", "rotation"; in 3D also "rx", "ry", "rz"); `hinge`: a point the
    body turns about and stays on (2D: about z; 3D: about `axis`, a coordinate axis,
    default z), e.g. a flap hinged at the bottom or a pendulum: its translations and other
    rotations are held, its inertia moved to the hinge, and gravity turns it about the
    hinge through its centre of mass (:func:`_hinge`).

    ``motion="prescribed"``: `trajectory` is a wave maker (a
    :class:`taisph.scene.wave_makers.Motion`: a translation along `axis`, or a rotation
    about `centre`), a function ``f(t) -> (offset (dim), angle)`` or an (M, dim + 2) table
    of rows (t, offset, angle). The offset moves the body from where it starts, the angle
    (rad) turns it about `centre` (default: the particles' mean; in 3D about `axis`). The
    trajectory is tabulated every :data:`TABLE_DT` up to `until` (default: the scene's
    t_end; velocities and accelerations: a wave maker's exact ones, otherwise differences
    of the table), after which the body stays at its last pose."""
    d = scene.dim
    name = str(name)
    fixed = _check_new(scene, name, motion, fixed)
    ids, x = _ids(scene, name, particles)
    _check_clear(scene, name, ids, x)
    axis = _vector(name, "axis", axis if axis is not None else ([1.0, 0.0] if d == 2 else [0.0, 0.0, 1.0]), d)
    if np.linalg.norm(axis) == 0.0:
        raise InputError(f"body {name!r}: axis must not be zero")
    axis = axis / np.linalg.norm(axis)
    body = Body(name=name, ids=np.arange(len(x)) if ids is None else ids, motion=motion, fixed=fixed,
                velocity=_vector(name, "velocity", velocity, d),
                angular_velocity=(float(_vector(name, "angular_velocity", angular_velocity, 1)[0]) if d == 2
                                  else _vector(name, "angular_velocity", angular_velocity, 3)))
    if motion == "floating":
        _floating(scene, body, x, density, mass, centre, inertia, hinge, axis)
    else:
        if hinge is not None:
            raise InputError(f"body {name!r}: hinge is for a floating body; a prescribed body turns about its "
                             "centre")
        _prescribed(scene, body, x, centre, trajectory, axis, until)
    _register(scene, body, ids, x)
    return body


def _check_new(scene, name, motion, fixed) -> tuple:
    """Refuse a body the scene cannot have (a 1D scene, a name taken, an unknown motion or
    degree of freedom); returns `fixed` as a tuple."""
    d = scene.dim
    if d == 1:
        raise InputError(f"body {name!r}: bodies need a 2D or 3D scene")
    if any(b.name == name for b in scene.bodies):
        raise InputError(f"body {name!r}: the scene has a body of that name already")
    if motion not in MOTIONS:
        raise InputError(f"body {name!r}: motion must be one of {', '.join(MOTIONS)}, got {motion!r}")
    fixed = (fixed,) if isinstance(fixed, str) else tuple(fixed)
    unknown = [f for f in fixed if f not in FIXABLE[d]]
    if unknown:
        raise InputError(f"body {name!r}: fixed: {unknown[0]!r} is not a degree of freedom of a {d}D body "
                         f"({', '.join(FIXABLE[d])})")
    return fixed


def _check_clear(scene, name, ids, x) -> None:
    """Refuse a body (particles `ids` at `x`) whose particles belong to another body, or
    that overlaps the fluid or the other walls at t = 0 (closer than half a spacing)."""
    taken = [b.name for b in scene.bodies if ids is not None and np.intersect1d(b.ids, ids).size]
    if taken:
        raise InputError(f"body {name!r}: particles: some belong to body {taken[0]!r} already")
    gap = _nearest(x, scene.position[scene.kind == FLUID], scene.dx)
    if gap < 0.5 * scene.dx:
        raise InputError(f"body {name!r} overlaps the fluid at t = 0: a fluid particle lies {gap:.3g} m from "
                         f"one of its particles (less than half the spacing {scene.dx:g} m); leave the body's "
                         "volume free of fluid")
    others = scene.kind == WALL
    if ids is not None:
        others[ids] = False
    gap = _nearest(x, scene.position[others], scene.dx)
    if gap < 0.5 * scene.dx:
        raise InputError(f"body {name!r} overlaps the walls at t = 0: a wall particle lies {gap:.3g} m from one "
                         f"of its particles (less than half the spacing {scene.dx:g} m)")


def _floating(scene, body, x, density, mass, centre, inertia, hinge, axis) -> None:
    """A floating body's mass (given, or its density times its particles' volume), centre
    and inertia (given, or its particles', :func:`mass_properties`), and its hinge."""
    name, d = body.name, scene.dim
    if (mass is None) == (density is None):
        raise InputError(f"body {name!r}: give its mass or its density (one of them), got mass={mass!r}, "
                         f"density={density!r}")
    body.mass = (_positive(name, "mass", mass) if mass is not None
                 else _positive(name, "density", density) * len(x) * scene.dx**d)
    c = None if centre is None else _vector(name, "centre", centre, d)
    body.centre, body.inertia = mass_properties(scene.dim, scene.dx, x, body.mass, c)
    if inertia is not None:
        if d == 2:
            body.inertia = _positive(name, "inertia", inertia)
        else:
            arr = np.asarray(inertia, float)
            arr = np.diag(arr) if arr.shape == (3,) else arr
            if arr.shape != (3, 3) or not np.all(np.isfinite(arr)) or np.any(np.linalg.eigvalsh(
                    0.5 * (arr + arr.T)) <= 0):
                raise InputError(f"body {name!r}: inertia must be 3 positive numbers (principal moments) or "
                                 f"a symmetric positive 3 x 3 matrix, got {inertia!r}")
            body.inertia = arr
    if hinge is not None:
        _hinge(body, name, d, hinge, axis)


def _prescribed(scene, body, x, centre, trajectory, axis, until) -> None:
    """A prescribed body's centre (given, or its particles' mean), its trajectory
    tabulated up to `until` (:func:`_table`) and checked to stay in the domain."""
    name, d = body.name, scene.dim
    if trajectory is None:
        raise InputError(f"body {name!r}: a prescribed body needs a trajectory (a wave maker, a function "
                         "of t or a table)")
    body.centre = _vector(name, "centre", centre, d) if centre is not None else x.mean(axis=0)
    body.mass = 1.0
    body.inertia = 1.0 if d == 2 else np.eye(3)
    body.axis3 = tuple(axis) if d == 3 else (0.0, 0.0, 1.0)
    until = scene.t_end if until is None else _positive(name, "until", until)
    table, dt, what = _table(scene, name, trajectory, axis, until)
    body.table, body.trajectory = (table, dt), what
    _check_sweep(scene, body, x)


def _register(scene, body, ids, x) -> None:
    """The checked body joins the scene: its particles (added as walls if given as
    positions), its wall group, its per-particle quantities and the rigid_bodies term."""
    from ..terms.rigid_bodies import RigidBodies

    d = scene.dim
    if ids is None:  # checked: now its particles join the scene
        added = scene.add_walls(x)
        body.ids = np.arange(added.start, added.stop)
    scene.bodies.append(body)
    scene.wall_groups[body.name] = body.ids
    offsets = np.zeros((scene.n, d))
    codes = np.asarray(scene.quantities.get("body", np.zeros(scene.n)), float).copy()
    if "body_offset" in scene.quantities:
        offsets[: len(scene.quantities["body_offset"])] = scene.quantities["body_offset"]
    offsets[body.ids] = x - body.centre
    codes[body.ids] = len(scene.bodies)
    scene.quantities["body_offset"], scene.quantities["body"] = offsets, codes
    term = scene.terms_by_name.get("rigid_bodies")
    if term is None:
        scene.terms.append(RigidBodies(scene.bodies, d))
        term = scene.terms_by_name["rigid_bodies"]
    term.bodies = scene.bodies
    term.refresh()
