"""Open boundary zones as a scene describes them: where each is, what it prescribes, the
particles that fill its buffer, and the checks a zone must pass before anything is built.

What the zones do during a step, and why, is in :mod:`taisph.terms.open_boundary`.
"""

import math
import re
from dataclasses import dataclass

import numpy as np

from ..engine.layout import FLUID, WALL
from ..eos import tait
from ..geometry.shapes import support_layers
from ..messages import InputError
from ..terms.open_boundary import (EXTRAPOLATED, FACE_SAMPLES, PRESCRIBED, PROFILES, TIME_SAMPLES, ZONE_ROW,
                                   OpenBoundaries)


@dataclass
class OpenBoundary:
    """One open boundary zone (see the module docstring); made by
    :meth:`taisph.Scene.add_open_boundary`, which also fills its buffer.

    ``face``: (at, to), the segment (2D) or the opposite corners of an axis-aligned
    rectangle (3D). ``normal``: the unit normal pointing into the fluid. ``velocity``:
    None (extrapolated), a number (speed along ``normal``), a vector, an (M, 2) table of
    (t, speed) or a function ``f(points, t)`` of the face's points ((P, dim) array) and
    the time, returning speeds along the normal ((P,)) or vectors ((P, dim)).
    ``profile`` multiplies a number or a table across the face: "uniform" or
    "parabolic" (4 s (1 - s) along each face axis, s from 0 to 1: a channel's or a
    duct's laminar profile, the number its maximum). ``period``: a table or function
    repeats with this period (s); without one it holds its last value. ``pressure``:
    None (extrapolated) or the prescribed pressure (Pa). ``layers``: rows of buffer
    particles (``depth = layers dx``)."""

    name: str
    at: tuple
    to: tuple
    normal: tuple
    layers: int
    velocity: object = None
    profile: str = "uniform"
    pressure: float | None = None
    period: float | None = None
    span: float = 1.0  # the time a function is tabulated over (the scene's t_end, or period)

    @property
    def velocity_mode(self) -> str:
        return EXTRAPOLATED if self.velocity is None else PRESCRIBED

    @property
    def pressure_mode(self) -> str:
        return EXTRAPOLATED if self.pressure is None else PRESCRIBED

    def describe(self) -> str:
        return (f"{self.name}: face {self.at} .. {self.to}, inward normal {self.normal}, {self.layers} layers; "
                f"velocity {self.describe_velocity()}, pressure "
                + ("extrapolated" if self.pressure is None else f"{self.pressure:g} Pa"))

    def describe_velocity(self) -> str:
        v = self.velocity
        if v is None:
            return "extrapolated"
        if callable(v) or isinstance(v, dict):
            return "f(x, t)" + (f" every {self.period:g} s" if self.period else "")
        arr = np.asarray(v, float)
        if arr.ndim == 2:
            return f"table of {len(arr)} (t, u) rows" + (f" every {self.period:g} s" if self.period else "")
        return (f"{self.profile} " if arr.ndim == 0 else "") + f"{v} m/s"

    # --- geometry -------------------------------------------------------------------
    def frame(self, dim: int):
        """(origin, axes, lengths): the face is origin + sum_k s_k lengths[k] axes[k], s_k in [0, 1]."""
        a, b = np.asarray(self.at, float), np.asarray(self.to, float)
        if dim == 2:
            length = float(np.linalg.norm(b - a))
            return a, [(b - a) / length], [length]
        spans = [k for k in range(3) if a[k] != b[k]]
        axes = [np.sign(b[k] - a[k]) * np.eye(3)[k] for k in spans]
        return a, axes, [abs(b[k] - a[k]) for k in spans]

    def face_normal(self, dim: int) -> np.ndarray:
        """A unit normal of the face (either sign)."""
        _, axes, _ = self.frame(dim)
        if dim == 2:
            t = axes[0]
            return np.array([t[1], -t[0]])
        return np.cross(axes[0], axes[1])

    def buffer_points(self, dim: int, dx: float) -> np.ndarray:
        """The lattice filling the zone: ``layers`` rows outside the face, each point at
        the centre of its dx-cell (continuing a fluid lattice that starts dx/2 inside)."""
        origin, axes, lengths = self.frame(dim)
        counts = [round(length / dx) for length in lengths]
        n = np.asarray(self.normal, float)
        grids = np.meshgrid(*[np.arange(c) + 0.5 for c in counts], np.arange(self.layers) + 0.5, indexing="ij")
        coords = [g.ravel() for g in grids]
        points = origin + sum(dx * c[:, None] * axis for c, axis in zip(coords[:-1], axes))
        return points - dx * coords[-1][:, None] * n

    def contains(self, points: np.ndarray, dx: float, dim: int, margin: float = 0.0) -> np.ndarray:
        """Which of `points` lie in the zone (behind the face, within its depth and
        extent), the box grown by `margin` on every side."""
        origin, axes, lengths = self.frame(dim)
        rel = np.asarray(points, float) - origin
        depth = -rel @ np.asarray(self.normal, float)
        inside = (depth > -margin) & (depth < self.layers * dx + margin)
        for axis, length in zip(axes, lengths):
            s = rel @ axis
            inside &= (s > -margin) & (s < length + margin)
        return inside

    # --- the velocity table ---------------------------------------------------------
    def face_samples(self, dim: int):
        """(points, (n_s1, n_s2), s-coordinates): where a profile or function is sampled."""
        origin, axes, lengths = self.frame(dim)
        counts = [FACE_SAMPLES[dim]] * (dim - 1)
        s = [np.linspace(0.0, 1.0, c) for c in counts]
        grids = np.meshgrid(*s, indexing="ij")
        points = origin + sum(g.ravel()[:, None] * length * axis for g, length, axis in zip(grids, lengths, axes))
        return points, (counts + [1])[:2], [g.ravel() for g in grids]

    def table(self, dim: int) -> tuple:
        """The prescribed velocity as a table: (values (n_t, n_s1, n_s2, dim), time step
        of its rows (0 for one row)). Raises :class:`InputError` naming the zone."""
        n = np.asarray(self.normal, float)
        v = self.velocity
        shape_1 = (1, 1)
        if isinstance(v, dict):  # a function's table, stored (taisph.scene.serialize)
            return np.asarray(v["tabulated"], float), float(v["step"])
        if callable(v):
            points, counts, _ = self.face_samples(dim)
            times = np.linspace(0.0, self.span, TIME_SAMPLES)
            rows = []
            for t in times:
                values = np.asarray(v(points.copy(), float(t)), float)
                values = self._as_vectors(values, len(points), dim, n, f"its function at t = {t:g} s")
                rows.append(values.reshape(*counts, dim))
            return np.stack(rows), times[1] - times[0]
        if self.profile == "parabolic":
            _, shape_1, s = self.face_samples(dim)
            shape = np.prod([4.0 * c * (1.0 - c) for c in s], axis=0).reshape(*shape_1)
        else:
            shape = np.ones(shape_1)
        arr = np.asarray(v, float)
        if arr.ndim == 2 and arr.shape[1] == 2 and arr.shape[0] >= 2:  # (t, speed) rows
            t, u = arr[:, 0], arr[:, 1]
            if not np.all(np.diff(t) > 0):
                k = int(np.flatnonzero(np.diff(t) <= 0)[0]) + 1
                raise InputError(f"open boundary {self.name!r}: its velocity table's times must increase; "
                                 f"row {k + 1} has t = {t[k]:g} after {t[k - 1]:g}")
            if t[0] < 0:
                raise InputError(f"open boundary {self.name!r}: its velocity table starts at t = {t[0]:g} s < 0")
            times = np.linspace(0.0, t[-1], TIME_SAMPLES)
            speeds = np.interp(times, t, u)
            return speeds[:, None, None, None] * shape[None, :, :, None] * n, times[1] - times[0]
        vector = self._as_vectors(arr.reshape(1, -1) if arr.ndim == 1 else arr.reshape(1), 1, dim, n, "its velocity")
        return shape[None, :, :, None] * vector.reshape(1, 1, 1, dim), 0.0

    def _as_vectors(self, values, count, dim, n, what):
        if values.shape == (count,):
            values = values[:, None] * n
        elif values.shape != (count, dim):
            raise InputError(f"open boundary {self.name!r}: {what} gives an array of shape {values.shape}; "
                             f"expected speeds ({count},) or vectors ({count}, {dim})")
        bad = np.flatnonzero(~np.all(np.isfinite(values), axis=1))
        if bad.size:
            raise InputError(f"open boundary {self.name!r}: {what} is not finite ({values[bad[0]]})")
        return values


