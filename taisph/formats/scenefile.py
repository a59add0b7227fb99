"""Scene files, second half: build the :class:`taisph.Scene` a checked
:class:`SceneSpec` (:mod:`.scenefile_spec`) describes; :func:`load` reads, checks
and builds. A scene file as a case, for sweeps: :func:`scene_factory`.

The physics follows ``cases/dam_break.py`` (:mod:`taisph.scene.water`): Tait water,
c0 = 10 max(sqrt(2 |g| H), |v|max) unless a material sets it (H: the tallest fluid
block), h = h_factor dx, continuity + pressure gradient + Monaghan viscosity + gravity,
dummy walls (Adami et al. 2012: layers of particles dx apart, ceil(support / dx) deep)
or Lennard-Jones walls (particles dx/2 apart, r0 = dx/2, D = 5 max(|g| H, |v|max^2/2)
/ r0), density diffusion (delta-SPH) and XSPH on request, fluid blocks starting in
hydrostatic equilibrium (at ``pressure`` at their top: particles dx^dim of fluid at their
pressure), Morris laminar viscosity on request (``physics.nu``, with the dummy walls'
no-slip velocity). Fluids of different reference densities use the sharp-interface
terms of ``cases/two_fluids.py``, with dummy walls those of ``cases/rising_bubble.py``
(:func:`taisph.scene.phases.two_phase_terms`: the walls join the sums, density diffusion
off unless the file sets ``delta``). A material's dynamic ``viscosity`` adds Hu & Adams'
viscosity per phase (``PhaseViscosity``), ``background_pressure`` the Tait pressure at
rest, and ``physics.surface_tension`` the CSF surface tension (``SurfaceTension``: between
the first material and the others, or at the free surface of a scene of one material).
Open boundaries (``[[open_boundaries]]``,
:mod:`.scenefile_open`) are added after the fluid and the walls, as ``cases/channel.py`` does,
and so are bodies (``[[bodies]]``, :mod:`.scenefile_bodies`: a shape filled with dummy-wall
particles on the lattice, moving as one; a scene with bodies and no walls has dummy walls).

Walls are tanks or obstacles (``kind``). A tank (a box) holds the fluid: its wall layers
lie outside the box, and an open top is an open face of the domain (water may fly up
and fall back, as in ``cases/dam_break.py``). An obstacle (a box, mesh or polygon) is
solid: its layers lie inside it, the outer one dx/2 inside a face on the lattice, and
the fluid it overlaps is removed. Particles that leave the domain elsewhere are removed
and counted (``remove_escaped``, default true) or stop the run.
"""

from __future__ import annotations

import inspect
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..eos import tait
from ..geometry.shapes import box_walls, lattice, solid_layers, wall_layers
from ..geometry.fill import surface_points, volume_points
from ..scene import catalogue, water
from ..scene.model import Material, Scene
from ..scene.names import UP
from ..scene.parameters import checked
from . import scenefile_bodies, scenefile_open
from .scenefile_spec import Probe  # noqa: F401  (what [[probes]] become, for users of this module)
from .scenefile_spec import RANGES, SceneFileError, SceneSpec, default_domain, read, wall_layers_needed


@dataclass
class RunSettings:
    """What a scene file asks of the run besides the scene: end time, frames, the
    solver, the Courant number (None: the default) and the other run controls the file
    sets (``controls``: dt_max, dfsph_tolerance...), the probes, and the particles of
    each wall group (``name -> slice`` of the scene's particle arrays, a body's ids:
    for force probes); `notes`: a line per wall group for the run's header (its kind, its
    particles and, for an obstacle, the fluid particles it removed). `frames` may be 0
    (the initial frame only); the scene's ``frames`` is then 1, as Simulation.run needs."""

    t_end: float
    frames: int
    solver: str
    courant: float | None = None
    probes: list = field(default_factory=list)
    wall_groups: dict = field(default_factory=dict)
    source: Path | None = None
    notes: list = field(default_factory=list)
    controls: dict = field(default_factory=dict)


def load(path, overrides: dict | None = None):
    """``(scene, run_settings)`` from the scene file `path` (see :func:`read`)."""
    return build(read(path, overrides))


