"""Scene files, first half: reading and checking a scene described in TOML (``python -m taisph SCENE.toml``).

:func:`read` parses and checks a file completely (meshes included) and returns a :class:`SceneSpec`;
nothing is built or written before every key has been checked, and every error names the file, the key
(``fluid[1].box``) and the value. :mod:`taisph.formats.scenefile` builds the scene. Schema: docs/scenes.md.
"""

from __future__ import annotations

import math
import re
import sys
from dataclasses import dataclass
from types import SimpleNamespace
from pathlib import Path

tomllib = __import__("tomllib" if sys.version_info >= (3, 11) else "tomli")  # tomli: Python 3.10's dependency

import numpy as np

from ..engine import smoothing, timestep
from ..engine.dfsph import pairs
from ..geometry.mesh import MeshError, load_surface
from ..geometry.shapes import support_layers
from ..messages import InputError
from ..probes.spec import Probe  # noqa: F401  (what [[probes]] become)
from ..scene.model import CONSTANTS
from ..scene.names import UP, default_formulation
from ..scene.parameters import (BYTES_PER_PARTICLE, Range, between, courant_number, diffusion_delta, end_time, finite,
                                gravity_component, integer, known_formulation, known_integrator, known_kernel,
                                known_solver, memory_shortage, Number, one_of, output_frames, particle_spacing,
                                position_component, positive, reference_density, smoothing_factor, speed_of_sound,
                                tait_exponent, velocity_component, viscosity_alpha, xsph_epsilon)
from ..terms import Gravity
from .scenefile_open import MISSING as _MISSING, zones as open_boundaries  # [[open_boundaries]]
from .scenefile_bodies import SHAPES, blocks as bodies  # [[bodies]]; SHAPES: every block's shape keys
# [[probes]] (PROBE_KEYS: the schema)
from .scenefile_probes import PROBE_KEYS, RANGES as PROBE_RANGES, probes  # noqa: F401

WALL_KINDS = ("tank", "obstacle")  # a tank holds fluid (wall layers outside its box); an obstacle is solid

# The allowed values of each key, declared once in taisph.scene.parameters (the cases' and the command
# line's ranges for the same quantities): a value out of range is refused in the same words everywhere.
RANGES = {
    "dim": integer(at_least=2, at_most=3), "dx": Number(0, particle_spacing.high, low_open=True), "t_end": end_time,
    "frames": output_frames,
    "solver": known_solver, "kernel": known_kernel, "integrator": known_integrator, "h_factor": smoothing_factor,
    "dt": positive, "courant": courant_number, "physics.gravity": gravity_component, "physics.alpha": viscosity_alpha,
    "physics.delta": diffusion_delta, "physics.xsph": xsph_epsilon, "rho0": reference_density, "c0": speed_of_sound,
    "gamma": tait_exponent, "velocity": velocity_component, "scale": positive, "model": one_of("dummy", "lj"),
    "kind": PROBE_RANGES["kind"], "every": PROBE_RANGES["every"], "walls.kind": one_of(*WALL_KINDS),
    "physics.formulation": known_formulation, "physics.nu": between(0, 100), "physics.shifting": between(0, 1000),
    "physics.density_relaxation": between(0, 1e6), "pressure": between(0, 1e9),
    # a material's dynamic viscosity (Pa s: water 1e-3, glycerol 1.4, pitch-like fluids 1e5 and more) and its
    # background pressure (Pa, the range of a fluid block's pressure); surface tension's sigma (N/m: water 0.0728,
    # mercury 0.49; the benchmark of Hysing et al. 2009, in its units, 24.5)
    "viscosity": between(0, 1e6), "background_pressure": between(0, 1e9), "physics.surface_tension": between(0, 1e3)}
# The values of the keys a file may leave out (gravity: Gravity.default(dim), standard gravity along -y)
DEFAULTS = {"solver": "wcsph", "kernel": "spline", "integrator": "pc", "h_factor": 1.3, "physics.alpha": 0.1,
            "physics.delta": 0.1, "physics.xsph": 0.0, "physics.nu": 0.0, "physics.shifting": 0.0,
            "physics.density_relaxation": 0.0, "physics.surface_tension": 0.0, "rho0": 1000.0, "gamma": 7.0,
            "viscosity": 0.0, "background_pressure": 0.0, "model": "dummy", "every": 1}

