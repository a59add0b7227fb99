"""Scene files, second half: build the :class:`taisph.Scene` a checked
:class:`taisph.scenefile.SceneSpec` describes, and run it from the command line
(``python -m taisph SCENE.toml [options]``).

The physics follows ``cases/dam_break.py``: Tait water, c0 = 10 max(sqrt(2 |g| H),
|v|max) unless a material sets it (H: the tallest fluid block), h = h_factor dx,
continuity + pressure gradient + Monaghan viscosity + gravity, dummy walls (Adami
et al. 2012: layers of particles dx apart, ceil(support / dx) deep) or
Lennard-Jones walls (particles dx/2 apart, r0 = dx/2, D = 5 |g| H / r0), density
diffusion (delta-SPH) and XSPH on request, fluid blocks starting in hydrostatic
equilibrium. Fluids of different reference densities use the sharp-interface
terms of ``cases/two_fluids.py``.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

from .eos import tait
from .geometry import box_walls, lattice, wall_layers
from .mesh_fill import surface_points, volume_points
from .scene import Material, Scene
from .engine import smoothing
from .scenefile import UP, RunSettings, SceneFileError, SceneSpec, load, read


def wall_layers_needed(spec: SceneSpec) -> int:
    """Layers of dummy-wall particles that fill the kernel support: ceil(support / dx)."""
    support = smoothing.KERNELS[spec.kernel].support * spec.h_factor * spec.dx
    return math.ceil(support / spec.dx - 1e-9)


def default_domain(spec: SceneSpec):
    """The box around every fluid and wall block, grown by the wall layers and one
    dx, with half the height again above for splashes (as the cases do)."""
    lo = np.min([b.bounds[0] for b in spec.fluid + spec.walls], axis=0)
    hi = np.max([b.bounds[1] for b in spec.fluid + spec.walls], axis=0)
    pad = (wall_layers_needed(spec) + 1) * spec.dx
    top = np.eye(spec.dim)[UP] * 0.5 * (hi[UP] - lo[UP])
    return lo - pad, hi + pad + top


def build(spec: SceneSpec):
    """``(scene, RunSettings)`` for a checked spec."""
    dim, dx = spec.dim, spec.dx
    g = np.asarray(spec.gravity)
    g_norm = float(np.linalg.norm(g))
    down = g / g_norm if g_norm > 0 else np.eye(dim)[UP] * -1.0
    fluid = [_fluid_points(spec, b) for b in spec.fluid]
    height = max(float(np.ptp(p @ down)) + dx for p in fluid)  # tallest block, to its faces
    speed = max([float(np.linalg.norm(b.velocity)) for b in spec.fluid if b.velocity] + [0.0])
    materials = []
    for k, m in enumerate(spec.materials):
        c0 = m["c0"] or 10.0 * max(math.sqrt(2.0 * g_norm * height), speed)
        if c0 == 0:
            raise SceneFileError(f"{spec.path}: materials[{k}].c0 = (missing): no gravity and no velocity "
                                 "to choose a sound speed from; set c0")
        materials.append(Material(m["name"], rho0=m["rho0"], c0=c0, gamma=m["gamma"]))
    scene = Scene(name=spec.name, dim=dim, dx=dx, smoothing_length=spec.h_factor * dx,
                  domain=spec.domain or default_domain(spec), materials=materials,
                  terms=_terms(spec, max(g_norm * height, 0.5 * speed**2)), kernel=spec.kernel, integrator=spec.integrator,
                  dt=spec.dt, t_end=spec.t_end, frames=spec.frames, solver=spec.solver,
                  description=spec.description or f"scene file {spec.path.name}")
    for block, points in zip(spec.fluid, fluid):
        material = materials[block.material]
        density = None
        if block.hydrostatic and g_norm > 0:  # p = rho0 |g| (depth below the block's top)
            depth = points @ down - np.min(points @ down) + 0.5 * dx
            density = tait.density(material.rho0 * g_norm * depth, material.rho0, material.c0, material.gamma)
        scene.add_fluid(points, material=block.material, velocity=block.velocity, density=density)
    groups = {}
    for block in spec.walls:
        groups[block.name] = scene.add_walls(_wall_points(spec, block))
    settings = RunSettings(spec.t_end, spec.frames, spec.solver, spec.courant, list(spec.probes), groups, spec.path)
    return scene, settings


def _terms(spec, head):
    """The scene's terms; `head` (m^2/s^2, g H or v^2/2) scales the Lennard-Jones force."""
    from .terms import (AdamiWall, ArtificialViscosity, Continuity, ContinuityColagrossi, DensityDiffusion, Gravity,
                        LennardJonesWall, PressureGradient, PressureHuAdams, XSPH)

    dummy = spec.wall_model == "dummy"
    if spec.multiphase:
        terms = [ContinuityColagrossi(), PressureHuAdams()]
    else:
        terms = [Continuity(walls=dummy), PressureGradient(walls=dummy)]
    if spec.alpha > 0:
        terms.append(ArtificialViscosity(alpha=spec.alpha))
    if any(spec.gravity):
        terms.append(Gravity(gravity=spec.gravity))
    if dummy:
        terms.append(AdamiWall())
    elif spec.wall_model == "lj":
        r0 = spec.dx / 2.0
        terms.append(LennardJonesWall(lj_strength=5.0 * head / r0, lj_cutoff=r0))
    if spec.delta > 0:
        terms.append(DensityDiffusion(delta=spec.delta))
    if spec.xsph > 0:
        terms.append(XSPH(xsph_eps=spec.xsph))
    return terms


