"""The seed's command line: ``run`` simulates the seed's particle files, ``export``
writes a built-in case as those files.

``python -m taisph run INIT [BOUNDARY] TFINAL DT INTEGRATOR KERNEL [options]`` reads
the seed's particle file (and optional boundary file, :mod:`taisph.formats.dat`), builds the
scene with :func:`taisph.formats.seed.load_scene`, and writes ``fluid.dat`` (the seed's text
output) and ParaView frames. ``python -m taisph export CASE --dat DIR`` writes a
built-in case with :func:`taisph.formats.seed.export_scene`, plus the exact ``run`` command line
that reproduces it (``DIR/run.txt``). Details, defaults and examples: ``docs/seed.md``.
"""

from __future__ import annotations

import argparse
import shlex
import sys
import time
from pathlib import Path

from ..formats import seed
from ..formats import dat as seedio
from ..messages import InputError
from ..scene.parameters import finite, positive, viscosity_alpha
from ..scene import catalogue
from ..terms import STANDARD_GRAVITY
from .case import INTERRUPTED, interrupted
from .parser import FRAMES, NON_NEGATIVE, POSITIVE, THREADS, Parser, UsageError, ranged, ranged_list

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

POSITIVES = ranged_list(positive, "positive numbers")
NUMBERS = ranged_list(finite, "numbers")


