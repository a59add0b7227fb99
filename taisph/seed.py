"""The seed's workflow: simulate particle files, and export cases as particle files.

``python -m taisph run INIT [BOUNDARY] TFINAL DT INTEGRATOR KERNEL [options]`` reads
the seed's particle file (and optional boundary file, :mod:`taisph.io.dat`), runs
the seed's physics and writes ``fluid.dat`` (the seed's text output) and ParaView
frames. ``python -m taisph export CASE --dat DIR`` writes a built-in case as those
files plus the exact ``run`` command line that reproduces it (``DIR/run.txt``).

From Python: :func:`load_scene` builds a :class:`taisph.Scene` from files,
:func:`export_scene` writes one, :func:`run_files` is the ``run`` command.
Details, defaults and examples: ``docs/seed.md``.
"""

from __future__ import annotations

import argparse
import math
import shlex
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .io import dat as seedio
from .scene import Material, Scene
from .terms import (ArtificialViscosity, Continuity, ContinuityColagrossi, Gravity, LennardJonesWall,
                    PressureGradient, PressureHuAdams)
from .engine.timestep import fixed_dt
from .eos import tait

INTEGRATOR_WORDS = {"euler": "euler", "eulermid": "eulermid", "eulermom": "eulermom", "pc": "pc",
                    "predictorcorrector": "pc"}
KERNEL_WORDS = ("spline", "gaussian", "wendland")
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
        raise ValueError(f"--{name} has {len(values)} values but --rho0 defines {n} material(s)")
    return values


def _wall_spacing(points: np.ndarray) -> float:
    """Median distance from a wall particle to its nearest wall neighbour (from up to
    512 evenly chosen particles, brute force)."""
    if len(points) < 2:
        raise ValueError("one wall particle gives no spacing; set --lj-cutoff")
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

    `particles` and `boundary` are paths or :class:`taisph.io.dat.ParticleData`.
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
    up = 1  # y is vertical, as in the seed (and taisph's cases)
    rho0 = [float(r) for r in p.rho0]
    if not rho0 or any(not (math.isfinite(r) and r > 0) for r in rho0):
        raise ValueError(f"--rho0 must be positive numbers, got {p.rho0!r}")
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
    g_vec[up] = -9.81
    if p.gravity is not None:
        g_vec = np.asarray(p.gravity, float).ravel()
        if g_vec.shape != (dim,) or not np.all(np.isfinite(g_vec)):
            raise ValueError(f"--gravity needs {dim} finite components, got {p.gravity!r}")
    g = float(np.linalg.norm(g_vec))
    height = float(fluid.position[:, up].max() - all_pos[:, up].min())
    if p.c0 is None:
        v_max = float(np.linalg.norm(fluid.velocity, axis=1).max())
        u_scale = max(math.sqrt(2.0 * g * height), v_max)
        if u_scale <= 0:
            raise ValueError("cannot choose a sound speed: no gravity and no initial velocity; set --c0")
        c0 = [10.0 * u_scale] * n_mat
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
        raise ValueError(f"unknown formulation {formulation!r}; choose seed, multiphase or auto")
    continuity, pressure = FORMULATIONS[formulation]
    terms = [continuity(), pressure(), ArtificialViscosity(alpha=p.alpha, beta=p.beta, eta_factor=p.eta_factor),
             Gravity(gravity=tuple(float(v) for v in g_vec))]
    has_walls = walls is not None and walls.n > 0
    if has_walls:
        r0 = _wall_spacing(walls.position) if p.lj_cutoff is None else float(p.lj_cutoff)
        if p.lj_strength is None:
            if g * height <= 0:
                raise ValueError("cannot choose the wall strength without gravity; set --lj-strength")
            strength = 5.0 * g * height / r0
        else:
            strength = float(p.lj_strength)
        terms.append(LennardJonesWall(lj_strength=strength, lj_cutoff=r0))

    # --- domain and scene --------------------------------------------------------------------
    if p.domain is None:
        lo, hi = all_pos.min(axis=0) - spacing, all_pos.max(axis=0) + spacing
    else:
        box = np.asarray(p.domain, float).ravel()
        if box.shape != (2 * dim,):
            raise ValueError(f"--domain needs {2 * dim} numbers (lo then hi corner), got {p.domain!r}")
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
    from .engine.layout import FLUID, WALL

    scene.validate()
    names = [t.name for t in scene.terms]
    formulation = None
    for key, (cont, pres) in FORMULATIONS.items():
        if names[:2] == [cont.name, pres.name]:
            formulation = key
    expected = ["artificial_viscosity", "gravity"] + (["lennard_jones_wall"] if scene.n_wall else [])
    if formulation is None or names[2:] != expected:
        want = " or ".join(f"[{c.name}, {p.name}, {', '.join(expected)}]" for c, p in FORMULATIONS.values())
        raise ValueError(f"cannot export {scene.name!r}: its terms {names} are not the seed workflow's ({want})")
    if scene.n_wall:
        lj = scene.terms_by_name["lennard_jones_wall"]
        if lj.options != {"p1": 12, "p2": 6}:
            raise ValueError(f"cannot export {scene.name!r}: Lennard-Jones exponents {lj.options} (run uses 12, 6)")
    fluid = scene.kind == FLUID
    wall = scene.kind == WALL
    if np.any(scene.material[wall] != 0):
        raise ValueError(f"cannot export {scene.name!r}: wall particles of a material other than 0")
    rho0 = np.array([m.rho0 for m in scene.materials])
    nearest = np.argmin(np.abs(np.log(scene.density[fluid, None] / rho0[None, :])), axis=1)
    if np.any(nearest != scene.material[fluid]):
        raise ValueError(f"cannot export {scene.name!r}: a particle's material is not the one whose rho0 is "
                         "nearest its density, which is how `run` assigns materials")
    if np.any(np.abs(scene.density[fluid] / rho0[scene.material[fluid]] - 1) > MAX_DENSITY_DEVIATION):
        raise ValueError(f"cannot export {scene.name!r}: a density is more than "
                         f"{100 * MAX_DENSITY_DEVIATION:g} % from its rho0")
    if scene.dim not in seedio.COLUMNS:
        raise ValueError(f"cannot export {scene.name!r}: the seed format is 2D or 3D, not {scene.dim}D")

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


