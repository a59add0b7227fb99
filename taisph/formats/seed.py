"""The seed's workflow as scenes: build a scene from the seed's particle files, write a
scene as those files, and judge the health of a run from them.

:func:`load_scene` builds a :class:`taisph.Scene` from a particle file and an optional
boundary file (read by :mod:`taisph.formats.dat`) with :class:`Physics` (defaults computed
from the particles), :func:`export_scene` writes a scene as those files plus the
``run`` command line that simulates it exactly, and :func:`health` lists what is wrong
with a run's fluid state. The commands ``python -m taisph run`` and ``export`` are
in :mod:`taisph.cli.dat`. Details, defaults and examples: ``docs/seed.md``.
"""

from __future__ import annotations

import math
import shlex
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import dat as seedio
from ..messages import InputError
from ..scene import water
from ..scene.model import Material, Scene
from ..scene.names import INTEGRATORS, KERNELS, UP
from ..scene.parameters import particle_spacing
from ..terms import (STANDARD_GRAVITY, ArtificialViscosity, Continuity, ContinuityColagrossi, Gravity, LennardJonesWall,
                     PressureGradient, PressureHuAdams)
from ..engine import smoothing
from ..engine.timestep import fixed_dt
from ..eos import tait

# the seed's words for integrators and kernels (the `run` command's INTEGRATOR, KERNEL)
INTEGRATOR_WORDS = {**{name: name for name in INTEGRATORS}, "predictorcorrector": "pc"}
KERNEL_WORDS = KERNELS
FORMULATIONS = {
    "seed": (Continuity, PressureGradient),  # seed eqs. 7-8
    "multiphase": (ContinuityColagrossi, PressureHuAdams),  # Colagrossi & Landrini, Hu & Adams
}
KERNEL_SUPPORT = {name: smoothing.KERNELS[name].support for name in KERNELS}  # support radius / h
# A particle whose density is further than this from its material's rho0 is refused:
# the Tait pressure would be huge (10 % is (1.1^7 - 1) B ~ 0.95 B, with B = rho0 c0^2 / 7).
MAX_DENSITY_DEVIATION = 0.1


@dataclass
class Physics:
    """Physical and numerical parameters of a run from files. ``None`` means "the
    default computed from the particles" (see :func:`load_scene` and docs/seed.md)."""

    rho0: list = field(default_factory=lambda: [1000.0])
    c0: list | None = None
    gamma: list = field(default_factory=lambda: [7.0])
    h: float | None = None
    h_factor: float = 1.3
    alpha: float = 0.1
    beta: float = 0.0
    eta_factor: float = 0.01
    gravity: tuple | None = None
    lj_strength: float | None = None
    lj_cutoff: float | None = None
    formulation: str = "auto"
    domain: tuple | None = None


def _per_material(values, n, name):
    values = list(values)
    if len(values) == 1:
        return values * n
    if len(values) != n:
        raise InputError(f"--{name} has {len(values)} values but --rho0 defines {n} material(s)")
    return values