def build(spec: SceneSpec):
    """``(scene, RunSettings)`` for a checked spec."""
    dim, dx = spec.dim, spec.dx
    g = np.asarray(spec.gravity)
    g_norm = float(np.linalg.norm(g))
    down = g / g_norm if g_norm > 0 else np.eye(dim)[UP] * -1.0
    fluid, removed = _fluid_points(spec)
    height = max(float(np.ptp(p @ down)) + dx for p in fluid)  # tallest block, to its faces
    speed = max([float(np.linalg.norm(b.velocity)) for b in spec.fluid if b.velocity] + [0.0])
    materials = []
    for k, m in enumerate(spec.materials):
        c0 = m["c0"] or water.sound_speed(g_norm, height, speed)
        if c0 == 0:
            raise SceneFileError(f"{spec.path}: materials[{k}].c0 = (missing): no gravity and no velocity "
                                 "to choose a sound speed from; set c0")
        materials.append(Material(m["name"], rho0=m["rho0"], c0=c0, gamma=m["gamma"], viscosity=m["viscosity"],
                                  background_pressure=m["background_pressure"]))
    open_top = any(w.kind == "tank" and w.open_top for w in spec.walls)
    scene = Scene(name=spec.name, dim=dim, dx=dx, smoothing_length=spec.h_factor * dx,
                  domain=spec.domain or default_domain(spec), materials=materials,
                  terms=_terms(spec, g_norm, height, speed), kernel=spec.kernel, integrator=spec.integrator,
                  dt=spec.dt, t_end=spec.t_end, frames=max(spec.frames, 1), solver=spec.solver,
                  open_faces=("+" + "xyz"[UP],) if open_top else (), remove_escaped=spec.remove_escaped,
                  description=spec.description or f"scene file {spec.path.name}")
    for block, points in zip(spec.fluid, fluid):
        material = materials[block.material]
        density = mass = None
        head = block.hydrostatic and g_norm > 0  # the pressure at its depth below the block's top
        if head or block.pressure:  # (water.hydrostatic_density with the pressure at the top added)
            depth = points @ down - np.min(points @ down) + 0.5 * dx if head else 0.0
            density = tait.density(block.pressure + material.rho0 * g_norm * depth, material.rho0, material.c0,
                                   material.gamma)
            mass = density * dx**dim if block.pressure else None  # as a buffer's particles at its pressure
        scene.add_fluid(points, material=block.material, velocity=block.velocity, density=density, mass=mass)
    groups, notes = {}, _phase_notes(spec)
    for block in spec.walls:
        points = _wall_points(spec, block)
        if len(points) == 0:
            raise SceneFileError(f"{spec.path}: {block.key}.{block.shape} = {block.value!r}: no wall particle fits "
                                 f"in it at dx = {dx:g} (it is thinner than the wall lattice); make it larger or dx "
                                 "smaller")
        groups[block.name] = scene.add_walls(points)
        notes.append(_wall_note(spec, block, groups[block.name], removed.get(block.name, 0)))
    for block in spec.bodies or ():  # after the fluid and the walls, which it must not overlap; a wall group too
        groups[block.name] = scenefile_bodies.add(spec, scene, block, _body_points(spec, block), SceneFileError)
    for zone in spec.open_boundaries or ():  # after the fluid (its face must border it) and the walls
        scenefile_open.add(spec, scene, zone, SceneFileError)
    _check_grid(spec, scene)
    _validate(spec, scene)
    if spec.probes:  # a point probe in a wall's material reads nothing all run: refused, naming its key
        from ..probes.spec import check_inside

        check_inside(list(spec.probes), scene.domain, [f"{spec.path}: probes[{k}]" for k in range(len(spec.probes))],
                     scene=scene, walls=groups)
    settings = RunSettings(spec.t_end, spec.frames, spec.solver, spec.courant, list(spec.probes), groups, spec.path,
                           notes, dict(spec.controls))
    return scene, settings