def default_layers(scene) -> int:
    """Rows of buffer particles: enough to fill a kernel support (plus one for the
    particles that have just moved)."""
    return support_layers(scene.support_radius, scene.dx) + 1


# --- the checks of a zone that need no fluid (the scene files' reader makes them too) ---
ZONE_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")  # a zone's name names its parameters (NAME_pressure)


def is_zone_name(name: str) -> bool:
    """Can `name` name a zone: a word of letters, digits and _ (not starting with a digit)?"""
    return ZONE_NAME.fullmatch(name) is not None


def face_sides(at, to, dim: int) -> list | None:
    """The lengths of the sides of the face from corner `at` to corner `to`: in 2D a
    segment (its length), in 3D a rectangle in a coordinate plane (its two sides); None
    if `at` and `to` make no such face (2D: one point; 3D: not exactly two coordinates
    differ)."""
    differ = [a != b for a, b in zip(at, to)]
    if not (any(differ) if dim == 2 else sum(differ) == 2):
        return None
    a, b = np.asarray(at, float), np.asarray(to, float)
    if dim == 2:
        return [float(np.linalg.norm(b - a))]
    return [abs(float(v)) for v in (b - a)[np.array(differ)]]


def whole_spacings(length: float, dx: float) -> bool:
    """Is `length` a whole number (at least 1) of particle spacings `dx`, to a relative 1e-6?
    (A buffer is rows of particles dx apart.)"""
    count = length / dx
    return math.isfinite(count) and round(count) >= 1 and math.isclose(round(count) * dx, length, rel_tol=1e-6)