def box_cells(lo, hi, dx, origin) -> np.ndarray:
    """The points ``origin + (k + 1/2) dx`` (the scene's lattice) in the box [lo, hi),
    so a box that is not a whole number of cells of that lattice is filled to
    within dx/2 of each face, and fluid next to a tank is on the tank's lattice."""
    lo, hi, origin = (np.asarray(v, float) for v in (lo, hi, origin))
    first = np.ceil((lo - origin) / dx - 0.5 - 1e-9)
    last = np.ceil((hi - origin) / dx - 0.5 - 1e-9) - 1
    return lattice(origin + first * dx, origin + (last + 1) * dx, dx)


def scene_origin(spec: SceneSpec) -> np.ndarray:
    """The origin of the scene's lattice: the lower corner of the first box of walls
    (a tank), else 0. Fluid blocks and mesh walls are filled on this lattice."""
    tanks = [w.box[0] for w in spec.walls if w.box is not None]
    return np.asarray(tanks[0], float) if tanks else np.zeros(spec.dim)


def snap_box(lo, hi, dx, origin):
    """The box [lo, hi] with its faces moved to the nearest planes of the scene's
    lattice (by at most dx/2): a tank's walls then continue the fluid's lattice, dx/2
    outside each face, however long the tank (cf. :func:`box_cells`)."""
    lo, hi, origin = (np.asarray(v, float) for v in (lo, hi, origin))
    snap = lambda v: origin + np.round((v - origin) / dx) * dx  # noqa: E731
    return snap(lo), np.maximum(snap(hi), snap(lo) + dx)


def _fluid_points(spec, block):
    dx = spec.dx
    origin = scene_origin(spec)
    points = box_cells(*block.box, dx, origin) if block.box is not None else volume_points(block.surface, dx,
                                                                                            origin=origin)
    for wall in spec.walls:  # an obstacle wins over the fluid it overlaps
        if wall.surface is not None and len(points):
            from .mesh import contains

            lo, hi = wall.surface.bounds
            near = np.flatnonzero(np.all((points >= lo) & (points <= hi), axis=1))
            points = np.delete(points, near[contains(wall.surface, points[near])], axis=0)
    if len(points) == 0:
        raise SceneFileError(f"{spec.path}: {block.key}.{block.shape} = {block.value!r}: no fluid particle fits in it at dx = {dx:g} "
                             "(or a wall mesh covers it)")
    return points


def _wall_points(spec, block):
    dx = spec.dx
    if block.model == "dummy":
        layers = wall_layers_needed(spec)
        if block.box is not None:
            lo, hi = snap_box(*block.box, dx, scene_origin(spec))
            return wall_layers(lo, hi, dx, layers, vertical_axis=UP, open_top=block.open_top)
        return volume_points(block.surface, dx, depth=layers * dx, origin=scene_origin(spec))
    if block.box is not None:
        return box_walls(*snap_box(*block.box, dx, scene_origin(spec)), dx / 2.0, vertical_axis=UP,
                         open_top=block.open_top)
    return surface_points(block.surface, dx / 2.0)


# --- a scene file as a case (sweeps) ---------------------------------------------------
# The keys of a scene file a sweep may set or vary, as case parameters: name -> file key
SWEEP_KEYS = {"dx": "dx", "t_end": "t_end", "frames": "frames", "integrator": "integrator", "kernel": "kernel",
              "h_factor": "h_factor", "alpha": "physics.alpha", "delta": "physics.delta", "xsph": "physics.xsph"}