def _check_grid(spec, scene):
    """Refuse a domain whose neighbour grid would be out of proportion to the particles
    (:func:`taisph.engine.neighbours.grid_problem`, the check the engine makes), naming
    `domain` or, for the default domain, the block farthest from the others."""
    from ..engine.neighbours import grid_cells, grid_problem

    lo = np.minimum(scene.domain[0], scene.position.min(axis=0))
    hi = np.maximum(scene.domain[1], scene.position.max(axis=0))
    problem = grid_problem(grid_cells(lo, hi, scene.support_radius), scene.n, scene.support_radius)
    if not problem:
        return
    if spec.domain is not None:
        key, value = "domain", [list(spec.domain[0]), list(spec.domain[1])]
    else:
        blocks = spec.fluid + spec.walls
        centres = np.array([0.5 * (np.asarray(b.bounds[0]) + np.asarray(b.bounds[1])) for b in blocks])
        far = blocks[int(np.argmax(np.linalg.norm(centres - np.median(centres, axis=0), axis=1)))]
        key, value = f"{far.key}.{far.shape}", far.value
        problem += " (the domain is the box around all blocks: set domain, or move this block nearer the others)"
    raise SceneFileError(f"{spec.path}: {key} = {value!r}: {problem}")


# the keys that choose a term of a built scene (its refusal names that key)
_TERM_KEYS = {"lennard_jones_wall": "walls[0].model", "dummy_walls": "walls[0].model", "gravity": "physics.gravity",
              "artificial_viscosity": "physics.alpha", "density_diffusion": "physics.delta", "xsph": "physics.xsph",
              "continuity_colagrossi": "materials", "pressure_hu_adams": "materials", "riemann": "physics.formulation",
              "laminar_viscosity": "physics.nu", "particle_shifting": "physics.shifting",
              "open_boundaries": "open_boundaries", "rigid_bodies": "bodies",
              "density_relaxation": "physics.density_relaxation", "surface_tension": "physics.surface_tension",
              "phase_viscosity": "materials[].viscosity"}


def _validate(spec, scene):
    """The scene's own checks (:meth:`taisph.Scene.validate`: its terms', the solver's) on the
    built scene; a refusal becomes a SceneFileError naming the file and the key that chose
    the refusing term (else `solver` or `dx`), so an accepted file makes a valid scene."""
    from ..messages import InputError

    try:
        scene.validate()
    except InputError as err:
        key = "solver" if spec.solver == "dfsph" and "dfsph" in str(err) else "dx"
        for t in scene.terms:
            try:
                t.check(scene)
            except InputError:
                key = _TERM_KEYS.get(t.name, "solver")
                break
            except Exception:  # noqa: BLE001 - the scene's own refusal is the one to report
                break
        key = "open_boundaries" if "open boundary '" in str(err) else key
        key = next((k for name, k in _TERM_KEYS.items() if f"the term {name!r}" in str(err)), key)  # a solver's refusal
        viscous = next((k for k in spec.used_materials if spec.materials[k]["viscosity"] > 0), 0)
        values = {"walls[0].model": spec.wall_model, "physics.gravity": list(spec.gravity), "physics.alpha": spec.alpha,
                  "physics.delta": spec.delta, "physics.xsph": spec.xsph, "solver": spec.solver, "dx": spec.dx,
                  "physics.formulation": spec.formulation, "physics.nu": spec.nu, "physics.shifting": spec.shifting,
                  "physics.density_relaxation": spec.density_relaxation,
                  "physics.surface_tension": spec.surface_tension,
                  f"materials[{viscous}].viscosity": spec.materials[viscous]["viscosity"],
                  "open_boundaries": [z.name for z in spec.open_boundaries or ()],
                  "bodies": [b.name for b in spec.bodies or ()],
                  "materials": [m["name"] for m in spec.materials]}
        key = f"materials[{viscous}].viscosity" if key == "materials[].viscosity" else key
        raise SceneFileError(f"{spec.path}: {key} = {values[key]!r}: the scene it makes is refused: {err}") from None


def _wall_note(spec, block, group, removed):
    """The header's line about a wall group: 'wall group NAME: N particles (what)'."""
    dummy = block.model == "dummy"
    if block.kind == "tank":
        where = f"{wall_layers_needed(spec)} layers outside its box" if dummy else "on its faces"
        what = f"tank, {where}, " + ("open at the top" if block.open_top else "closed")
    else:
        where = f"{wall_layers_needed(spec)} layers inside it" if dummy else "on its surface"
        what = f"solid obstacle, {where}; {removed} fluid particles it overlapped removed"
    return f"wall group {block.name}: {group.stop - group.start} particles ({what})"


