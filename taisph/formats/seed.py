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
from ..terms import ArtificialViscosity, Continuity, ContinuityColagrossi, Gravity, LennardJonesWall, PressureGradient, PressureHuAdams
from ..engine.timestep import fixed_dt
from ..eos import tait

# the seed's words for integrators and kernels (the `run` command's INTEGRATOR, KERNEL)
INTEGRATOR_WORDS = {**{name: name for name in INTEGRATORS}, "predictorcorrector": "pc"}
KERNEL_WORDS = KERNELS
FORMULATIONS = {
    "seed": (Continuity, PressureGradient),  # seed eqs. 7-8
    "multiphase": (ContinuityColagrossi, PressureHuAdams),  # Colagrossi & Landrini, Hu & Adams
}
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


def _wall_spacing(points: np.ndarray) -> float:
    """Median distance from a wall particle to its nearest wall neighbour (from up to
    512 evenly chosen particles, brute force)."""
    if len(points) < 2:
        raise InputError("one wall particle gives no spacing; set --lj-cutoff")
    sample = points[:: max(1, len(points) // 512)]
    best = np.full(len(sample), np.inf)
    for start in range(0, len(points), 4096):
        block = points[start:start + 4096]
        d = np.linalg.norm(sample[:, None, :] - block[None, :, :], axis=2)
        d[d == 0] = np.inf
        best = np.minimum(best, d.min(axis=1))
    return float(np.median(best))


def load_scene(particles, boundary=None, physics: Physics | None = None, dim: int | None = None,
               kernel: str = "spline", integrator: str = "pc", dt: float | None = None, t_end: float = 1.0,
               frames: int = 20, name: str | None = None):
    """A :class:`taisph.Scene` from a seed particle file (and boundary file).

    `particles` and `boundary` are paths or :class:`taisph.formats.dat.ParticleData`.
    Returns ``(scene, energy)``: ``energy`` is the particle file's energy column (in
    index order), which taisph does not evolve (the liquid's energy is decoupled,
    seed sec. 2) and writes back unchanged. The pressure column is not used:
    pressure follows from density through the Tait equation of state.

    Fluid particle k (index k in the file) is taisph particle id k; wall particles
    follow. Wall particles move rigidly with the velocity of the boundary file.
    """
    p = physics or Physics()
    fluid = particles if isinstance(particles, seedio.ParticleData) else seedio.read_particles(particles, dim)
    dim = fluid.dim
    walls = None
    if boundary is not None:
        walls = boundary if isinstance(boundary, seedio.ParticleData) else seedio.read_particles(
            boundary, dim, what="boundary file", allow_empty=True)
        if walls.dim != dim:
            raise seedio.SeedFileError(walls.path, f"the boundary file is {walls.dim}D but the particle file "
                                                   f"{fluid.path} is {dim}D")
    rho0 = [float(r) for r in p.rho0]
    if not rho0 or any(not (math.isfinite(r) and r > 0) for r in rho0):
        raise InputError(f"--rho0 must be positive numbers, got {p.rho0!r}")
    n_mat = len(rho0)

    # --- materials: each particle gets the reference density nearest its density -------
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

    # --- length and speed scales for the defaults ---------------------------------------------
    spacing = float(np.median((fluid.mass / np.asarray(rho0)[material]) ** (1.0 / dim)))
    all_pos = fluid.position if walls is None or walls.n == 0 else np.concatenate([fluid.position, walls.position])
    g_vec = np.zeros(dim)
    g_vec[UP] = -9.81  # y is vertical, as in the seed (and taisph's cases)
    if p.gravity is not None:
        g_vec = np.asarray(p.gravity, float).ravel()
        if g_vec.shape != (dim,) or not np.all(np.isfinite(g_vec)):
            raise InputError(f"--gravity needs {dim} finite components, got {p.gravity!r}")
    g = float(np.linalg.norm(g_vec))
    height = float(fluid.position[:, UP].max() - all_pos[:, UP].min())
    if p.c0 is None:
        v_max = float(np.linalg.norm(fluid.velocity, axis=1).max())
        c0 = water.sound_speed(g, height, v_max)
        if c0 <= 0:
            raise InputError("cannot choose a sound speed: no gravity and no initial velocity; set --c0")
        c0 = [c0] * n_mat
    else:
        c0 = _per_material(p.c0, n_mat, "c0")
    gamma = _per_material(p.gamma, n_mat, "gamma")
    materials = [Material(f"fluid{k}" if n_mat > 1 else "water", rho0=rho0[k], c0=float(c0[k]), gamma=float(gamma[k]))
                 for k in range(n_mat)]
    for m in materials:
        m.check()
    h = p.h_factor * spacing if p.h is None else float(p.h)

    # --- terms ----------------------------------------------------------------------------------
    formulation = p.formulation
    if formulation == "auto":
        formulation = "multiphase" if n_mat > 1 else "seed"
    if formulation not in FORMULATIONS:
        raise InputError(f"unknown formulation {formulation!r}; choose seed, multiphase or auto")
    continuity, pressure = FORMULATIONS[formulation]
    terms = [continuity(), pressure(), ArtificialViscosity(alpha=p.alpha, beta=p.beta, eta_factor=p.eta_factor),
             Gravity(gravity=tuple(float(v) for v in g_vec))]
    has_walls = walls is not None and walls.n > 0
    if has_walls:
        r0 = _wall_spacing(walls.position) if p.lj_cutoff is None else float(p.lj_cutoff)
        if p.lj_strength is None:
            if g * height <= 0:
                raise InputError("cannot choose the wall strength without gravity; set --lj-strength")
            strength = water.lennard_jones_strength(g, height, r0)
        else:
            strength = float(p.lj_strength)
        terms.append(LennardJonesWall(lj_strength=strength, lj_cutoff=r0))

    # --- domain and scene --------------------------------------------------------------------
    if p.domain is None:
        lo, hi = all_pos.min(axis=0) - spacing, all_pos.max(axis=0) + spacing
    else:
        box = np.asarray(p.domain, float).ravel()
        if box.shape != (2 * dim,):
            raise InputError(f"--domain needs {2 * dim} numbers (lo then hi corner), got {p.domain!r}")
        lo, hi = box[:dim], box[dim:]
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
    if has_walls:
        scene.add_walls(walls.position, mass=walls.mass, density=walls.density, velocity=walls.velocity)
    scene.validate()
    return scene, fluid.energy.copy()


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
            problems.append(f"{int(outside.sum())} fluid particle(s) outside the box {lo.tolist()} .. {hi.tolist()}")
    return problems