def scene_factory(path):
    """A case-like function for the scene file `path` (or the name of a shipped one):
    ``factory(dx=..., alpha=...) -> Scene``, its parameters the keys of
    :data:`SWEEP_KEYS` with the file's values as defaults and their ranges declared
    (``factory.ranges``), as the built-in cases have them: what ``python -m taisph
    sweep SCENE.toml --vary dx=...`` runs. Raises SceneFileError for a bad file."""
    from .parameters import at_least, checked, integer, known_integrator, known_kernel, positive, smoothing_factor

    path = find_scene_file(str(path)).resolve()
    spec = read(path)

    def scene(dx, t_end, frames, integrator, kernel, h_factor, alpha, delta, xsph):
        values = dict(dx=dx, t_end=t_end, frames=frames, integrator=integrator, kernel=kernel, h_factor=h_factor,
                      alpha=alpha, delta=delta, xsph=xsph)
        return load(path, {SWEEP_KEYS[k]: v for k, v in values.items()})[0]

    scene.__defaults__ = (spec.dx, spec.t_end, spec.frames, spec.integrator, spec.kernel, spec.h_factor,
                          spec.alpha, spec.delta, spec.xsph)
    scene.__name__ = scene.__qualname__ = spec.name
    scene.__doc__ = f"{spec.description or spec.name} (scene file {path})"
    scene.path = path
    scene.courant = spec.courant  # a run setting, not the scene's: the sweep passes it on
    return checked(dx=positive, t_end=positive, frames=integer(at_least=1), integrator=known_integrator,
                   kernel=known_kernel, h_factor=smoothing_factor, alpha=at_least(0), delta=at_least(0),
                   xsph=at_least(0))(scene)


# --- command line ----------------------------------------------------------------------
def cases_folder() -> Path:
    import taisph

    return Path(taisph.cases.__file__).resolve().parent


def find_scene_file(name: str) -> Path:
    """`name` as given, or else the scene file of that name shipped in cases/."""
    path = Path(name)
    if not path.exists() and (cases_folder() / path.name).is_file():
        return cases_folder() / path.name
    return path


def list_scene_files(out=None):
    """Print the scene files shipped in cases/ (for ``python -m taisph list``)."""
    out = sys.stdout if out is None else out
    files = sorted(cases_folder().glob("*.toml"))
    if not files:
        return
    print("scene files (python -m taisph NAME.toml; copy one from cases/ to make your own):", file=out)
    width = max(len(f.name) for f in files)
    for f in files:
        try:
            spec = read(f)
            about = spec.description.splitlines()[0] if spec.description else spec.name
        except SceneFileError as err:
            about = f"(does not load: {err})"
        print(f"  {f.name:<{width}}  {about}", file=out)


def _set_value(text: str):
    """A --set value as TOML (numbers, lists, true/false, "strings"), else the text."""
    from .scenefile import tomllib

    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def main(argv) -> int:
    """``python -m taisph SCENE.toml [options]``: the case options where they apply;
    ``--set KEY=VALUE`` sets any key of the file (``--set physics.alpha=0.05``)."""
    from .cli.main import _guarded, build_parser

    parser = build_parser(target_help="the scene file (a path, or the name of one shipped in cases/)")
    parser.usage = "python -m taisph SCENE.toml [options]"
    parser.description = ("Run a scene file (schema: docs/scenes.md). The options below replace the file's values "
                          "where they apply; --set KEY=VALUE sets any key of the file, as TOML: "
                          "--set physics.alpha=0.05, --set 'fluid[0].velocity=[1.0, 0.0]'.")
    args = parser.parse_args(argv)
    return _guarded(run_file, find_scene_file(args.case[0]), args)


def run_file(path: Path, args) -> int:
    from .cli.main import command_line_probes, output_folder, probe_notes, probe_writers, simulate

    overrides = {k: getattr(args, k) for k in ("dx", "t_end", "frames", "integrator", "kernel", "dt", "courant", "solver")
                 if getattr(args, k) is not None}
    for item in args.set:
        if "=" not in item:
            raise ValueError(f"--set expects KEY=VALUE, got {item!r}")
        key, text = item.split("=", 1)
        overrides[key.strip()] = _set_value(text.strip())
    scene, settings = load(path, overrides)
    notes = [f"wall group {name}: {group.stop - group.start} particles" for name, group in settings.wall_groups.items()]
    probes = list(settings.probes) + command_line_probes(args, scene.dim, settings.wall_groups)
    names = [p.name for p in probes]
    for name in names:
        if names.count(name) > 1:
            raise ValueError(f"--probe: two probes named {name!r} (the scene file's and --probe's names must differ)")
    out = output_folder(scene, args)
    writers = probe_writers(probes, settings.wall_groups, out)
    notes += probe_notes(probes, out)
    try:
        return simulate(scene, args, t_end=settings.t_end, frames=settings.frames, notes=notes, writers=writers,
                        controls={"courant": settings.courant} if settings.courant else None)
    finally:
        for writer in writers:
            writer.close()