def perpendicular(normal, at, to, dim: int) -> bool:
    """Is the non-zero vector `normal` perpendicular to the face from `at` to `to`: its
    component along the face (2D: the segment; 3D: either side of the rectangle) at most
    1e-9 of its length (times the face's diagonal, if that is over 1 m)?"""
    n, d = np.asarray(normal, float), np.asarray(to, float) - np.asarray(at, float)
    across = np.abs(n @ d) if dim == 2 else np.abs(n[d != 0]).max()
    return not across > 1e-9 * float(np.linalg.norm(n)) * max(float(np.linalg.norm(d)), 1.0)


def _side_counts(scene, zone: OpenBoundary, normal: np.ndarray, reach: float) -> tuple:
    """(fluid particles within `reach` of the face on the `normal` side, within the
    zone on the other side), counting fluid outside every zone's buffer only."""
    dim, dx = scene.dim, scene.dx
    fluid = scene.kind == FLUID
    zones = scene.quantities.get(ZONE_ROW)
    if zones is not None:
        fluid &= np.asarray(zones) == 0
    x = scene.position[fluid]
    origin, axes, lengths = zone.frame(dim)
    rel = x - origin
    within = np.ones(len(x), bool)
    for axis, length in zip(axes, lengths):
        s = rel @ axis
        within &= (s > 0) & (s < length)
    distance = rel @ normal
    inner = int(np.count_nonzero(within & (distance > 0) & (distance < reach)))
    outer = int(np.count_nonzero(within & (distance < -0.01 * dx) & (distance > -zone.layers * dx)))
    return inner, outer