# --- command line ------------------------------------------------------------------------------
RUN_USAGE = "python -m taisph run INIT [BOUNDARY] TFINAL DT INTEGRATOR KERNEL [options]"
RUN_DESCRIPTION = """\
Simulate the seed's particle file INIT (and wall particles from BOUNDARY) until TFINAL
with time step DT, writing OUT/fluid.dat (the seed's text output) and ParaView frames
(OUT/NAME.pvd).

  INTEGRATOR  euler | eulermid (= eulermom) | pc (= predictorcorrector)
  KERNEL      spline | gaussian | wendland

Particle files: first line the particle count, then one line per particle
`index x y u v mass density pressure energy` (3D: `index x y z u v w mass density
pressure energy`), indices from 0. The pressure column is not used (taisph computes
pressure from density with the Tait equation); energy is carried through to fluid.dat
unchanged. Defaults are water's; see docs/seed.md."""
RUN_EPILOG = """\
defaults computed from the files: dx = median (mass/rho0)^(1/dim) of the fluid
particles; H = height of the highest fluid particle above the lowest particle;
c0 = 10 sqrt(2 g H) (or 10x the fastest initial speed); h = 1.3 dx; r0 = the wall
particles' spacing (median nearest-neighbour distance); D = 5 g H / r0.

examples:
  python -m taisph export dam_break_wedge --dat wedge/      # writes files + the run command
  python -m taisph run wedge/particles.dat wedge/boundary.dat 1.5 8e-5 pc spline
  python -m taisph run drop.dat walls.dat 0.5 0.0001 pc gaussian --alpha 0.2"""