def _phase_notes(spec) -> list:
    """The header's lines about the phases and their models, for a scene of several materials or one with a
    viscosity, a background pressure or surface tension (a plain scene of water gets none, as before):
    'phases: NAME (rho0 = ..., viscosity ...), ...' and 'models: ...'."""
    used = [spec.materials[k] for k in spec.used_materials]
    pressures = [m["background_pressure"] for m in used]
    if len(used) < 2 and not (spec.viscous or any(pressures) or spec.surface_tension > 0):
        return []
    phases = ", ".join(f"{m['name']} (rho0 = {m['rho0']:g} kg/m^3, viscosity "
                       + (f"{m['viscosity']:g} Pa s)" if m["viscosity"] > 0 else "0)") for m in used)
    if spec.multiphase:
        models = ["sharp interface (Colagrossi & Landrini continuity, Hu & Adams pressure"
                  + (", dummy walls in both)" if spec.wall_model == "dummy" else ")")]
    else:  # one fluid, or materials of one rho0: the one-fluid terms
        models = [] if len(used) < 2 else [f"one rho0: the one-fluid {spec.formulation} continuity and pressure"]
    if spec.viscous:
        models.append("viscosity per phase (Hu & Adams 2006" + (", no-slip walls)" if spec.wall_model == "dummy"
                                                                 else ")"))
    elif spec.nu > 0:
        models.append(f"laminar viscosity nu = {spec.nu:g} m^2/s in every phase")
    if spec.surface_tension > 0:
        where = (f"at {used[0]['name']}'s free surface" if len(used) == 1
                 else f"between {used[0]['name']} and " + ", ".join(m["name"] for m in used[1:]))
        models.append(f"surface tension sigma = {spec.surface_tension:g} N/m {where} (CSF)")
    if any(pressures):
        models.append(f"background pressure {pressures[0]:g} Pa")
    return [f"phases: {phases}", f"models: {', '.join(models)}"]


def _terms(spec, g, height, speed):
    """The scene's terms; gravity `g`, the fluid's `height` and its fastest initial
    `speed` scale the Lennard-Jones force."""
    from ..terms import (XSPH, AdamiWall, ArtificialViscosity, Continuity, ContinuityColagrossi, DensityDiffusion,
                         DensityRelaxation, Gravity, LaminarViscosity, LennardJonesWall, ParticleShifting,
                         PhaseViscosity, PressureGradient, PressureHuAdams, Riemann, SurfaceTension)

    dummy = spec.wall_model == "dummy"
    if spec.formulation == "riemann" and spec.multiphase:
        raise SceneFileError(f"{spec.path}: physics.formulation = 'riemann': fluids of different rho0 need the "
                             "sharp-interface terms (Hu & Adams, Colagrossi & Landrini); the Riemann formulation "
                             "takes one fluid: leave formulation out")
    if spec.formulation == "riemann":
        terms = [Riemann(walls=dummy)]
    elif spec.multiphase:  # with dummy walls they join the sums (cases/rising_bubble.py)
        terms = [ContinuityColagrossi(walls=dummy), PressureHuAdams(walls=dummy)]
    else:
        terms = [Continuity(walls=dummy), PressureGradient(walls=dummy)]
    if spec.alpha > 0:
        terms.append(ArtificialViscosity(alpha=spec.alpha))
    if spec.nu > 0:  # Morris et al. (1997); with dummy walls their no-slip velocity (cases/channel.py, poiseuille.py)
        terms.append(LaminarViscosity(nu=spec.nu, walls=dummy))
    if spec.viscous:  # each material's dynamic viscosity (Hu & Adams 2006); with dummy walls no-slip
        terms.append(PhaseViscosity(walls=dummy))
    if spec.surface_tension > 0:  # CSF: between the first material and the others, or one liquid's free surface
        terms.append(SurfaceTension(sigma=spec.surface_tension, free_surface=len(spec.used_materials) == 1))
    if any(spec.gravity):
        terms.append(Gravity(gravity=spec.gravity))
    if dummy:
        terms.append(AdamiWall(per_phase=spec.multiphase))  # each phase reads its own wall pressure
    elif spec.wall_model == "lj":
        r0 = spec.dx / 2.0
        strength = water.lennard_jones_strength(g, height, r0, speed)
        terms.append(LennardJonesWall(lj_strength=strength, lj_cutoff=r0))
    if spec.delta > 0:
        terms.append(DensityDiffusion(delta=spec.delta, hydrostatic=any(spec.gravity)))  # (the same without gravity)
    if spec.xsph > 0:
        terms.append(XSPH(xsph_eps=spec.xsph))
    if spec.shifting > 0:  # delta-plus-SPH's shifting (Sun et al. 2017), kept off free surfaces by their rule
        terms.append(ParticleShifting(shift_speed=spec.shifting, free_surface=True))
    if spec.density_relaxation > 0:  # the evolved density pulled towards the summed one over tau
        terms.append(DensityRelaxation(relaxation_time=spec.density_relaxation))
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
    """The origin of the scene's lattice: the lower corner of the first tank, else 0.
    Fluid blocks and walls are filled on this lattice (boxes snapped to it)."""
    tanks = [w.box[0] for w in spec.walls if w.kind == "tank"]
    return np.asarray(tanks[0], float) if tanks else np.zeros(spec.dim)