def run_parser() -> Parser:
    p = Parser(prog="python -m taisph run", usage=RUN_USAGE, description=RUN_DESCRIPTION, epilog=RUN_EPILOG,
               formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("values", nargs="*", metavar="INIT [BOUNDARY] TFINAL DT INTEGRATOR KERNEL")
    g = p.add_argument_group("fluid (comma-separated lists give one value per material)")
    g.add_argument("--rho0", type=POSITIVES, default=[1000.0],
                   help="reference density per material (> 0, default 1000); each particle gets the material "
                        "whose rho0 is nearest its density")
    g.add_argument("--c0", type=POSITIVES, help="sound speed per material (> 0, default 10 sqrt(2 g H))")
    g.add_argument("--gamma", type=POSITIVES, default=[7.0], help="Tait exponent (> 0, default 7)")
    g.add_argument("--formulation", choices=["auto", "seed", "multiphase"], default="auto",
                   help="seed: eqs. 7-8; multiphase: Colagrossi & Landrini continuity + Hu & Adams pressure; "
                        "auto (default): multiphase if more than one material")
    g = p.add_argument_group("numerics and forces")
    g.add_argument("--h", type=POSITIVE, help="smoothing length (> 0, default 1.3 dx)")
    g.add_argument("--alpha", type=ranged(viscosity_alpha, "alpha"), default=0.1,
                   help="artificial viscosity alpha (0 to 2, the cases' range; default 0.1)")
    g.add_argument("--beta", type=NON_NEGATIVE, default=0.0, help="artificial viscosity beta (>= 0, default 0)")
    g.add_argument("--eta-factor", type=POSITIVE, default=0.01, help="eta^2 = eta_factor h^2 (> 0, default 0.01)")
    g.add_argument("--gravity", type=NUMBERS, help=f"gravity vector (default 0,{-STANDARD_GRAVITY} in 2D, "
                        f"0,{-STANDARD_GRAVITY},0 in 3D)")
    g.add_argument("--lj-strength", type=POSITIVE, help="wall force D in m/s^2 (> 0, default 5 g H / r0)")
    g.add_argument("--lj-cutoff", type=POSITIVE, help="wall force range r0 (> 0, default: the wall spacing)")
    g.add_argument("--dim", type=int, choices=[2, 3], help="insist on 2D (9 columns) or 3D (11 columns)")
    g.add_argument("--domain", type=NUMBERS, help="neighbour grid box lo..hi, e.g. --domain=-1,-1,5,5 "
                                                  "(default: the particles' bounding box)")
    g = p.add_argument_group("output and machine")
    g.add_argument("--frames", type=FRAMES, default=20,
                   help="output frames after the initial one (1 to 1e5, default 20)")
    g.add_argument("--out", type=Path, help="output folder (default out/NAME)")
    g.add_argument("--name", help="name of the run and of its .pvd (default: INIT's file name)")
    g.add_argument("--precision", choices=["f32", "f64"], default="f64")
    g.add_argument("--threads", type=THREADS, help="CPU threads (>= 1, default: all cores)")
    g.add_argument("--no-progress", action="store_true",
                   help="no progress display (on a terminal a bar, else a line on stderr every 10 s; "
                        "TAISPH_PROGRESS_EVERY sets the seconds)")
    return p


def _positional(values):
    """INIT, BOUNDARY (or None), TFINAL, DT, INTEGRATOR, KERNEL from the positional words."""
    if len(values) not in (5, 6):
        raise UsageError(f"expected INIT [BOUNDARY] TFINAL DT INTEGRATOR KERNEL (5 or 6 values), got "
                         f"{len(values)}: {' '.join(values) or '(none)'}\nusage: {RUN_USAGE}")
    init = values[0]
    boundary = values[1] if len(values) == 6 else None
    tfinal, dt, integrator, kernel = values[-4:]
    out = {}
    for label, text in (("TFINAL", tfinal), ("DT", dt)):
        try:
            out[label] = positive.parse(text)
        except ValueError:
            out[label] = float("nan")  # not a number: refused below
        if not positive.accepts(out[label]):
            hint = " (is BOUNDARY misplaced?)" if label == "TFINAL" and len(values) == 5 else ""
            raise UsageError(f"{label} must be a number {positive.describe()}, got {text!r}{hint}")
    if integrator not in seed.INTEGRATOR_WORDS:
        raise UsageError(f"INTEGRATOR must be one of {', '.join(seed.INTEGRATOR_WORDS)}, got {integrator!r}")
    if kernel not in seed.KERNEL_WORDS:
        raise UsageError(f"KERNEL must be one of {', '.join(seed.KERNEL_WORDS)}, got {kernel!r}")
    if out["DT"] > out["TFINAL"]:
        raise UsageError(f"DT = {dt} is larger than TFINAL = {tfinal}")
    return init, boundary, out["TFINAL"], out["DT"], integrator, kernel


def run_main(argv) -> int:
    """``python -m taisph run ...``; returns the exit code (2: input refused, nothing written)."""
    try:
        args = run_parser().parse_intermixed_args(argv)
        init, boundary, t_end, dt, integrator, kernel = _positional(args.values)
        physics = seed.Physics(rho0=args.rho0, c0=args.c0, gamma=args.gamma, h=args.h, alpha=args.alpha,
                               beta=args.beta, eta_factor=args.eta_factor, gravity=args.gravity,
                               lj_strength=args.lj_strength, lj_cutoff=args.lj_cutoff,
                               formulation=args.formulation, domain=args.domain)
        scene, energy = seed.load_scene(init, boundary, physics, dim=args.dim, kernel=kernel,
                                        integrator=integrator, dt=dt, t_end=t_end, frames=args.frames,
                                        name=args.name)
        files = [init, boundary] if boundary else [init]
        return run_files(scene, energy, out=args.out, precision=args.precision, threads=args.threads,
                         progress=not args.no_progress, source=dict(seed_files=files))
    except InputError as err:  # SeedFileError, UsageError, ParameterError, a scene refused; others: a traceback
        print(f"taisph run: error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as err:  # Ctrl-C: one line, where the run stopped (taisph.run.record.Interrupted)
        print(f"taisph run: {interrupted(err)}", file=sys.stderr)
        return INTERRUPTED


def run_files(scene, energy, out=None, precision="f64", threads=None, progress=True, source=None) -> int:
    """Simulate a scene from files and write ``OUT/fluid.dat``, ParaView frames and
    ``OUT/run.json`` (:mod:`taisph.run.record`; `source`: the files); return the exit code
    (1: the run was unstable)."""
    from ..run.record import RunRecord, scene_entry
    from ..run.simulation import Simulation, SimulationError

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

    run = dict(t_end=scene.t_end, frames=scene.frames, out=out)
    rec = RunRecord(out, sim, scene_entry(scene, **(source or {})), run, can_checkpoint=False)
    with rec, seedio.OutputWriter(out / "fluid.dat") as writer:
        write_frame(sim)
        try:
            summary = sim.run(scene.t_end, frames=scene.frames, out=out, progress=progress, callback=write_frame)
        except SimulationError as err:  # a guard tripped: frames so far are kept
            rec.finish("stopped by a guard: " + str(err).splitlines()[0])
            print(f"taisph run: {err}", file=sys.stderr)
            print("taisph run: the run was unstable; try a smaller DT (see the stability table in "
                  "docs/seed.md)", file=sys.stderr)
            return 1
        problems = seed.health(sim)
        rec.finish(f"unstable: {'; '.join(problems)}" if problems else "done", summary)
    print(f"done: {summary}; seed output {out / 'fluid.dat'} ({writer.frames} frames); "
          f"open {out / (scene.name + '.pvd')} in ParaView")
    if problems:
        print(f"taisph run: warning: the run was unstable ({'; '.join(problems)}); try a smaller DT "
              "(see the stability table in docs/seed.md)", file=sys.stderr)
        return 1
    return 0


def export_parser() -> Parser:
    p = Parser(prog="python -m taisph export", usage="python -m taisph export CASE --dat DIR [options]",
               description="Write a built-in case as the seed's particle and boundary files, and print the "
                           "`run` command line that simulates it exactly (also saved as DIR/run.txt).")
    p.add_argument("case")
    p.add_argument("--dat", type=Path, required=True, help="folder for particles.dat, boundary.dat, run.txt")
    p.add_argument("--dx", type=POSITIVE, help="particle spacing (m, > 0)")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="any case parameter (see python -m taisph CASE --help)")
    p.add_argument("--integrator", choices=list(seed.INTEGRATOR_WORDS), help="time integrator")
    p.add_argument("--kernel", choices=list(seed.KERNEL_WORDS), help="smoothing kernel")
    p.add_argument("--t-end", type=POSITIVE, help="TFINAL of the command (> 0, default: the case's)")
    p.add_argument("--dt", type=POSITIVE, help="DT of the command (> 0, default: the case's stable step)")
    p.add_argument("--frames", type=FRAMES, help="--frames of the command (>= 1, default: the case's)")
    p.add_argument("--out", help="--out of the command (default out/CASE_from_dat)")
    return p


def export_main(argv) -> int:
    """``python -m taisph export CASE --dat DIR [--dx DX] [--set NAME=VALUE] ...``;
    returns the exit code (2: input refused, nothing written)."""
    try:
        args = export_parser().parse_args(argv)
        integrator = seed.INTEGRATOR_WORDS.get(args.integrator, args.integrator)
        kwargs = catalogue.case_arguments(args.case, args.set, dx=args.dx, integrator=integrator, kernel=args.kernel)
        scene = catalogue.find(args.case)(**kwargs)
        argv_run = seed.export_scene(scene, args.dat, t_end=args.t_end, dt=args.dt, frames=args.frames,
                                     out=args.out)
    except InputError as err:
        print(f"taisph export: error: {err}", file=sys.stderr)
        return 2
    print(f"wrote {scene.n_fluid} fluid particles to {args.dat / 'particles.dat'}"
          + (f" and {scene.n_wall} wall particles to {args.dat / 'boundary.dat'}" if scene.n_wall else ""))
    print(f"simulate them with (also in {args.dat / 'run.txt'}):")
    print(f"python -m taisph {shlex.join(argv_run)}")
    return 0