TOP_KEYS = {"name", "description", "dim", "dx", "t_end", "frames", "solver", "kernel", "integrator", "h_factor", "dt",
            "courant", "domain", "remove_escaped", "physics", "materials", "fluid", "walls", "probes",
            "open_boundaries", "bodies", *timestep.SETTABLE}
PHYSICS_KEYS = {"gravity", "alpha", "delta", "xsph", "formulation", "nu", "shifting", "density_relaxation",
                "surface_tension"}
MATERIAL_KEYS = {"name", "rho0", "c0", "gamma", "viscosity", "background_pressure"}
# ``--set NAME=VALUE`` of a scene parameter's name (Scene.set's) rather than a file key: a material constant sets
# that key of every [[materials]] table (as Scene.set sets every material's), sigma the surface tension
MATERIAL_CONSTANTS = CONSTANTS  # rho0, c0, gamma, viscosity, background_pressure
SET_ALIASES = {"sigma": "physics.surface_tension"}
FLUID_KEYS = {*SHAPES, "scale", "translate", "material", "velocity", "hydrostatic", "pressure"}
WALL_KEYS = {*SHAPES, "scale", "translate", "name", "model", "kind", "open_top"}


class SceneFileError(InputError):
    """A mistake in a scene file: ``str(err)`` names the file, the key and the value."""


@dataclass
class Block:
    """A ``[[fluid]]`` or ``[[walls]]`` entry: its shape (``box`` (lo, hi), or a ClosedSurface) and settings."""

    key: str  # e.g. "fluid[0]", for messages
    shape: str = "box"  # which key gave the shape: box, mesh or polygon
    value: object = None  # its value in the file, for messages
    box: tuple | None = None
    surface: object = None
    material: int = 0
    velocity: tuple | None = None
    hydrostatic: bool = True
    pressure: float = 0.0  # a fluid's initial pressure (Pa) at its top
    name: str = ""
    model: str = "dummy"
    kind: str = "tank"  # walls: "tank" or "obstacle" (WALL_KINDS)
    kind_given: bool = False  # the file says which (else a tank must hold fluid)
    open_top: bool = True  # a tank's

    @property
    def bounds(self):
        return self.box if self.box is not None else self.surface.bounds


@dataclass
class SceneSpec:
    """A checked scene file: everything :func:`taisph.formats.scenefile.build` needs."""

    path: Path
    name: str
    description: str
    dim: int
    dx: float
    t_end: float
    frames: int
    solver: str
    kernel: str
    integrator: str
    h_factor: float
    dt: float | None
    courant: float | None  # the adaptive step's Courant number (None: the default, 0.25)
    controls: dict  # the other run controls the file sets (timestep.SETTABLE: dt_max, dfsph_tolerance...)
    gravity: tuple
    alpha: float
    delta: float
    xsph: float
    nu: float  # the laminar viscosity's kinematic viscosity (m^2/s; 0: none)
    shifting: float  # particle shifting's reference speed U (m/s; 0: none), with the free-surface rule
    density_relaxation: float  # DensityRelaxation's relaxation time tau (s; 0: none)
    materials: list  # of dicts: name, rho0, c0 (None: default), gamma, viscosity (Pa s), background_pressure (Pa)
    fluid: list
    walls: list
    probes: list
    domain: tuple | None = None  # None: around the geometry
    remove_escaped: bool = True  # particles leaving the domain (not by an open top) removed, else the run stops
    wall_model: str | None = None  # the one model of all wall groups (None: no walls)
    multiphase: bool = False  # fluids of different rho0: the sharp-interface terms
    formulation: str = "symmetric"  # names.FORMULATIONS: "symmetric" or "riemann" (alpha and delta then default to 0)
    open_boundaries: list | None = None  # of scenefile_open.Zone
    bodies: list | None = None  # of scenefile_bodies.BodyBlock
    surface_tension: float = 0.0  # SurfaceTension's sigma (N/m; 0: none): two-phase, or free-surface for one fluid

    @property
    def used_materials(self) -> list:
        """The indices of the materials some fluid block uses, in order."""
        return sorted({b.material for b in self.fluid})

    @property
    def viscous(self) -> bool:
        """Some material a fluid uses has a dynamic viscosity: PhaseViscosity (Hu & Adams 2006)."""
        return any(self.materials[k]["viscosity"] > 0 for k in self.used_materials)