def _floats(text: str) -> list:
    try:
        return [float(v) for v in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers, got {text!r}") from None


def _positive(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise argparse.ArgumentTypeError(f"must be a positive number, got {text!r}")
    return v


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        raise UsageError(f"{message}\nusage: {self.format_usage().split(':', 1)[1].strip()}")


class UsageError(ValueError):
    pass


def run_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="python -m taisph run", usage=RUN_USAGE, description=RUN_DESCRIPTION, epilog=RUN_EPILOG,
                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("values", nargs="*", metavar="INIT [BOUNDARY] TFINAL DT INTEGRATOR KERNEL")
    g = p.add_argument_group("fluid (comma-separated lists give one value per material)")
    g.add_argument("--rho0", type=_floats, default=[1000.0],
                   help="reference density per material (default 1000); each particle gets the material "
                        "whose rho0 is nearest its density")
    g.add_argument("--c0", type=_floats, help="sound speed per material (default 10 sqrt(2 g H))")
    g.add_argument("--gamma", type=_floats, default=[7.0], help="Tait exponent (default 7)")
    g.add_argument("--formulation", choices=["auto", "seed", "multiphase"], default="auto",
                   help="seed: eqs. 7-8; multiphase: Colagrossi & Landrini continuity + Hu & Adams pressure; "
                        "auto (default): multiphase if more than one material")
    g = p.add_argument_group("numerics and forces")
    g.add_argument("--h", type=_positive, help="smoothing length (default 1.3 dx)")
    g.add_argument("--alpha", type=float, default=0.1, help="artificial viscosity alpha (default 0.1)")
    g.add_argument("--beta", type=float, default=0.0, help="artificial viscosity beta (default 0)")
    g.add_argument("--eta-factor", type=float, default=0.01, help="eta^2 = eta_factor h^2 (default 0.01)")
    g.add_argument("--gravity", type=_floats, help="gravity vector (default 0,-9.81 in 2D, 0,-9.81,0 in 3D)")
    g.add_argument("--lj-strength", type=float, help="wall force D in m/s^2 (default 5 g H / r0)")
    g.add_argument("--lj-cutoff", type=_positive, help="wall force range r0 (default: the wall spacing)")
    g.add_argument("--dim", type=int, choices=[2, 3], help="insist on 2D (9 columns) or 3D (11 columns)")
    g.add_argument("--domain", type=_floats, help="neighbour grid box lo..hi, e.g. --domain=-1,-1,5,5 "
                                                   "(default: the particles' bounding box)")
    g = p.add_argument_group("output and machine")
    g.add_argument("--frames", type=int, default=20, help="output frames after the initial one (default 20)")
    g.add_argument("--out", type=Path, help="output folder (default out/NAME)")
    g.add_argument("--name", help="name of the run and of its .pvd (default: INIT's file name)")
    g.add_argument("--precision", choices=["f32", "f64"], default="f64")
    g.add_argument("--threads", type=int, help="CPU threads (default: all cores)")
    g.add_argument("--no-progress", action="store_true", help="no progress bar")
    return p


def _positional(values):
    if len(values) not in (5, 6):
        raise UsageError(f"expected INIT [BOUNDARY] TFINAL DT INTEGRATOR KERNEL (5 or 6 values), got "
                         f"{len(values)}: {' '.join(values) or '(none)'}\nusage: {RUN_USAGE}")
    init = values[0]
    boundary = values[1] if len(values) == 6 else None
    tfinal, dt, integrator, kernel = values[-4:]
    out = {}
    for label, text in (("TFINAL", tfinal), ("DT", dt)):
        try:
            out[label] = _positive(text)
        except argparse.ArgumentTypeError as err:
            hint = " (is BOUNDARY misplaced?)" if label == "TFINAL" and len(values) == 5 else ""
            raise UsageError(f"{label} {err}{hint}") from None
    if integrator not in INTEGRATOR_WORDS:
        raise UsageError(f"INTEGRATOR must be one of {', '.join(INTEGRATOR_WORDS)}, got {integrator!r}")
    if kernel not in KERNEL_WORDS:
        raise UsageError(f"KERNEL must be one of {', '.join(KERNEL_WORDS)}, got {kernel!r}")
    if out["DT"] > out["TFINAL"]:
        raise UsageError(f"DT = {dt} is larger than TFINAL = {tfinal}")
    return init, boundary, out["TFINAL"], out["DT"], integrator, kernel


def run_main(argv) -> int:
    """``python -m taisph run ...``; returns the exit code (2: input refused, nothing written)."""
    try:
        args = run_parser().parse_intermixed_args(argv)
        init, boundary, t_end, dt, integrator, kernel = _positional(args.values)
        if args.frames < 1:
            raise UsageError("--frames must be at least 1")
        physics = Physics(rho0=args.rho0, c0=args.c0, gamma=args.gamma, h=args.h, alpha=args.alpha,
                          beta=args.beta, eta_factor=args.eta_factor, gravity=args.gravity,
                          lj_strength=args.lj_strength, lj_cutoff=args.lj_cutoff, formulation=args.formulation,
                          domain=args.domain)
        scene, energy = load_scene(init, boundary, physics, dim=args.dim, kernel=kernel, integrator=integrator,
                                   dt=dt, t_end=t_end, frames=args.frames, name=args.name)
        return run_files(scene, energy, out=args.out, precision=args.precision, threads=args.threads,
                         progress=not args.no_progress)
    except (ValueError, KeyError, TypeError) as err:  # SeedFileError, UsageError are ValueErrors
        print(f"taisph run: error: {err}", file=sys.stderr)
        return 2


def run_files(scene, energy, out=None, precision="f64", threads=None, progress=True) -> int:
    """Simulate a scene from files and write ``OUT/fluid.dat`` and ParaView frames."""
    from .simulation import Simulation

    print(scene.describe())
    print("  pressure column of the input: not used (pressure = Tait EOS of the density); "
          "energy column: carried through unchanged")
    start = time.perf_counter()
    sim = Simulation(scene, precision=precision, threads=threads)  # may refuse: nothing written yet
    print(f"  {sim.runtime.arch}, {sim.runtime.precision}, {sim.runtime.threads} thread(s); dt = {sim.dt:.6g} s; "
          f"ready in {time.perf_counter() - start:.2f} s (kernel compilation included)")
    out = Path("out") / scene.name if out is None else Path(out)
    out.mkdir(parents=True, exist_ok=True)
    fluid = sim.fluid
    ids = sim.ids()[fluid]

    def write_frame(s):
        writer.write(s.time, s.positions()[fluid], s.velocities()[fluid], s.masses()[fluid], s.density()[fluid],
                     s.pressure()[fluid], energy, index=ids)

    from .simulation import SimulationError

    with seedio.OutputWriter(out / "fluid.dat") as writer:
        write_frame(sim)
        try:
            summary = sim.run(scene.t_end, frames=scene.frames, out=out, progress=progress, callback=write_frame)
        except SimulationError as err:  # a guard tripped: frames so far are kept
            print(f"taisph run: {err}", file=sys.stderr)
            print("taisph run: the run was unstable; try a smaller DT (see the stability table in "
                  "docs/seed.md)", file=sys.stderr)
            return 1
    print(f"done: {summary}; seed output {out / 'fluid.dat'} ({writer.frames} frames); "
          f"open {out / (scene.name + '.pvd')} in ParaView")
    problems = health(sim)
    if problems:
        print(f"taisph run: warning: the run was unstable ({'; '.join(problems)}); try a smaller DT "
              "(see the stability table in docs/seed.md)", file=sys.stderr)
        return 1
    return 0


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


def export_main(argv) -> int:
    """``python -m taisph export CASE --dat DIR [--dx DX] [--set NAME=VALUE] ...``."""
    from .cli import main as cli

    p = _Parser(prog="python -m taisph export", usage="python -m taisph export CASE --dat DIR [options]",
                description="Write a built-in case as the seed's particle and boundary files, and print the "
                            "`run` command line that simulates it exactly (also saved as DIR/run.txt).")
    p.add_argument("case")
    p.add_argument("--dat", type=Path, required=True, help="folder for particles.dat, boundary.dat, run.txt")
    p.add_argument("--dx", type=float, help="particle spacing (m)")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE", help="any case parameter")
    p.add_argument("--integrator", choices=list(INTEGRATOR_WORDS), help="time integrator")
    p.add_argument("--kernel", choices=list(KERNEL_WORDS), help="smoothing kernel")
    p.add_argument("--t-end", type=_positive, help="TFINAL of the command (default: the case's)")
    p.add_argument("--dt", type=_positive, help="DT of the command (default: the case's stable step)")
    p.add_argument("--frames", type=int, help="--frames of the command (default: the case's)")
    p.add_argument("--out", help="--out of the command (default out/CASE_from_dat)")
    try:
        args = p.parse_args(argv)
        cases = cli._cases()
        if args.case not in cases:
            raise ValueError(f"unknown case {args.case!r}; cases: {', '.join(cases)}")
        func = cases[args.case]
        params = cli._case_parameters(func)
        kwargs = {}
        for key in ("dx", "integrator", "kernel"):
            value = getattr(args, key)
            if value is not None:
                kwargs[key] = INTEGRATOR_WORDS.get(value, value) if key == "integrator" else value
        for item in args.set:
            key, sep, text = item.partition("=")
            key = key.strip().replace("-", "_")
            if not sep or key not in params:
                raise ValueError(f"--set {item!r}: case {args.case} has parameters {', '.join(params)}")
            kwargs[key] = cli._parse_value(text.strip(), params[key])
        scene = func(**kwargs)
        argv_run = export_scene(scene, args.dat, t_end=args.t_end, dt=args.dt, frames=args.frames, out=args.out)
    except (ValueError, KeyError, TypeError) as err:
        print(f"taisph export: error: {err}", file=sys.stderr)
        return 2
    print(f"wrote {scene.n_fluid} fluid particles to {args.dat / 'particles.dat'}"
          + (f" and {scene.n_wall} wall particles to {args.dat / 'boundary.dat'}" if scene.n_wall else ""))
    print(f"simulate them with (also in {args.dat / 'run.txt'}):")
    print(f"python -m taisph {shlex.join(argv_run)}")
    return 0