def _wall_spacing(points: np.ndarray, path) -> float:
    """Median distance from a wall particle to its nearest wall neighbour (from up to
    512 evenly chosen particles, brute force); `path`: the boundary file, for messages."""
    if len(points) < 2:
        raise InputError(f"{path}: one wall particle gives no spacing to take the Lennard-Jones cut-off r0 "
                         "from; give the walls' particles or set --lj-cutoff")
    sample = points[:: max(1, len(points) // 512)]
    best = np.full(len(sample), np.inf)
    for start in range(0, len(points), 4096):
        block = points[start:start + 4096]
        d = np.linalg.norm(sample[:, None, :] - block[None, :, :], axis=2)
        d[d == 0] = np.inf
        best = np.minimum(best, d.min(axis=1))
    spacing = float(np.median(best))
    if not math.isfinite(spacing):
        raise InputError(f"{path}: the wall particles all lie on one point: no spacing "
                         "to take the Lennard-Jones cut-off r0 from; set --lj-cutoff")
    return spacing


def load_scene(particles, boundary=None, physics: Physics | None = None, dim: int | None = None,
               kernel: str = "spline", integrator: str = "pc", dt: float | None = None, t_end: float = 1.0,
               frames: int = 20, name: str | None = None):
    """A :class:`taisph.Scene` from a seed particle file (and boundary file).

    Every refusal (:class:`taisph.messages.InputError`) names the file it concerns: a
    :class:`taisph.formats.dat.SeedFileError` the file and line, others start with the
    particle file's name (or the boundary file's).

    `particles` and `boundary` are paths or :class:`taisph.formats.dat.ParticleData`.
    Returns ``(scene, energy)``: ``energy`` is the particle file's energy column (in
    index order), which taisph does not evolve (the liquid's energy is decoupled,
    seed sec. 2) and writes back unchanged. The pressure column is not used:
    pressure follows from density through the Tait equation of state.

    Fluid particle k (index k in the file) is taisph particle id k; wall particles
    follow. Wall particles move rigidly with the velocity of the boundary file.
    """
    p = physics or Physics()
    fluid, walls = _read_files(particles, boundary, dim)
    dim = fluid.dim
    rho0 = [float(r) for r in p.rho0]
    if not rho0 or any(not (math.isfinite(r) and r > 0) for r in rho0):
        raise InputError(f"--rho0 must be positive numbers, got {p.rho0!r}")
    material = _nearest_material(fluid, rho0)
    spacing = _spacing(fluid, rho0, material, dim)
    all_pos = fluid.position if walls is None or walls.n == 0 else np.concatenate([fluid.position, walls.position])
    scales = _scales(fluid, walls, all_pos, _gravity_vector(p.gravity, dim))
    materials = _materials(p, fluid, rho0, scales)
    h = p.h_factor * spacing if p.h is None else float(p.h)
    terms = _terms(p, len(rho0), fluid, walls, scales, kernel, spacing)
    lo, hi = _domain(p.domain, all_pos, spacing, dim)
    _check_grid(fluid, walls, lo, hi, h, kernel)
    scene = Scene(
        name=name or Path(fluid.path).stem,
        dim=dim,
        dx=spacing,
        smoothing_length=h,
        domain=(lo, hi),
        materials=materials,
        terms=terms,
        kernel=kernel,
        integrator=INTEGRATOR_WORDS.get(integrator, integrator),
        dt=dt,
        t_end=t_end,
        frames=frames,
        description=f"from {fluid.path}" + (f" and {walls.path}" if walls is not None else ""),
    )
    scene.add_particles(fluid.position, kind="fluid", mass=fluid.mass, density=fluid.density,
                        velocity=fluid.velocity)
    scene.material[: fluid.n] = material
    if walls is not None and walls.n > 0:
        scene.add_walls(walls.position, mass=walls.mass, density=walls.density, velocity=walls.velocity)
    try:
        scene.validate()
    except InputError as err:  # (options such as --lj-cutoff, --h): the files it was built from
        files = str(fluid.path) + (f" and {walls.path}" if walls is not None else "")
        raise InputError(f"{files}: the scene they make is refused: {err}") from None
    return scene, fluid.energy.copy()


def _read_files(particles, boundary, dim) -> tuple:
    """(fluid, walls): the particle file's and the boundary file's particles (walls None
    without a boundary file), read unless given as ParticleData; both of one dimension."""
    fluid = particles if isinstance(particles, seedio.ParticleData) else seedio.read_particles(particles, dim)
    walls = None
    if boundary is not None:
        walls = boundary if isinstance(boundary, seedio.ParticleData) else seedio.read_particles(
            boundary, fluid.dim, what="boundary file", allow_empty=True)
        if walls.dim != fluid.dim:
            raise seedio.SeedFileError(walls.path, f"the boundary file is {walls.dim}D but the particle file "
                                                   f"{fluid.path} is {fluid.dim}D")
    return fluid, walls


def _nearest_material(fluid, rho0: list) -> np.ndarray:
    """Each fluid particle's material: the one whose reference density is nearest its
    density, which must lie within :data:`MAX_DENSITY_DEVIATION` of it."""
    ratio = np.log(fluid.density[:, None] / np.asarray(rho0)[None, :])
    material = np.argmin(np.abs(ratio), axis=1).astype(np.int32)
    deviation = np.abs(fluid.density / np.asarray(rho0)[material] - 1.0)
    worst = int(np.argmax(deviation))
    if deviation[worst] > MAX_DENSITY_DEVIATION:
        given = ", ".join(f"{r:g}" for r in rho0)
        raise seedio.SeedFileError(
            fluid.path,
            f"density {fluid.density[worst]:g} is {100 * deviation[worst]:.0f} % from the nearest reference "
            f"density rho0 = {rho0[material[worst]]:g} (given: --rho0 {given}); weakly compressible SPH needs "
            f"densities within {100 * MAX_DENSITY_DEVIATION:g} % of rho0. Give each fluid's reference density, "
            f"e.g. --rho0 1000,{fluid.density[worst]:g}", int(fluid.line[worst]))
    return material


def _spacing(fluid, rho0: list, material: np.ndarray, dim: int) -> float:
    """The particle spacing: the median of the particles' (mass / rho0)^(1/dim), each of
    which must be within the range of a spacing."""
    each = (fluid.mass / np.asarray(rho0)[material]) ** (1.0 / dim)  # each particle's spacing
    outside = np.flatnonzero(~((each >= particle_spacing.low) & (each <= particle_spacing.high)))
    if outside.size:
        r = int(outside[0])
        raise seedio.SeedFileError(
            fluid.path, f"mass {fluid.mass[r]:g} at density {rho0[material[r]]:g} is a particle spacing "
            f"(mass / rho0)^(1/{dim}) of {each[r]:.3g} m; it must be {particle_spacing.describe()} m",
            int(fluid.line[r]))
    return float(np.median(each))


def _gravity_vector(gravity, dim: int) -> np.ndarray:
    """--gravity's vector, checked; by default standard gravity along -y."""
    g_vec = np.zeros(dim)
    g_vec[UP] = -STANDARD_GRAVITY  # y is vertical, as in the seed (and taisph's cases)
    if gravity is not None:
        g_vec = np.asarray(gravity, float).ravel()
        if g_vec.shape != (dim,) or not np.all(np.isfinite(g_vec)):
            raise InputError(f"--gravity needs {dim} finite components, got {gravity!r}")
    return g_vec


@dataclass
class _Scales:
    """The scales the defaults are computed from: gravity (its vector and magnitude), the
    fluid's column height above the lowest particle, its fastest initial speed, and the
    start of the message refusing a still, flat fluid."""

    g_vec: np.ndarray
    g: float
    height: float
    v_max: float
    flat: str


def _scales(fluid, walls, all_pos, g_vec) -> _Scales:
    """The :class:`_Scales` of the particles `all_pos` (fluid and walls) under `g_vec`."""
    height = float(fluid.position[:, UP].max() - all_pos[:, UP].min())
    axis = "xyz"[UP]
    flat = (f"{fluid.path}: the fluid's column height is 0 (the highest fluid particle, {axis} = "
            f"{fluid.position[:, UP].max():g}, is not above the lowest particle"
            + (f" of {fluid.path} and {walls.path}" if walls is not None and walls.n else "") + ") and no "
            "particle moves")
    return _Scales(g_vec, float(np.linalg.norm(g_vec)), height, float(np.linalg.norm(fluid.velocity, axis=1).max()),
                   flat)


def _materials(p: Physics, fluid, rho0: list, scales: _Scales) -> list:
    """The materials, checked: rho0, c0 (by default from the scales, the same for all) and gamma."""
    n_mat = len(rho0)
    if p.c0 is None:
        c0 = water.sound_speed(scales.g, scales.height, scales.v_max)
        if c0 <= 0:
            if scales.g > 0:
                raise InputError(f"{scales.flat}: no speed to choose the sound speed from (10 sqrt(2 g H)); "
                                 "set --c0")
            raise InputError(f"{fluid.path}: cannot choose a sound speed: no gravity and no initial velocity; "
                             "set --c0")
        c0 = [c0] * n_mat
    else:
        c0 = _per_material(p.c0, n_mat, "c0")
    gamma = _per_material(p.gamma, n_mat, "gamma")
    materials = [Material(f"fluid{k}" if n_mat > 1 else "water", rho0=rho0[k], c0=float(c0[k]),
                          gamma=float(gamma[k]))
                 for k in range(n_mat)]
    for m in materials:
        m.check()
    return materials


def _terms(p: Physics, n_mat: int, fluid, walls, scales: _Scales, kernel: str, spacing: float) -> list:
    """The terms: the formulation's continuity and pressure terms, artificial viscosity,
    gravity, and with wall particles the Lennard-Jones wall force."""
    formulation = p.formulation
    if formulation == "auto":
        formulation = "multiphase" if n_mat > 1 else "seed"
    if formulation not in FORMULATIONS:
        raise InputError(f"unknown formulation {formulation!r}; choose seed, multiphase or auto")
    continuity, pressure = FORMULATIONS[formulation]
    terms = [continuity(), pressure(), ArtificialViscosity(alpha=p.alpha, beta=p.beta, eta_factor=p.eta_factor),
             Gravity(gravity=tuple(float(v) for v in scales.g_vec))]
    if walls is not None and walls.n > 0:
        terms.append(_wall_force(p, fluid, walls, scales, kernel, spacing))
    return terms


def _wall_force(p: Physics, fluid, walls, scales: _Scales, kernel: str, spacing: float) -> LennardJonesWall:
    """The Lennard-Jones wall force: its cut-off r0 (by default the walls' spacing, which
    must be within the kernel support) and strength D (by default 5 g H / r0, or without a
    head 5 v^2 / (2 r0) of the fastest initial speed)."""
    g, height, v_max, flat = scales.g, scales.height, scales.v_max, scales.flat
    r0 = _wall_spacing(walls.position, walls.path) if p.lj_cutoff is None else float(p.lj_cutoff)
    support = KERNEL_SUPPORT.get(kernel, math.inf) * (p.h_factor * spacing if p.h is None else float(p.h))
    if p.lj_cutoff is None and not r0 <= support:
        raise InputError(f"{walls.path}: the wall particles are {r0:g} m apart (the median distance to the "
                         f"nearest), farther than the kernel support radius {support:g} m of the fluid "
                         f"(spacing {spacing:g} m from the masses of {fluid.path}): the fluid would pass "
                         "between them; place them closer or set --lj-cutoff")
    if p.lj_strength is None:
        if g * height <= 0 and v_max > 0:  # no head: the fastest initial speed's (D = 5 v^2 / (2 r0))
            strength = water.lennard_jones_strength(g, height, r0, v_max)
        elif g * height <= 0:
            if g > 0:
                raise InputError(f"{flat}: no height to choose the wall strength from (5 g H / r0); "
                                 "set --lj-strength")
            raise InputError(f"{fluid.path}: cannot choose the wall strength: no gravity and no initial "
                             "velocity; set --lj-strength")
        else:
            strength = water.lennard_jones_strength(g, height, r0)
    else:
        strength = float(p.lj_strength)
    return LennardJonesWall(lj_strength=strength, lj_cutoff=r0)


def _domain(domain, all_pos: np.ndarray, spacing: float, dim: int) -> tuple:
    """(lo, hi) of the neighbour grid: --domain's box, or the particles' grown by a spacing."""
    if domain is None:
        return all_pos.min(axis=0) - spacing, all_pos.max(axis=0) + spacing
    box = np.asarray(domain, float).ravel()
    if box.shape != (2 * dim,):
        raise InputError(f"--domain needs {2 * dim} numbers (lo then hi corner), got {domain!r}")
    return box[:dim], box[dim:]


def _check_grid(fluid, walls, lo, hi, h, kernel):
    """Refuse particles spread so far apart (for their spacing) that the neighbour grid
    would be out of proportion to them (:func:`taisph.engine.neighbours.grid_problem`,
    the engine's check), naming the file and line of the particle farthest from the others."""
    from ..engine.neighbours import grid_cells, grid_problem

    support = KERNEL_SUPPORT.get(kernel)
    if support is None or not (math.isfinite(h) and h > 0):
        return  # Scene.validate refuses these
    support *= h
    parts = [fluid] + ([walls] if walls is not None and walls.n else [])
    position = np.concatenate([d.position for d in parts])
    lo, hi = np.minimum(lo, position.min(axis=0)), np.maximum(hi, position.max(axis=0))
    problem = grid_problem(grid_cells(lo, hi, support), len(position), support)
    if not problem:
        return
    far = int(np.argmax(np.linalg.norm(position - np.median(position, axis=0), axis=1)))
    data = parts[0] if far < fluid.n else parts[1]
    r = far if far < fluid.n else far - fluid.n
    where = ", ".join(f"{a} = {v:g}" for a, v in zip("xyz", data.position[r]))
    raise seedio.SeedFileError(data.path, f"the particles span {', '.join(f'{v:g}' for v in hi - lo)} m (this "
                                          f"particle, at {where}, is the farthest from the others): {problem}",
                               int(data.line[r]))


# --- export ------------------------------------------------------------------------------------
def _fmt(v) -> str:
    return repr(float(v))


def _list(values) -> str:
    return ",".join(_fmt(v) for v in values)


def _term_value(scene, term_name, key):
    return scene.terms_by_name[term_name].param_values(scene.dim)[key]


def export_scene(scene, folder, t_end: float | None = None, dt: float | None = None, frames: int | None = None,
                 out: str | None = None) -> list[str]:
    """Write `scene` as seed files in `folder` (``particles.dat``, ``boundary.dat`` if
    it has walls) and ``run.txt``; return the ``run`` command line (argv after
    ``python -m taisph``) that simulates exactly this scene.

    Raises ValueError (writing nothing) if the scene uses something the files and
    the command's options cannot express."""
    from ..engine.layout import FLUID, WALL

    scene.validate()
    names = [t.name for t in scene.terms]
    formulation = None
    for key, (cont, pres) in FORMULATIONS.items():
        if names[:2] == [cont.name, pres.name]:
            formulation = key
    expected = ["artificial_viscosity", "gravity"] + (["lennard_jones_wall"] if scene.n_wall else [])
    if formulation is None or names[2:] != expected:
        want = " or ".join(f"[{c.name}, {p.name}, {', '.join(expected)}]" for c, p in FORMULATIONS.values())
        raise InputError(f"cannot export {scene.name!r}: its terms {names} are not the seed workflow's ({want})")
    if scene.n_wall:
        lj = scene.terms_by_name["lennard_jones_wall"]
        if lj.options != {"p1": 12, "p2": 6}:
            raise InputError(f"cannot export {scene.name!r}: Lennard-Jones exponents {lj.options} (run uses 12, 6)")
    fluid = scene.kind == FLUID
    wall = scene.kind == WALL
    if np.any(scene.material[wall] != 0):
        raise InputError(f"cannot export {scene.name!r}: wall particles of a material other than 0")
    rho0 = np.array([m.rho0 for m in scene.materials])
    nearest = np.argmin(np.abs(np.log(scene.density[fluid, None] / rho0[None, :])), axis=1)
    if np.any(nearest != scene.material[fluid]):
        raise InputError(f"cannot export {scene.name!r}: a particle's material is not the one whose rho0 is "
                         "nearest its density, which is how `run` assigns materials")
    if np.any(np.abs(scene.density[fluid] / rho0[scene.material[fluid]] - 1) > MAX_DENSITY_DEVIATION):
        raise InputError(f"cannot export {scene.name!r}: a density is more than "
                         f"{100 * MAX_DENSITY_DEVIATION:g} % from its rho0")
    if scene.dim not in seedio.COLUMNS:
        raise InputError(f"cannot export {scene.name!r}: the seed format is 2D or 3D, not {scene.dim}D")

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    order = np.flatnonzero(fluid)  # id order
    mats = scene.materials
    mat = scene.material[order]
    pressure = np.array([tait.pressure(r, mats[k].rho0, mats[k].c0, mats[k].gamma)
                         for r, k in zip(scene.density[order], mat)])
    init = seedio.write_particles(folder / "particles.dat", scene.position[order], scene.velocity[order],
                                  scene.mass[order], scene.density[order], pressure)
    files = [str(init)]
    if scene.n_wall:
        w = np.flatnonzero(wall)
        seedio.write_particles(folder / "boundary.dat", scene.position[w], scene.velocity[w], scene.mass[w],
                               scene.density[w], np.zeros(len(w)))
        files.append(str(folder / "boundary.dat"))
    t_end = scene.t_end if t_end is None else t_end
    dt = (scene.dt if scene.dt is not None else fixed_dt(scene)) if dt is None else dt
    frames = scene.frames if frames is None else frames
    av = scene.terms_by_name["artificial_viscosity"]
    argv = ["run", *files, _fmt(t_end), _fmt(dt), scene.integrator, scene.kernel,
            "--rho0", _list(m.rho0 for m in mats), "--c0", _list(m.c0 for m in mats),
            "--gamma", _list(m.gamma for m in mats),
            "--h", _fmt(scene.smoothing_length),
            "--alpha", _fmt(av.values["alpha"]), "--beta", _fmt(av.values["beta"]),
            "--eta-factor", _fmt(av.values["eta_factor"]),
            f"--gravity={_list(_term_value(scene, 'gravity', 'gravity'))}",
            "--formulation", formulation]
    if scene.n_wall:
        argv += ["--lj-strength", _fmt(_term_value(scene, "lennard_jones_wall", "lj_strength")[0]),
                 "--lj-cutoff", _fmt(_term_value(scene, "lennard_jones_wall", "lj_cutoff")[0])]
    argv += [f"--domain={_list(np.concatenate(scene.domain))}", "--frames", str(frames),
             "--name", scene.name, "--out", out or f"out/{scene.name}_from_dat"]
    (folder / "run.txt").write_text(
        f"# {scene.name} exported by taisph; this command simulates exactly the case:\n"
        f"python -m taisph {shlex.join(argv)}\n")
    return argv


# --- health of a run ---------------------------------------------------------------------------
def health(sim, box=None, max_density_deviation: float = MAX_DENSITY_DEVIATION) -> list[str]:
    """What is wrong with a simulation's fluid state (an empty list if nothing):
    non-finite positions, velocities or densities; a density further than
    `max_density_deviation` from its material's rho0; with `box` = (lo, hi), fluid
    particles outside it. The stability table of docs/seed.md uses this test."""
    fluid = sim.fluid
    x, v, rho = sim.positions()[fluid], sim.velocities()[fluid], sim.density()[fluid]
    problems = []
    bad = ~(np.isfinite(x).all(axis=1) & np.isfinite(v).all(axis=1) & np.isfinite(rho))
    if bad.any():
        problems.append(f"{int(bad.sum())} fluid particle(s) with a non-finite state")
    rho0 = np.array([m.rho0 for m in sim.scene.materials])[sim.materials()[fluid]]
    with np.errstate(invalid="ignore"):
        dev = np.abs(rho / rho0 - 1.0)
    if np.any(dev[~bad] > max_density_deviation):
        problems.append(f"density up to {100 * np.nanmax(dev[~bad]):.3g} % from rho0 "
                        f"(bound {100 * max_density_deviation:g} %)")
    if box is not None:
        lo, hi = (np.asarray(b, float) for b in box)
        outside = ~bad & ~np.all((x >= lo) & (x <= hi), axis=1)
        if outside.any():
            problems.append(f"{int(outside.sum())} fluid particle(s) outside the box "
                            f"{lo.tolist()} .. {hi.tolist()}")
    return problems
