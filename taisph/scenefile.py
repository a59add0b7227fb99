"""Scene files: a scene described in TOML, run with ``python -m taisph SCENE.toml``.

:func:`read` parses and checks a file completely (meshes included) and returns a
:class:`SceneSpec`; nothing is built or written before every key has been checked,
and every error names the file, the key (``fluid[1].box``) and the value.
:func:`taisph.scenefile_build.build` turns a spec into a :class:`taisph.Scene` and
:class:`RunSettings`; :func:`load` does both. The schema is documented in
docs/scenes.md; ``cases/*.toml`` are examples. The Python API stays the way to
script; a scene file is the way to run without code.
"""

from __future__ import annotations

import math
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10 (the tomli dependency)
    import tomli as tomllib

from .mesh import MeshError, load_surface
from .probes.spec import KINDS, Probe  # noqa: F401  (Probe: what [[probes]] become)

SOLVERS = ("wcsph", "dfsph")  # the solvers a scene file can ask for (taisph.Scene.solver)
COMING = {}  # solvers named but not available yet: name -> message
WALL_MODELS = ("dummy", "lj")
PROBE_KINDS = KINDS  # pressure, elevation, force
KERNELS = ("spline", "gaussian", "wendland")
INTEGRATORS = ("pc", "euler", "eulermid", "eulermom")
UP = 1  # the vertical axis: y, in 2D and 3D
_MISSING = object()  # a key the file does not have

TOP_KEYS = {"name", "description", "dim", "dx", "t_end", "frames", "solver", "kernel", "integrator", "h_factor",
            "dt", "courant", "domain", "physics", "materials", "fluid", "walls", "probes"}
PHYSICS = {"gravity": None, "alpha": 0.1, "delta": 0.1, "xsph": 0.0}  # None: (0, -9.81(, 0))
MATERIAL_KEYS = {"name", "rho0", "c0", "gamma"}
SHAPES = ("box", "mesh", "polygon")
FLUID_KEYS = {*SHAPES, "scale", "translate", "material", "velocity", "hydrostatic"}
WALL_KEYS = {*SHAPES, "scale", "translate", "name", "model", "open_top"}
PROBE_KEYS = {"name", "kind", "at", "to", "walls", "every"}


class SceneFileError(ValueError):
    """A mistake in a scene file: ``str(err)`` names the file, the key and the value."""


@dataclass
class Block:
    """A ``[[fluid]]`` or ``[[walls]]`` entry: its shape (``box`` (lo, hi), or a
    ClosedSurface from ``mesh``/``polygon``) and its settings."""

    key: str  # e.g. "fluid[0]", for messages
    shape: str = "box"  # which key gave the shape: box, mesh or polygon
    value: object = None  # its value in the file, for messages
    box: tuple | None = None
    surface: object = None
    material: int = 0
    velocity: tuple | None = None
    hydrostatic: bool = True
    name: str = ""
    model: str = "dummy"
    open_top: bool = True

    @property
    def bounds(self):
        return self.box if self.box is not None else self.surface.bounds


@dataclass
class SceneSpec:
    """A checked scene file: everything :func:`taisph.scenefile_build.build` needs."""

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
    gravity: tuple
    alpha: float
    delta: float
    xsph: float
    materials: list  # of dicts: name, rho0, c0 (None: default), gamma
    fluid: list
    walls: list
    probes: list
    domain: tuple | None = None  # None: around the geometry
    wall_model: str | None = None  # the one model of all wall groups (None: no walls)
    multiphase: bool = False  # fluids of different rho0: the sharp-interface terms


@dataclass
class RunSettings:
    """What a scene file asks of the run besides the scene: end time, frames, the
    solver, the Courant number (None: the default), the probes, and the particles of
    each wall group (``name -> slice`` of the scene's particle arrays, for force
    probes)."""

    t_end: float
    frames: int
    solver: str
    courant: float | None = None
    probes: list = field(default_factory=list)
    wall_groups: dict = field(default_factory=dict)
    source: Path | None = None


def load(path, overrides: dict | None = None):
    """``(scene, run_settings)`` from the scene file `path` (see :func:`read`)."""
    from .scenefile_build import build

    return build(read(path, overrides))