def snap_box(lo, hi, dx, origin):
    """The box [lo, hi] with its faces moved to the nearest planes of the scene's
    lattice (by at most dx/2): a tank's walls then continue the fluid's lattice, dx/2
    outside each face, however long the tank (cf. :func:`box_cells`)."""
    lo, hi, origin = (np.asarray(v, float) for v in (lo, hi, origin))
    snap = lambda v: origin + np.round((v - origin) / dx) * dx  # noqa: E731
    return snap(lo), np.maximum(snap(hi), snap(lo) + dx)


def _fluid_points(spec):
    """The fluid blocks' points, and how many fluid particles each obstacle removed
    (``{name: count}``): an obstacle wins over the fluid it overlaps. A tank's walls
    must not lie on the fluid, and a tank must hold some fluid (in it, or above an
    open top) unless the file says ``kind = "tank"``: a box meant as an obstacle is
    refused, not built as a shell of walls around it."""
    dx, origin = spec.dx, scene_origin(spec)
    fluid = [box_cells(*b.box, dx, origin) if b.box is not None else volume_points(b.surface, dx, origin=origin)
             for b in spec.fluid]
    removed = {}
    for wall in spec.walls:
        if wall.kind == "obstacle":
            inside = [_inside(spec, wall, points) for points in fluid]
            removed[wall.name] = int(sum(np.count_nonzero(k) for k in inside))
            fluid = [points[~k] for points, k in zip(fluid, inside)]
    for block, points in zip(spec.fluid, fluid):
        if len(points) == 0:
            raise SceneFileError(f"{spec.path}: {block.key}.{block.shape} = {block.value!r}: no fluid particle fits "
                                 f"in it at dx = {dx:g} (or an obstacle covers it)")
    for wall in spec.walls:
        if wall.kind == "tank":
            _check_tank(spec, wall, fluid)
    return fluid, removed


def _inside(spec, wall, points):
    """Mask of `points` inside the obstacle `wall` (a box snapped to the lattice, or its surface)."""
    if wall.box is not None:
        lo, hi = snap_box(*wall.box, spec.dx, scene_origin(spec))
        return np.all((points > lo) & (points < hi), axis=1)
    from ..geometry.mesh import contains

    lo, hi = wall.surface.bounds
    mask = np.zeros(len(points), bool)
    near = np.flatnonzero(np.all((points >= lo) & (points <= hi), axis=1))
    mask[near] = contains(wall.surface, points[near])
    return mask