def read(path, overrides: dict | None = None) -> SceneSpec:
    """Parse and check the scene file `path`. `overrides` (``{"dx": 0.05, "physics.alpha": 0.05}``) replace
    values of the file before the checks (``--dx``, ``--set``...). Raises :class:`SceneFileError`."""
    path = Path(path)
    if not path.is_file():
        raise SceneFileError(f"{path}: no such scene file")
    try:
        data = tomllib.loads(path.read_text())
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as err:
        raise SceneFileError(f"{path}: not valid TOML: {err}") from None
    for key, value in (overrides or {}).items():
        _override(path, data, key, value)
    return _Checker(path).scene(data)


def _override(path, data, key, value):
    """Set `key` ("dx", "physics.alpha", "fluid[0].velocity") of the parsed file; a material constant's name
    ("viscosity") sets it in every [[materials]] table, "sigma" sets physics.surface_tension (SET_ALIASES)."""
    if key in MATERIAL_CONSTANTS:
        materials = data.setdefault("materials", [{"name": "water"}])  # (the default material, named)
        for m in materials if isinstance(materials, list) else ():
            if isinstance(m, dict):
                m[key] = value
        return
    key = SET_ALIASES.get(key, key)
    match = re.fullmatch(r"(?:([a-z_]+)(?:\[(\d+)\])?\.)?([a-z_0-9]+)", key)
    table = data
    if match and match[1]:
        table = data.setdefault(match[1], {} if match[2] is None else [])
        if match[2] is not None:
            table = table[int(match[2])] if isinstance(table, list) and int(match[2]) < len(table) else None
    if not match or not isinstance(table, dict):
        raise SceneFileError(f"{path}: {key} = {value!r} (set on the command line): no such table in the file; "
                             "set KEY, TABLE.KEY or LIST[INDEX].KEY (e.g. dx, physics.alpha, fluid[0].velocity)")
    table[match[3]] = value


def wall_layers_needed(spec: SceneSpec) -> int:
    """Layers of dummy-wall particles that fill the kernel support: ceil(support / dx)."""
    support = smoothing.KERNELS[spec.kernel].support * spec.h_factor * spec.dx
    return support_layers(support, spec.dx)


def default_domain(spec: SceneSpec):
    """The box around all blocks, grown by the wall layers and dx, half the height again above (as the cases)."""
    blocks = spec.fluid + spec.walls + (spec.bodies or [])
    lo, hi = np.min([b.bounds[0] for b in blocks], axis=0), np.max([b.bounds[1] for b in blocks], axis=0)
    pad = (wall_layers_needed(spec) + 1) * spec.dx
    top = np.eye(spec.dim)[UP] * 0.5 * (hi[UP] - lo[UP])
    return lo - pad, hi + pad + top


