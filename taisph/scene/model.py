"""A scene: particles, materials, the terms to simulate and the numerical settings.

A scene is plain Python and numpy; nothing touches Taichi until a
:class:`taisph.Simulation` is made from it. Cases (``taisph.cases.dam_break(...)``)
return scenes, and scripts may edit them before simulating::

    scene = taisph.cases.dam_break(dx=0.02)
    scene.terms_by_name["artificial_viscosity"].values["alpha"] = 0.05
    sim = taisph.Simulation(scene)
"""

from __future__ import annotations

import copy
import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from ..engine import smoothing
from ..engine.layout import FLUID, KINDS, WALL
from ..eos import Tait
from ..messages import InputError
from ..terms.base import Term
from .names import INTEGRATORS, KERNELS, SOLVERS
from .parameters import check_runtime
from .solvers import check_dfsph


@dataclass
class Material:
    """A fluid's constants: the equation of state's (Tait): reference density rho0
    (kg/m^3), sound speed c0 (m/s), exponent gamma and background pressure (Pa, the
    pressure at rho0: 0 for a free surface; a positive one for two phases filling a closed
    box, docs/multiphase.md); and its dynamic viscosity (Pa s), which terms that
    declare it in ``material_columns`` read (:class:`taisph.terms.PhaseViscosity`)."""

    name: str = "water"
    rho0: float = 1000.0
    c0: float = 50.0
    gamma: float = 7.0
    viscosity: float = 0.0
    background_pressure: float = 0.0
    _positive = ("rho0", "c0", "gamma")  # constants check() requires (not a dataclass field)
    _not_negative = ("viscosity", "background_pressure")

    def set(self, **values):
        """Change constants by name (``rho0``, ``c0``, ``gamma``), checked before any
        is changed: a refused value (KeyError for an unknown name, :class:`InputError`
        for a bad value) leaves the material as it was."""
        for key in values:
            if key not in CONSTANTS:
                raise KeyError(f"materials have no constant {key!r} ({', '.join(CONSTANTS)})")
        trial = dataclasses.replace(self, **{key: _number(key, value) for key, value in values.items()})
        trial.check()
        for key in values:
            check_runtime(key, getattr(trial, key), f"material {self.name!r}")
        for key in values:
            setattr(self, key, getattr(trial, key))

    def check(self):
        """:class:`InputError` naming the first constant out of its range."""
        for key in self._positive:
            v = getattr(self, key)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise InputError(f"material {self.name!r}: {key} must be a positive number, got {v!r}")
        for key in self._not_negative:
            v = getattr(self, key)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
                raise InputError(f"material {self.name!r}: {key} must be a number >= 0, got {v!r}")


# a material's constants, by name (Material.set, Scene.set)
CONSTANTS = ("rho0", "c0", "gamma", "viscosity", "background_pressure")


def _copy_term(term: Term) -> Term:
    """A copy of `term` with its own values (what :meth:`Scene.set` changes)."""
    twin = copy.copy(term)
    twin.values = dict(term.values)
    return twin


def _number(key: str, value) -> float:
    """`value` as a float (:class:`InputError` naming `key` if it is none)."""
    try:
        return float(value)
    except (TypeError, ValueError):
        raise InputError(f"{key} must be a number, got {value!r}") from None


@dataclass
class Gas(Material):
    """An ideal gas (use with ``Scene(eos=IdealGas())``): only the ratio of specific
    heats gamma enters the physics, p = (gamma - 1) rho e. ``rho0`` is only the default
    density of :meth:`Scene.add_fluid`; the sound speed follows from the state."""

    name: str = "gas"
    rho0: float = 1.0
    c0: float | None = None
    gamma: float = 1.4
    _positive = ("rho0", "gamma")

    def check(self):
        super().check()
        if self.gamma <= 1.0:
            raise InputError(f"gas {self.name!r}: gamma must be > 1, got {self.gamma!r}")