def _check_tank(spec, wall, fluid):
    """Refuse a tank whose wall layers lie on fluid particles, or (unless its kind is
    explicit) that holds none: both are what a box meant as an obstacle builds."""
    dx = spec.dx
    lo, hi = snap_box(*wall.box, dx, scene_origin(spec))
    grow = wall_layers_needed(spec) * dx if wall.model == "dummy" else 0.5 * dx
    top = hi.copy()
    if wall.open_top:
        top[UP] = np.inf  # the open top: fluid above it is in the tank, no wall there
    outer = hi + grow
    outer[UP] = hi[UP] if wall.open_top else outer[UP]
    points = np.concatenate(fluid)
    held = np.all((points > lo) & (points < top), axis=1)
    covered = np.count_nonzero(np.all((points > lo - grow) & (points < outer), axis=1) & ~held)
    obstacle = 'for a solid obstacle (wall layers inside it, the fluid it overlaps removed) set kind = "obstacle"'
    value = f"{spec.path}: {wall.key}.box = {wall.value!r}"
    if covered:
        raise SceneFileError(f"{value}: the walls of this tank, outside the box, lie on {covered} fluid particles; "
                             f"{obstacle}, or move the fluid into the tank")
    if not wall.kind_given and not held.any():
        raise SceneFileError(f"{value}: a tank (its wall layers outside the box) with no fluid in it"
                             + (" or above it" if wall.open_top else "") + f"; {obstacle}; for an empty tank, "
                             'kind = "tank"')


def _body_points(spec, block):
    """A body's particles: the lattice points in its box (the cells whose centres lie in
    it, as a fluid box's) or inside its surface: a solid body, on the fluid's lattice."""
    if block.box is not None:
        return box_cells(*block.box, spec.dx, scene_origin(spec))
    return volume_points(block.surface, spec.dx, origin=scene_origin(spec))


def _wall_points(spec, block):
    dx = spec.dx
    box = snap_box(*block.box, dx, scene_origin(spec)) if block.box is not None else None
    tank = block.kind == "tank"
    if block.model == "dummy":
        layers = wall_layers_needed(spec)
        if box is None:  # an obstacle: the lattice points inside the surface within that depth of it
            return volume_points(block.surface, dx, depth=layers * dx, origin=scene_origin(spec))
        if tank:
            return wall_layers(*box, dx, layers, vertical_axis=UP, open_top=block.open_top)
        return solid_layers(*box, dx, layers)
    if box is None:
        return surface_points(block.surface, dx / 2.0)
    return box_walls(*box, dx / 2.0, vertical_axis=UP, open_top=tank and block.open_top)


# --- a scene file as a case (sweeps) ---------------------------------------------------
# The keys of a scene file a sweep may set or vary, as case parameters: name -> file key
SWEEP_KEYS = {"dx": "dx", "t_end": "t_end", "frames": "frames", "integrator": "integrator", "kernel": "kernel",
              "h_factor": "h_factor", "alpha": "physics.alpha", "delta": "physics.delta", "xsph": "physics.xsph",
              "shifting": "physics.shifting", "density_relaxation": "physics.density_relaxation"}


def scene_factory(path):
    """A case-like function for the scene file `path` (or the name of a shipped one):
    ``factory(dx=..., alpha=...) -> Scene``, its parameters the keys of
    :data:`SWEEP_KEYS` with the file's values as defaults (its ``__signature__``) and
    the file's ranges (:data:`taisph.formats.scenefile_spec.RANGES`) declared with
    :func:`taisph.scene.parameters.checked` (``factory.ranges``), as the built-in cases
    have them: what ``python -m taisph sweep SCENE.toml --vary dx=...`` runs. Raises
    SceneFileError for a bad file."""
    path = catalogue.find_scene_file(str(path)).resolve()
    spec = read(path)
    signature = inspect.Signature([inspect.Parameter(name, inspect.Parameter.POSITIONAL_OR_KEYWORD,
                                                     default=getattr(spec, name)) for name in SWEEP_KEYS])

    def scene(*args, **kwargs):
        values = signature.bind(*args, **kwargs)
        values.apply_defaults()
        return load(path, {SWEEP_KEYS[k]: v for k, v in values.arguments.items()})[0]

    scene.__signature__ = signature
    scene.__name__ = scene.__qualname__ = spec.name
    scene.__doc__ = f"{spec.description or spec.name} (scene file {path})"
    factory = checked(**{name: RANGES[key] for name, key in SWEEP_KEYS.items()})(scene)
    factory.path = path
    factory.courant = spec.courant  # a run setting, not the scene's: the sweep passes it on
    factory.controls = dict(spec.controls)  # likewise the file's dt_max, dfsph_tolerance...
    return factory