def _face_density(scene, zone: OpenBoundary, default: float) -> float:
    """The mean density of the fluid within a kernel support inside `zone`'s face."""
    fluid = scene.kind == FLUID
    zones = scene.quantities.get(ZONE_ROW)
    if zones is not None:
        fluid &= np.asarray(zones) == 0
    origin, axes, lengths = zone.frame(scene.dim)
    rel = scene.position[fluid] - origin
    near = (rel @ np.asarray(zone.normal, float) > 0) & (rel @ np.asarray(zone.normal, float) < scene.support_radius)
    for axis, length in zip(axes, lengths):
        near &= (rel @ axis > 0) & (rel @ axis < length)
    return float(scene.density[fluid][near].mean()) if near.any() else default


def zone_problem(scene, zone: OpenBoundary, normal=None) -> str | None:
    """What is wrong with `zone` in `scene`, or None; sets ``zone.normal`` (given, or
    found from the side of the face the fluid is on)."""
    dim, dx = scene.dim, scene.dx
    if not is_zone_name(zone.name):
        return "its name must be a word of letters, digits and _ (it names its parameters, e.g. NAME_pressure)"
    others = [z for z in scene.open_boundaries if z is not zone]
    if any(z.name == zone.name for z in others):
        return "another open boundary has that name"
    if len(zone.at) != dim or len(zone.to) != dim:
        return f"its face's corners at and to need {dim} coordinates each, got {zone.at} and {zone.to}"
    lengths = face_sides(zone.at, zone.to, dim)
    if lengths is None:
        return ("its face is a segment of non-zero length (at != to)" if dim == 2 else
                "its face is a rectangle in a coordinate plane: at and to differ in exactly two coordinates")
    for length in lengths:
        if not whole_spacings(length, dx):
            return f"its face's extent {length:g} m is not a whole number of particle spacings dx = {dx:g} m"
    least = support_layers(scene.support_radius, dx)
    if zone.layers < least:
        return (f"layers = {zone.layers} gives a buffer {zone.layers * dx:g} m deep, less than the kernel support "
                f"{scene.support_radius:g} m: at least {least}")
    if zone.profile not in PROFILES:
        return f"profile {zone.profile!r} is not one of {', '.join(PROFILES)}"
    if zone.period is not None and not (math.isfinite(zone.period) and zone.period > 0):
        return f"period must be a positive time (s), got {zone.period!r}"
    if zone.pressure is not None and not math.isfinite(zone.pressure):
        return f"pressure must be a finite number (Pa), got {zone.pressure!r}"
    face = zone.face_normal(dim)
    reach = scene.support_radius
    if normal is None:
        plus, plus_out = _side_counts(scene, zone, face, reach)
        minus, minus_out = _side_counts(scene, zone, -face, reach)
        if plus and not plus_out:
            normal = face
        elif minus and not minus_out:
            normal = -face
        else:
            return ("its inward normal cannot be found from the fluid (fluid on neither side of the face, or on "
                    "both): give normal=")
    normal = np.asarray(normal, float).ravel()
    if normal.shape != (dim,) or not np.all(np.isfinite(normal)) or not np.linalg.norm(normal) > 0:
        return f"its normal must be a non-zero vector of {dim} numbers, got {tuple(float(v) for v in normal)}"
    normal = normal / np.linalg.norm(normal)
    if not perpendicular(normal, zone.at, zone.to, dim):
        return f"its normal {tuple(float(v) for v in normal)} is not perpendicular to its face"
    zone.normal = tuple(float(v) + 0.0 for v in normal)  # (+ 0.0: no -0.0)
    inner, outer = _side_counts(scene, zone, normal, dx)
    if outer:
        _, opposite = _side_counts(scene, zone, -normal, dx)
        if opposite == 0 and _side_counts(scene, zone, -normal, reach)[0]:
            return f"its normal {zone.normal} points out of the fluid (the fluid is on the other side of the face)"
        return (f"{outer} fluid particles lie inside its buffer zone: the face must be on the boundary of the "
                "fluid region, with no fluid behind it")
    if not inner:
        return (f"no fluid lies within dx = {dx:g} m of its face on the side its normal {zone.normal} points to: "
                "the face must be on the boundary of the fluid region")
    walls = scene.position[scene.kind == WALL]
    inside = zone.contains(walls, dx, dim, margin=-0.25 * dx)
    if inside.any():
        return (f"{int(inside.sum())} wall particles lie inside its buffer zone (e.g. at "
                f"{tuple(float(v) for v in np.round(walls[inside][0], 9))}): walls may border a zone, not cross it")
    points = zone.buffer_points(dim, dx)
    for other in others:
        if other.normal != (0.0,) * dim and other.contains(points, dx, dim, margin=-0.25 * dx).any():
            return f"its buffer zone overlaps that of open boundary {other.name!r}"
    lo, hi = scene.domain
    if zone in scene.open_boundaries and (np.any(points < lo) or np.any(points > hi)):
        return (f"its buffer zone reaches outside the scene's domain {tuple(float(v) for v in lo)} .. "
                f"{tuple(float(v) for v in hi)}")
    return None