@dataclass
class Scene:
    """Everything a simulation needs. Arrays are in SI units, shape ``(N, dim)`` or ``(N,)``.

    Particles are added in blocks with :meth:`add_fluid` and :meth:`add_walls`.
    ``domain`` is the box ``(lo, hi)`` the neighbour grid covers; particles outside it
    are still simulated correctly (only more slowly); the guards stop a run when a
    particle leaves it by more than a kernel support, except along periodic axes and
    through the faces listed in ``open_faces`` (e.g. ``("+y",)``, the open top of a
    tank: water may fly up and fall back). ``dt=None`` (the default) adapts the step
    to the flow (:mod:`taisph.engine.timestep`); a number fixes it.
    """

    name: str
    dim: int
    dx: float
    smoothing_length: float
    domain: tuple
    materials: list = field(default_factory=lambda: [Material()])
    terms: list = field(default_factory=list)
    kernel: str = "spline"
    integrator: str = "pc"
    dt: float | None = None
    t_end: float = 1.0
    frames: int = 50
    description: str = ""
    eos: object = field(default_factory=Tait)
    periodic: tuple = None  # per axis; the domain's extent is the period
    # neighbour lists reused while no particle has moved half this skin (a fraction of
    # the support radius); 0: walk the cells every step (see taisph.engine.neighbours)
    neighbour_skin: float = 0.0
    # faces of the domain particles may cross without tripping the guards: "-x", "+y"...
    open_faces: tuple = ()
    # particles that leave the domain elsewhere are removed and counted (instead of
    # stopping the run), and so are particles whose density leaves the guard's range, up
    # to the max_out_of_range control (taisph.engine.guards); the remove_escaped control
    # overrides this
    remove_escaped: bool = False
    # the Courant number of the adaptive step, for a scene measured to hold more than
    # the engine's default 0.25 (taisph.engine.timestep); the courant control overrides
    courant: float | None = None
    # "wcsph" (weakly compressible: the terms and the equation of state) or "dfsph" (divergence-
    # free SPH: an implicit pressure solve keeps the density at rho0; the scene's non-pressure
    # terms only, taisph.engine.dfsph); compile time
    solver: str = "wcsph"
    # per-particle data, filled by add_fluid/add_walls
    position: np.ndarray = None
    velocity: np.ndarray = None
    mass: np.ndarray = None
    density: np.ndarray = None
    kind: np.ndarray = None
    material: np.ndarray = None
    # initial values of further stored quantities (e.g. "energy"), name -> (N,) or (N, dim)
    quantities: dict = field(default_factory=dict)
    # open boundary zones (taisph.terms.open_boundary.OpenBoundary), made by add_open_boundary
    open_boundaries: list = field(default_factory=list)
    # named groups of wall particles (name -> particle indices; force probes), and probes a
    # command-line run of the scene writes to OUT/probes.csv besides --probe's
    wall_groups: dict = field(default_factory=dict)
    probes: list = field(default_factory=list)
    # moving and floating bodies (taisph.scene.bodies.Body), made by add_body
    bodies: list = field(default_factory=list)
    # the built-in case that made the scene and the values of all its parameters (set by the
    # case's @checked, taisph.scene.parameters; "" and {} for a scene made otherwise): what
    # the case's headline results read (taisph.run.results)
    case: str = ""
    case_parameters: dict = field(default_factory=dict)

    def __post_init__(self):
        if self.dim not in (1, 2, 3):
            raise InputError(f"dim must be 1, 2 or 3, got {self.dim!r}")
        d = self.dim
        self.position = np.zeros((0, d)) if self.position is None else np.asarray(self.position, float).reshape(-1, d)
        n = len(self.position)
        self.velocity = np.zeros((n, d)) if self.velocity is None else np.asarray(self.velocity, float).reshape(-1, d)
        self.mass = np.zeros(n) if self.mass is None else np.asarray(self.mass, float).ravel()
        self.density = np.zeros(n) if self.density is None else np.asarray(self.density, float).ravel()
        self.kind = np.zeros(n, np.int32) if self.kind is None else np.asarray(self.kind, np.int32).ravel()
        self.material = np.zeros(n, np.int32) if self.material is None else np.asarray(self.material, np.int32).ravel()
        lo, hi = self.domain
        self.domain = (np.asarray(lo, float).reshape(d), np.asarray(hi, float).reshape(d))
        self.periodic = (False,) * d if self.periodic is None else tuple(bool(p) for p in self.periodic)
        self.open_faces = (self.open_faces,) if isinstance(self.open_faces, str) else tuple(self.open_faces)

    # --- building -------------------------------------------------------------
    def add_particles(self, position, kind="fluid", material=0, mass=None, density=None, velocity=None,
                      **quantities):
        """Append particles. `mass` defaults to rho0 dx^dim of their material,
        `density` to rho0, `velocity` to zero; further keyword arguments give initial
        values of other stored quantities (e.g. ``energy=2.5``; zero for particles
        added without them). Returns the slice of the new ones."""
        position = np.asarray(position, float).reshape(-1, self.dim)
        n = len(position)
        kind_code = KINDS[kind] if isinstance(kind, str) else int(kind)
        rho0 = self.materials[material].rho0
        density = np.full(n, rho0) if density is None else np.broadcast_to(np.asarray(density, float), (n,))
        mass = np.full(n, rho0 * self.dx**self.dim) if mass is None else np.broadcast_to(np.asarray(mass, float), (n,))
        velocity = (np.zeros((n, self.dim)) if velocity is None
                    else np.broadcast_to(np.asarray(velocity, float), (n, self.dim)))
        start = len(self.position)
        self.position = np.concatenate([self.position, position])
        self.velocity = np.concatenate([self.velocity, velocity])
        self.mass = np.concatenate([self.mass, mass])
        self.density = np.concatenate([self.density, density])
        self.kind = np.concatenate([self.kind, np.full(n, kind_code, np.int32)])
        self.material = np.concatenate([self.material, np.full(n, material, np.int32)])
        for name in set(quantities) | set(self.quantities):
            old = self.quantities.get(name)
            new = quantities.get(name)
            width = (old.shape[1:] if old is not None else np.shape(new)[1:] if np.ndim(new) == 2 else ())
            old = np.zeros((start, *width)) if old is None else old
            new = np.zeros((n, *width)) if new is None else np.broadcast_to(np.asarray(new, float), (n, *width))
            self.quantities[name] = np.concatenate([old, new])
        return slice(start, start + n)

    def add_fluid(self, position, material=0, **kw):
        return self.add_particles(position, kind="fluid", material=material, **kw)

    def add_walls(self, position, material=0, **kw):
        return self.add_particles(position, kind="wall", material=material, **kw)

    def add_open_boundary(self, name: str, at, to, normal=None, velocity=None, pressure=None,
                          profile: str = "uniform", period: float | None = None, layers: int | None = None,
                          material: int = 0):
        """An open boundary (inflow, outflow or both, :mod:`taisph.terms.open_boundary`) on the
        face from `at` to `to` (2D: a segment; 3D: opposite corners of a rectangle in a
        coordinate plane), `normal` into the fluid (default: found). `velocity`: None
        (extrapolated), a speed along `normal`, a vector, an (M, 2) table of (t, speed) or
        ``f(points, t)``, shaped across the face by `profile` ("uniform", "parabolic"),
        repeating every `period` s; `pressure`: None (extrapolated) or Pa. Fills the buffer
        (`layers` rows, default a support and one) and grows the domain to hold it."""
        from .open_boundary import add

        return add(self, name, at, to, normal, velocity, pressure, profile, period, layers, material)

    def add_body(self, name: str, particles, motion: str = "floating", *, density=None, mass=None, centre=None,
                 inertia=None, velocity=None, angular_velocity=None, fixed=(), trajectory=None, axis=None,
                 until=None, hinge=None):
        """A body of wall particles moving as one, ``"floating"`` or ``"prescribed"``: every
        argument in :func:`taisph.scene.bodies.add`, the physics in docs/bodies.md."""
        from .bodies import add

        return add(self, name, particles, motion, density, mass, centre, inertia, velocity, angular_velocity,
                   fixed, trajectory, axis, until, hinge)

    # --- derived ----------------------------------------------------------------
    @property
    def n(self) -> int:
        return len(self.position)

    @property
    def n_fluid(self) -> int:
        return int(np.count_nonzero(self.kind == FLUID))

    @property
    def n_wall(self) -> int:
        return int(np.count_nonzero(self.kind == WALL))

    @property
    def support_radius(self) -> float:
        return smoothing.KERNELS[self.kernel].support * self.smoothing_length

    @property
    def terms_by_name(self) -> dict:
        return {t.name: t for t in self.terms}

    def parameters(self) -> dict:
        """All runtime parameters of the scene's terms, by name."""
        out = {"smoothing_length": self.smoothing_length}
        for t in self.terms:
            out.update(t.values)
        return out

    def set(self, **values):
        """Change parameters by name: ``smoothing_length``, any term's parameter (e.g.
        ``alpha``, ``gravity``), or a material constant (``rho0``, ``c0``, ``gamma``: of
        every material). Raises KeyError naming the unknown one, :class:`InputError` (a
        ValueError, from :meth:`validate`) for a bad value, and
        :class:`taisph.scene.parameters.ParameterError` (an InputError) naming the
        parameter, the value and the allowed range for a value outside the range the
        command line and scene files allow (:data:`taisph.scene.parameters.RUNTIME`, e.g.
        alpha in [0, 2]). All the values are checked together, on a copy, before any is
        written: a refused call leaves the scene as it was."""
        by_param = {k: t for t in self.terms for k in t.params}
        for key in values:
            if key not in by_param and key not in CONSTANTS and key != "smoothing_length":
                names = sorted(set(self.parameters()) | set(CONSTANTS))
                raise KeyError(f"no parameter {key!r}; parameters: {', '.join(names)}")
        values = {key: _number(key, v) if key in CONSTANTS or key == "smoothing_length" else v
                  for key, v in values.items()}
        self._with(values).validate()  # the scene as it would be; raises before anything is written
        for key, value in values.items():  # and each value within its declared range
            check_runtime(key, value, f"scene {self.name!r}")
        self._write(self, values)

    def _with(self, values: dict) -> "Scene":
        """A copy of the scene with `values` (checked names) set: its own materials and
        its own copies of the terms whose values change; particles shared."""
        trial = copy.copy(self)
        trial.materials = [copy.copy(m) for m in self.materials]
        trial.terms = [_copy_term(t) if set(t.params) & set(values) else t for t in self.terms]
        self._write(trial, values)
        return trial

    @staticmethod
    def _write(scene: "Scene", values: dict) -> None:
        by_param = {k: t for t in scene.terms for k in t.params}
        for key, value in values.items():
            if key == "smoothing_length":
                scene.smoothing_length = value
            elif key in CONSTANTS:
                for m in scene.materials:
                    setattr(m, key, value)
            else:
                by_param[key].values[key] = value

    def smallest_smoothing_length(self) -> float:
        """The scene's h, or if a term varies it (``initial(scene)``, e.g. adaptive_h)
        the smallest initial one."""
        h = self.smoothing_length
        for t in self.terms:
            if hasattr(t, "initial"):
                h = min(h, float(np.min(t.initial(self), initial=h)))
        return h

    # --- checking -----------------------------------------------------------------
    def validate(self) -> None:
        """Raise :class:`InputError` (a ValueError) naming the first problem found (the
        scene's own checks, each term's ``check``, the equation of state's, DFSPH's)."""
        self._check_particles()
        for m in self.materials:
            m.check()
        if hasattr(self.eos, "check"):
            self.eos.check(self)
        self._check_settings()
        self._check_terms()
        if self.open_boundaries:
            from .open_boundary import check

            check(self)
        if self.solver == "dfsph":
            check_dfsph(self)

    def _check_particles(self) -> None:
        """The particle arrays: their shapes, finite values, positive masses and densities,
        known materials and kinds (and the neighbour skin, checked first)."""
        d, n = self.dim, self.n
        if n == 0:
            raise InputError(f"scene {self.name!r} has no particles")
        if not (0.0 <= self.neighbour_skin <= 2.0):
            raise InputError(f"scene {self.name!r}: neighbour_skin is {self.neighbour_skin!r}; it is a fraction "
                             "of the support radius, from 0 (no lists) to 2")
        for name, arr, shape in (
            ("position", self.position, (n, d)),
            ("velocity", self.velocity, (n, d)),
            ("mass", self.mass, (n,)),
            ("density", self.density, (n,)),
            ("kind", self.kind, (n,)),
            ("material", self.material, (n,)),
        ):
            if arr.shape != shape:
                raise InputError(f"scene {self.name!r}: {name} has shape {arr.shape}, expected {shape}")
            if arr.dtype.kind == "f":
                bad = np.flatnonzero(~np.all(np.isfinite(arr.reshape(n, -1)), axis=1))
                if bad.size:
                    raise InputError(f"scene {self.name!r}: {name} of particle {bad[0]} is not finite: "
                                     f"{arr[bad[0]]}")
        for name, arr in (("mass", self.mass), ("density", self.density)):
            bad = np.flatnonzero(arr <= 0)
            if bad.size:
                raise InputError(f"scene {self.name!r}: {name} of particle {bad[0]} is {arr[bad[0]]}; "
                                 "it must be > 0")
        bad = np.flatnonzero((self.material < 0) | (self.material >= len(self.materials)))
        if bad.size:
            raise InputError(
                f"scene {self.name!r}: particle {bad[0]} has material {self.material[bad[0]]}, "
                f"but only {len(self.materials)} material(s) are defined"
            )
        bad = np.flatnonzero(~np.isin(self.kind, list(KINDS.values())))
        if bad.size:
            raise InputError(f"scene {self.name!r}: particle {bad[0]} has unknown kind {self.kind[bad[0]]}")

    def _check_settings(self) -> None:
        """The numerical settings (kernel, solver, integrator, dx, h, times, Courant
        number), the domain, periodic flags, open faces and per-particle quantities."""
        d, n = self.dim, self.n
        if self.kernel not in KERNELS:
            raise InputError(f"unknown kernel {self.kernel!r}; choose one of {', '.join(KERNELS)}")
        if self.solver not in SOLVERS:
            raise InputError(f"scene {self.name!r}: unknown solver {self.solver!r}; "
                             f"choose one of {', '.join(SOLVERS)}")
        if self.integrator not in INTEGRATORS:
            raise InputError(f"unknown integrator {self.integrator!r}; choose one of {', '.join(INTEGRATORS)}")
        for key in ("dx", "smoothing_length", "t_end"):
            v = getattr(self, key)
            if not (math.isfinite(v) and v > 0):
                raise InputError(f"scene {self.name!r}: {key} must be positive, got {v!r}")
        if self.dt is not None and not (math.isfinite(self.dt) and self.dt > 0):
            raise InputError(f"scene {self.name!r}: dt must be positive, got {self.dt!r}")
        if self.courant is not None and not (math.isfinite(self.courant) and 0 < self.courant <= 1):
            raise InputError(f"scene {self.name!r}: courant must be in (0, 1], got {self.courant!r}")
        lo, hi = self.domain
        if np.any(hi <= lo):
            raise InputError(f"scene {self.name!r}: domain {lo} .. {hi} is empty")
        if len(self.periodic) != d:
            raise InputError(f"scene {self.name!r}: periodic needs {d} flags, got {self.periodic}")
        faces = [s + a for a in "xyz"[:d] for s in "-+"]
        for face in self.open_faces:
            if face not in faces:
                raise InputError(f"scene {self.name!r}: open face {face!r} is not one of {', '.join(faces)}")
        for name, values in self.quantities.items():
            values = np.asarray(values, float)
            if len(values) != n or not np.all(np.isfinite(values)):
                raise InputError(f"scene {self.name!r}: quantity {name!r} needs {n} finite values")

    def _check_terms(self) -> None:
        """The terms: taisph terms, each listed once, each passing its own check."""
        names = set()
        for t in self.terms:
            if not isinstance(t, Term):
                raise TypeError(f"scene {self.name!r}: {t!r} is not a taisph term")
            if t.name in names:
                raise InputError(f"scene {self.name!r}: term {t.name!r} listed twice")
            names.add(t.name)
            t.check(self)
            t.param_values(self.dim)

    def describe(self) -> str:
        """The scene in a few lines: particles, numerics, effects and boundaries (the header of a run)."""
        from .description import describe

        return describe(self)