def read(path, overrides: dict | None = None) -> SceneSpec:
    """Parse and check the scene file `path`. `overrides` (``{"dx": 0.05,
    "physics.alpha": 0.05}``) replace values of the file before the checks (the
    command line's ``--dx``, ``--set``...). Raises :class:`SceneFileError`."""
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
    """Set `key` ("dx", "physics.alpha", "fluid[0].velocity") of the parsed file."""
    match = re.fullmatch(r"(?:([a-z_]+)(?:\[(\d+)\])?\.)?([a-z_0-9]+)", key)
    table = data
    if match and match[1]:
        table = data.setdefault(match[1], {} if match[2] is None else [])
        if match[2] is not None:
            k = int(match[2])
            table = table[k] if isinstance(table, list) and k < len(table) else None
    if not match or not isinstance(table, dict):
        raise SceneFileError(f"{path}: {key} = {value!r} (set on the command line): no such table in the file; "
                             "set KEY, TABLE.KEY or LIST[INDEX].KEY (e.g. dx, physics.alpha, fluid[0].velocity)")
    table[match[3]] = value


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

    def number(self, key, value, positive=False, minimum=None, integer=False):
        if value is _MISSING:
            self.fail(key, value, "required")
        kind = int if integer else (int, float)
        if isinstance(value, bool) or not isinstance(value, kind) or not math.isfinite(value):
            self.fail(key, value, "expected " + ("an integer" if integer else "a number"))
        if positive and value <= 0:
            self.fail(key, value, "must be positive")
        if minimum is not None and value < minimum:
            self.fail(key, value, f"must be at least {minimum}")
        return value if integer else float(value)

    def choice(self, key, value, choices, coming=None):
        if value is _MISSING:
            self.fail(key, value, f"required; one of {', '.join(map(repr, choices))}")
        if coming and value in coming:
            self.fail(key, value, coming[value])
        if value not in choices:
            self.fail(key, value, f"expected one of {', '.join(map(repr, choices))}")
        return value

    def vector(self, key, value, n):
        if not (isinstance(value, list) and len(value) == n):
            self.fail(key, value, f"expected a list of {n} numbers")
        for k, v in enumerate(value):
            self.number(f"{key}[{k}]", v)
        return tuple(float(v) for v in value)

    def box(self, key, value, dim):
        if not (isinstance(value, list) and len(value) == 2):
            self.fail(key, value, f"expected [lo, hi], two lists of {dim} numbers")
        lo, hi = self.vector(f"{key}[0]", value[0], dim), self.vector(f"{key}[1]", value[1], dim)
        if not all(a < b for a, b in zip(lo, hi)):
            self.fail(key, value, "lo must be below hi along every axis")
        return lo, hi

    def courant(self, value):
        value = self.number("courant", value, positive=True)
        if value > 1:
            self.fail("courant", value, "must be at most 1 (dt = courant h / max(c + |v|))")
        return value

    def text(self, key, value):
        if value is _MISSING:
            self.fail(key, value, "required")
        if not isinstance(value, str) or not value:
            self.fail(key, value, "expected a non-empty string")
        return value

    def flag(self, key, value, default):
        if value is _MISSING:
            return default
        if not isinstance(value, bool):
            self.fail(key, value, "expected true or false")
        return value

    # --- the file -------------------------------------------------------------------
    def scene(self, data) -> SceneSpec:
        self.keys("", data, TOP_KEYS)
        get = lambda k: data.get(k, _MISSING)  # noqa: E731
        dim = self.number("dim", get("dim"), integer=True)
        if dim not in (2, 3):
            self.fail("dim", dim, "expected 2 or 3")
        dx = self.number("dx", get("dx"), positive=True)
        physics = data.get("physics", {})
        self.keys("physics", physics, set(PHYSICS))
        gravity = physics.get("gravity", [0.0, -9.81] + [0.0] * (dim - 2))
        spec = SceneSpec(
            path=self.path,
            name=self.text("name", get("name")),
            description=self.text("description", data["description"]) if "description" in data else "",
            dim=dim,
            dx=dx,
            t_end=self.number("t_end", get("t_end"), positive=True),
            frames=self.number("frames", get("frames"), integer=True, minimum=1),
            solver=self.choice("solver", get("solver"), SOLVERS, COMING),
            kernel=self.choice("kernel", data.get("kernel", "spline"), KERNELS),
            integrator=self.choice("integrator", data.get("integrator", "pc"), INTEGRATORS),
            h_factor=self.number("h_factor", data.get("h_factor", 1.3), positive=True),
            dt=self.number("dt", data["dt"], positive=True) if "dt" in data else None,
            courant=self.courant(data["courant"]) if "courant" in data else None,
            gravity=self.vector("physics.gravity", gravity, dim),
            alpha=self.number("physics.alpha", physics.get("alpha", PHYSICS["alpha"]), minimum=0),
            delta=self.number("physics.delta", physics.get("delta", PHYSICS["delta"]), minimum=0),
            xsph=self.number("physics.xsph", physics.get("xsph", PHYSICS["xsph"]), minimum=0),
            materials=self.materials(data.get("materials", [{"name": "water"}])),
            fluid=[],
            walls=[],
            probes=[],
        )
        names = [m["name"] for m in spec.materials]
        spec.fluid = [self.block(f"fluid[{k}]", b, spec, names, FLUID_KEYS) for k, b in enumerate(self.entries("fluid", data))]
        if not spec.fluid:
            self.fail("fluid", data.get("fluid", _MISSING), "a scene needs at least one [[fluid]] block")
        spec.walls = [self.block(f"walls[{k}]", b, spec, names, WALL_KEYS) for k, b in enumerate(self.entries("walls", data))]
        seen = {}
        for k, w in enumerate(spec.walls):
            if w.name in seen:
                self.fail(f"walls[{k}].name", w.name, f"already the name of walls[{seen[w.name]}]")
            seen[w.name] = k
            if w.model != spec.walls[0].model:
                self.fail(f"walls[{k}].model", w.model, f"all wall groups need one model (walls[0] is "
                          f"{spec.walls[0].model!r}): the wall terms act on every wall particle")
        spec.wall_model = spec.walls[0].model if spec.walls else None
        used = sorted({b.material for b in spec.fluid})
        spec.multiphase = len({spec.materials[k]["rho0"] for k in used}) > 1
        if spec.multiphase and spec.wall_model == "dummy":
            self.fail("walls[0].model", "dummy", "fluids of different rho0 ("
                      + ", ".join(spec.materials[k]["name"] for k in used) + ") use the sharp-interface terms "
                      "(Hu & Adams, Colagrossi & Landrini), which take only model = \"lj\" walls")
        if "domain" in data:
            spec.domain = self.box("domain", data["domain"], dim)
        from .scenefile_build import default_domain

        lo, hi = spec.domain or default_domain(spec)
        spec.probes = self.probes(self.entries("probes", data), spec, lo, hi)
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
            c0 = m.get("c0")
            out.append({"name": name, "rho0": self.number(f"{key}.rho0", m.get("rho0", 1000.0), positive=True),
                        "c0": None if c0 is None else self.number(f"{key}.c0", c0, positive=True),
                        "gamma": self.number(f"{key}.gamma", m.get("gamma", 7.0), positive=True)})
        return out

    def block(self, key, entry, spec, material_names, allowed) -> Block:
        self.keys(key, entry, allowed)
        shapes = [s for s in SHAPES if s in entry]
        if len(shapes) != 1:
            self.fail(key, {s: entry[s] for s in shapes} if shapes else _MISSING,
                      "give exactly one of box = [lo, hi], mesh = \"file\" or polygon = [[x, y], ...]")
        shape = shapes[0]
        block = Block(key, shape, entry[shape] if shape != "polygon" else "[...]")
        if shape == "box":
            block.box = self.box(f"{key}.box", entry["box"], spec.dim)
        else:
            block.surface = self.surface(key, shape, entry, spec.dim)
        if "material" in entry:
            name = self.text(f"{key}.material", entry["material"])
            if name not in material_names:
                self.fail(f"{key}.material", name, f"no such material; defined: {', '.join(material_names)}")
            block.material = material_names.index(name)
        if "velocity" in entry:
            block.velocity = self.vector(f"{key}.velocity", entry["velocity"], spec.dim)
        block.hydrostatic = self.flag(f"{key}.hydrostatic", entry.get("hydrostatic", _MISSING), True)
        block.name = self.text(f"{key}.name", entry["name"]) if "name" in entry else key
        block.model = self.choice(f"{key}.model", entry.get("model", "dummy"), WALL_MODELS)
        block.open_top = self.flag(f"{key}.open_top", entry.get("open_top", _MISSING), True)
        if "open_top" in entry and shape != "box":
            self.fail(f"{key}.open_top", entry["open_top"], "only a box (a tank) has a top to leave open")
        return block

    def surface(self, key, shape, entry, dim):
        for k in ("scale", "translate"):
            if k in entry and shape == "box":
                self.fail(f"{key}.{k}", entry[k], "applies to a mesh or polygon, not a box")
        scale = self.number(f"{key}.scale", entry.get("scale", 1.0), positive=True)
        translate = self.vector(f"{key}.translate", entry["translate"], dim) if "translate" in entry else None
        value = entry[shape]
        if shape == "polygon":
            if dim != 2:
                self.fail(f"{key}.polygon", value, "a polygon is 2D; in 3D use mesh = \"file\"")
            if not (isinstance(value, list) and len(value) >= 3):
                self.fail(f"{key}.polygon", value, "expected a list of at least 3 [x, y] vertices")
            source = [self.vector(f"{key}.polygon[{k}]", v, 2) for k, v in enumerate(value)]
            name = "polygon"
        else:
            self.text(f"{key}.mesh", value)
            source = name = self.path.parent / value  # relative to the scene file
        try:
            import numpy as np

            surface = load_surface(np.asarray(source, float) if shape == "polygon" else source, dim=dim, name=str(name))
        except MeshError as err:  # "NAME: problem"; a polygon's name would repeat the key
            self.fail(f"{key}.{shape}", value if shape == "mesh" else "[...]",
                      str(err) if shape == "mesh" else str(err).split(": ", 1)[1])
        return surface.transformed(scale, translate)

    def probes(self, entries, spec, lo, hi):
        out, names = [], {}
        groups = [w.name for w in spec.walls]
        for k, p in enumerate(entries):
            key = f"probes[{k}]"
            self.keys(key, p, PROBE_KEYS)
            name = self.text(f"{key}.name", p.get("name", _MISSING))
            if name in names:
                self.fail(f"{key}.name", name, f"already the name of probes[{names[name]}]")
            names[name] = k
            kind = self.choice(f"{key}.kind", p.get("kind", _MISSING), PROBE_KINDS)
            probe = Probe(name, kind, every=self.number(f"{key}.every", p.get("every", 1), integer=True, minimum=1))
            needs = {"pressure": "at", "elevation": "at", "force": "walls"}[kind]
            for extra in sorted({"at", "to", "walls"} - {needs} - ({"to"} if kind == "pressure" else set())):
                if extra in p:
                    self.fail(f"{key}.{extra}", p[extra], f"a {kind} probe takes {needs}"
                              + (" (and to)" if kind == "pressure" else "") + f", not {extra}")
            if kind == "force":
                probe.walls = self.text(f"{key}.walls", p.get("walls", _MISSING))
                if probe.walls not in groups:
                    self.fail(f"{key}.walls", probe.walls, "no wall group of that name; wall groups: "
                              + (", ".join(groups) or "none"))
            else:
                axes = list(range(spec.dim)) if kind == "pressure" else [a for a in range(spec.dim) if a != UP]
                for point in ("at", "to") if "to" in p else ("at",):
                    value = self.vector(f"{key}.{point}", p.get(point, _MISSING), len(axes))
                    for a, v in zip(axes, value):
                        if not lo[a] <= v <= hi[a]:
                            self.fail(f"{key}.{point}", p[point], f"{'xyz'[a]} = {v:g} is outside the domain "
                                      f"({lo[a]:g} .. {hi[a]:g})")
                    setattr(probe, point, value)
            out.append(probe)
        return out