class _Checker:
    """The checks, each raising SceneFileError('FILE: KEY = VALUE: problem')."""

    def __init__(self, path: Path):
        self.path = path

    def fail(self, key, value, problem):
        shown = "(missing)" if value is _MISSING else repr(value)
        raise SceneFileError(f"{self.path}: {key} = {shown}: {problem}")

    def keys(self, key, table, allowed):
        if not isinstance(table, dict):
            self.fail(key, table, "expected a table")
        for k in table:
            if k not in allowed:
                self.fail(f"{key}.{k}" if key else k, table[k], f"unknown key; known: {', '.join(sorted(allowed))}")

    def number(self, key, value, rng: Range):
        """`value` checked against `rng` (a range of taisph.scene.parameters)."""
        if value is _MISSING:
            self.fail(key, value, "required")
        integral = getattr(rng, "integer", False)
        if isinstance(value, bool) or not isinstance(value, int if integral else (int, float)):
            self.fail(key, value, "expected " + ("an integer" if integral else "a number"))
        if not rng.accepts(value):
            self.fail(key, value, f"must be {rng.describe()}")
        return value if integral else float(value)

    def choice(self, key, value, rng: Range):
        """`value` checked against a one_of range."""
        if value is _MISSING or not rng.accepts(value):
            self.fail(key, value, f"required; {rng.describe()}" if value is _MISSING else f"must be {rng.describe()}")
        return value

    def vector(self, key, value, n, rng: Range = finite):
        if not (isinstance(value, list) and len(value) == n):
            self.fail(key, value, f"expected a list of {n} numbers")
        for k, v in enumerate(value):
            self.number(f"{key}[{k}]", v, rng)
        return tuple(float(v) for v in value)

    def box(self, key, value, dim):
        if not (isinstance(value, list) and len(value) == 2):
            self.fail(key, value, f"expected [lo, hi], two lists of {dim} numbers")
        lo, hi = self.vector(f"{key}[0]", value[0], dim), self.vector(f"{key}[1]", value[1], dim)
        if not all(a < b for a, b in zip(lo, hi)):
            self.fail(key, value, "lo must be below hi along every axis")
        return lo, hi

    def text(self, key, value):
        if value is _MISSING or not isinstance(value, str) or not value:
            self.fail(key, value, "required" if value is _MISSING else "expected a non-empty string")
        return value

    def flag(self, key, value, default):
        if value is not _MISSING and not isinstance(value, bool):
            self.fail(key, value, "expected true or false")
        return default if value is _MISSING else value

    # --- the file -------------------------------------------------------------------
    def scene(self, data) -> SceneSpec:
        self.keys("", data, TOP_KEYS)
        physics = data.get("physics", {})
        self.keys("physics", physics, PHYSICS_KEYS)
        numbers = {k: self.number(k, data.get(k, DEFAULTS.get(k, _MISSING)), RANGES[k])
                   for k in ("dim", "dx", "t_end", "frames", "h_factor")}
        dim = numbers["dim"]
        gravity = physics.get("gravity", list(Gravity.default(dim)))
        spec = SceneSpec(
            path=self.path,
            name=self.text("name", data.get("name", _MISSING)),
            description=self.text("description", data["description"]) if "description" in data else "",
            **numbers,
            **{k: self.choice(k, data.get(k, DEFAULTS[k]), RANGES[k]) for k in ("solver", "kernel", "integrator")},
            **{k: self.number(k, data[k], RANGES[k]) if k in data else None for k in ("dt", "courant")},
            controls={k: self.number(k, data[k], timestep.SETTABLE[k]) for k in timestep.SETTABLE if k in data},
            remove_escaped=self.flag("remove_escaped", data.get("remove_escaped", _MISSING), True),
            gravity=self.vector("physics.gravity", gravity, dim, RANGES["physics.gravity"]),
            **{k: self.number(f"physics.{k}", physics.get(k, DEFAULTS[f"physics.{k}"]), RANGES[f"physics.{k}"])
               for k in ("alpha", "delta", "xsph", "nu", "shifting", "density_relaxation", "surface_tension")},
            materials=self.materials(data.get("materials", [{"name": "water"}])),
            fluid=[], walls=[], probes=[],
        )
        names = [m["name"] for m in spec.materials]
        spec.fluid = [self.block(f"fluid[{k}]", b, spec, names, FLUID_KEYS)
                      for k, b in enumerate(self.entries("fluid", data))]
        if not spec.fluid:
            self.fail("fluid", data.get("fluid", _MISSING), "a scene needs at least one [[fluid]] block")
        spec.walls = [self.block(f"walls[{k}]", b, spec, names, WALL_KEYS)
                      for k, b in enumerate(self.entries("walls", data))]
        seen = {}
        for k, w in enumerate(spec.walls):
            if seen.setdefault(w.name, k) != k:
                self.fail(f"walls[{k}].name", w.name, f"already the name of walls[{seen[w.name]}]")
            if w.model != spec.walls[0].model:
                self.fail(f"walls[{k}].model", w.model, f"all wall groups need one model (walls[0] is "
                          f"{spec.walls[0].model!r}): the wall terms act on every wall particle")
        # (bodies are dummy walls)
        spec.wall_model = spec.walls[0].model if spec.walls else ("dummy" if data.get("bodies") else None)
        self.memory(spec)
        spec.multiphase = len({spec.materials[k]["rho0"] for k in spec.used_materials}) > 1
        self.phases(spec, physics)
        spec.formulation = self.choice("physics.formulation", physics.get("formulation", default_formulation(spec)),
                                       known_formulation)
        if spec.formulation == "riemann":  # its own dissipation: alpha and delta only where the file sets them
            spec.alpha = spec.alpha if "alpha" in physics else 0.0
            spec.delta = spec.delta if "delta" in physics else 0.0
        if spec.multiphase and spec.wall_model == "dummy" and "delta" not in physics:
            spec.delta = 0.0  # delta-SPH would diffuse each phase's density towards the other's across the interface
        spec.domain = self.box("domain", data["domain"], dim) if "domain" in data else None
        spec.bodies = bodies(self, self.entries("bodies", data), spec, [w.name for w in spec.walls])
        lo, hi = spec.domain or default_domain(spec)
        spec.probes = probes(self, self.entries("probes", data), spec, lo, hi)
        spec.open_boundaries = open_boundaries(self, self.entries("open_boundaries", data), spec, names)
        return spec

    def entries(self, key, data):
        value = data.get(key, [])
        if not (isinstance(value, list) and all(isinstance(v, dict) for v in value)):
            self.fail(key, value, f"expected [[{key}]] tables")
        return value

    def materials(self, entries):
        if not (isinstance(entries, list) and entries and all(isinstance(m, dict) for m in entries)):
            self.fail("materials", entries, "expected one or more [[materials]] tables")
        out = []
        for k, m in enumerate(entries):
            key = f"materials[{k}]"
            self.keys(key, m, MATERIAL_KEYS)
            name = self.text(f"{key}.name", m.get("name", _MISSING))
            if name in [o["name"] for o in out]:
                self.fail(f"{key}.name", name, "already the name of another material")
            constant = lambda k: self.number(f"{key}.{k}", m.get(k, DEFAULTS.get(k)), RANGES[k])  # noqa: E731
            out.append({"name": name, "rho0": constant("rho0"), "c0": None if m.get("c0") is None else constant("c0"),
                        "gamma": constant("gamma"), "viscosity": constant("viscosity"),
                        "background_pressure": constant("background_pressure")})
        return out

    def phases(self, spec, physics):
        """The choice between the materials' viscosity and physics.nu, one background pressure for all phases,
        and surface tension's materials."""
        used, materials = spec.used_materials, spec.materials
        viscous = [k for k in used if materials[k]["viscosity"] > 0]
        if viscous and spec.nu > 0:
            m = materials[viscous[0]]
            self.fail("physics.nu", physics["nu"], f"a kinematic viscosity for every fluid (Morris et al.), and "
                      f"materials[{viscous[0]}].viscosity = {m['viscosity']!r} gives {m['name']} its own dynamic "
                      "viscosity (Hu & Adams): give either physics.nu or the materials' viscosity, not both")
        first = materials[used[0]]
        for k in used:  # Material.background_pressure: one for all phases (the pressure at rest across an interface)
            if materials[k]["background_pressure"] != first["background_pressure"]:
                self.fail(f"materials[{k}].background_pressure", materials[k]["background_pressure"],
                          f"differs from materials[{used[0]}]'s ({first['name']}: {first['background_pressure']:g} "
                          "Pa); the phases share one pressure at rest, so their background pressure must be the "
                          "same (a fluid block's own pressure is its pressure key)")
        unused = [k for k in range(len(materials)) if k not in used]
        if spec.surface_tension > 0 and unused:
            self.fail("physics.surface_tension", physics["surface_tension"], f"materials[{unused[0]}] "
                      f"({materials[unused[0]]['name']}) is used by no [[fluid]] block; surface tension acts between "
                      "the first material and the others (with one material, at its free surface), over the "
                      "materials of the scene: declare only the materials the fluid uses")

    def memory(self, spec):
        """Refuse blocks whose particles (a lattice of each block's bounds: dx/2 apart for Lennard-Jones walls, grown
        by dummy walls' layers; DFSPH's pair list counted) would need more memory than the machine has, before any
        is made."""
        layers = wall_layers_needed(spec) * spec.dx
        filled = [(b, spec.dx, 0.0) for b in spec.fluid] + [
            (b, spec.dx / 2.0, 0.0) if b.model == "lj" else (b, spec.dx, 2.0 * layers) for b in spec.walls]
        count = sum(math.prod(float(hi - lo + pad) / spacing + 1.0 for lo, hi in zip(*b.bounds))
                    for b, spacing, pad in filled)
        support = smoothing.KERNELS[spec.kernel].support * spec.h_factor * spec.dx  # entries: a power of 2 (fields)
        try:
            capacity = pairs.capacity(SimpleNamespace(support_radius=support, dim=spec.dim, dx=spec.dx))
            entries = 1 << math.ceil(math.log2(capacity))
        except (OverflowError, ZeroDivisionError, ValueError):  # dx = 1e300, 5e-324: refused by the count or the fill
            entries = 1
        per = BYTES_PER_PARTICLE + (pairs.bytes_per_particle(entries, 8) if spec.solver == "dfsph" else 0)
        problem = memory_shortage(count, per)
        if problem:
            shapes = ", ".join(f"{b.key}.{b.shape}" for b, _, _ in filled)
            each = f" (DFSPH: {per} B each)" * (per > BYTES_PER_PARTICLE)
            self.fail("dx", spec.dx, f"fills {shapes} with {count:.3g} particles{each}, {problem}")

    def block(self, key, entry, spec, material_names, allowed) -> Block:
        self.keys(key, entry, allowed)
        shapes = [s for s in SHAPES if s in entry]
        if len(shapes) != 1:
            self.fail(key, {s: entry[s] for s in shapes} if shapes else _MISSING,
                      "give exactly one of box = [lo, hi], mesh = \"file\" or polygon = [[x, y], ...]")
        shape = shapes[0]
        block = Block(key, shape, entry[shape] if shape != "polygon" else "[...]")
        if shape == "box":
            for k in sorted({"scale", "translate"} & set(entry)):
                self.fail(f"{key}.{k}", entry[k], "applies to a mesh or polygon, not a box")
            block.box = self.box(f"{key}.box", entry["box"], spec.dim)
        else:
            block.surface = self.surface(key, shape, entry, spec.dim)
        if "material" in entry:
            name = self.text(f"{key}.material", entry["material"])
            if name not in material_names:
                self.fail(f"{key}.material", name, f"no such material; defined: {', '.join(material_names)}")
            block.material = material_names.index(name)
        block.velocity = (self.vector(f"{key}.velocity", entry["velocity"], spec.dim, RANGES["velocity"])
                          if "velocity" in entry else None)
        block.hydrostatic = self.flag(f"{key}.hydrostatic", entry.get("hydrostatic", _MISSING), True)
        block.pressure = self.number(f"{key}.pressure", entry.get("pressure", 0.0), RANGES["pressure"])
        block.name = self.text(f"{key}.name", entry["name"]) if "name" in entry else key
        block.model = self.choice(f"{key}.model", entry.get("model", DEFAULTS["model"]), RANGES["model"])
        kind = entry.get("kind", "tank" if shape == "box" else "obstacle")
        block.kind, block.kind_given = self.choice(f"{key}.kind", kind, RANGES["walls.kind"]), "kind" in entry
        if block.kind == "tank" and shape != "box":
            self.fail(f"{key}.kind", kind, "a tank is a box; a mesh or polygon wall is a solid obstacle")
        block.open_top = self.flag(f"{key}.open_top", entry.get("open_top", _MISSING), block.kind == "tank")
        if block.open_top and block.kind == "obstacle":
            self.fail(f"{key}.open_top", True, "an obstacle is solid; a box open at the top is a tank")
        return block

    def surface(self, key, shape, entry, dim):
        scale = self.number(f"{key}.scale", entry.get("scale", 1.0), RANGES["scale"])
        translate = self.vector(f"{key}.translate", entry["translate"], dim) if "translate" in entry else None
        value = entry[shape]
        if shape == "polygon":
            if dim != 2:
                self.fail(f"{key}.polygon", value, "a polygon is 2D; in 3D use mesh = \"file\"")
            if not (isinstance(value, list) and len(value) >= 3):
                self.fail(f"{key}.polygon", value, "expected a list of at least 3 [x, y] vertices")
            source = [self.vector(f"{key}.polygon[{k}]", v, 2, position_component) for k, v in enumerate(value)]
            name = "polygon"
        else:
            self.text(f"{key}.mesh", value)
            source = name = self.path.parent / value  # relative to the scene file
        try:
            surface = load_surface(np.asarray(source, float) if shape == "polygon" else source, dim=dim, name=str(name))
        except MeshError as err:  # "NAME: problem"; a polygon's name would repeat the key
            self.fail(f"{key}.{shape}", value if shape == "mesh" else "[...]",
                      str(err) if shape == "mesh" else str(err).split(": ", 1)[1])
        return surface.transformed(scale, translate)