def check(scene) -> None:
    """Raise :class:`InputError` naming the first zone of `scene` with a problem."""
    for zone in scene.open_boundaries:
        problem = zone_problem(scene, zone, zone.normal)
        if problem:
            raise InputError(f"scene {scene.name!r}: open boundary {zone.name!r}: {problem}")
        if zone.velocity is not None:
            zone.table(scene.dim)  # a function that gives NaN, a table whose times go back...


def add(scene, name, at, to, normal=None, velocity=None, pressure=None, profile="uniform", period=None,
        layers=None, material=0) -> OpenBoundary:
    """:meth:`taisph.Scene.add_open_boundary` (see there): the zone, checked; its buffer's
    particles; the domain grown to hold them; the scene's open-boundary term updated."""
    d = scene.dim
    at, to = tuple(float(v) for v in np.ravel(at)), tuple(float(v) for v in np.ravel(to))
    layers = default_layers(scene) if layers is None else int(layers)
    zone = OpenBoundary(name=str(name), at=at, to=to, normal=(0.0,) * d, layers=layers, velocity=velocity,
                        profile=profile, pressure=None if pressure is None else float(pressure),
                        period=None if period is None else float(period), span=float(period or scene.t_end))
    problem = zone_problem(scene, zone, normal)  # fills in the normal
    if problem:
        raise InputError(f"scene {scene.name!r}: open boundary {zone.name!r}: {problem}")
    points = zone.buffer_points(d, scene.dx)
    lo, hi = scene.domain  # the domain holds the buffer, with a cell to spare (not along a period)
    periodic = np.asarray(scene.periodic, bool)
    scene.domain = (np.where(periodic, lo, np.minimum(lo, points.min(axis=0) - scene.dx)),
                    np.where(periodic, hi, np.maximum(hi, points.max(axis=0) + scene.dx)))
    m = scene.materials[material]
    if zone.pressure is not None and getattr(m, "c0", None):
        density = tait.density(zone.pressure, m.rho0, m.c0, m.gamma)  # inverse Tait
    else:  # the fluid's next to the face: the particles that enter then fill the space they leave
        density = _face_density(scene, zone, m.rho0)
    velocity0 = None
    if zone.velocity is not None:
        table, _ = zone.table(d)
        velocity0 = table[0].reshape(-1, d).mean(axis=0) if zone.profile == "uniform" or callable(
            zone.velocity) else None
    scene.open_boundaries.append(zone)
    scene.add_particles(points, kind="fluid", material=material, density=density, velocity=velocity0,
                       mass=density * scene.dx**d,  # volume dx^d at the zone's pressure, as it will enter
                       open_zone=np.full(len(points), float(len(scene.open_boundaries))))
    term = scene.terms_by_name.get("open_boundaries")
    if term is None:
        scene.terms.append(OpenBoundaries(scene.open_boundaries, d, scene.dx))
    term = scene.terms_by_name["open_boundaries"]
    term.zones = scene.open_boundaries
    term.refresh()
    return zone
