"""Command line: ``python -m taisph CASE [options]``, ``list`` and ``resume``; the seed's
``run`` and ``export`` commands are in :mod:`taisph.cli.dat`, ``sweep`` in
:mod:`taisph.cli.sweep`."""

from __future__ import annotations

import argparse
import inspect
import sys
import time
from pathlib import Path

import numpy as np

from ..engine.layout import WALL
from . import cases
from .parser import COURANT, FRACTION, FRAMES, NON_NEGATIVE, POSITIVE, SKIN, THREADS, Parser

USAGE = """\
python -m taisph CASE [options]     run a built-in case (e.g. dam_break)
python -m taisph CASE --help        the case's description and parameters
python -m taisph list               list the built-in cases
python -m taisph resume DIR         continue a run from its checkpoint folder
python -m taisph sweep CASE --vary NAME=v1,v2 --out DIR   runs of every combination on a Dask cluster (sweep --help)
python -m taisph run INIT [BOUNDARY] TFINAL DT INTEGRATOR KERNEL   the seed's files (run --help)
python -m taisph export CASE --dat DIR    a case as the seed's files (export --help)"""

EPILOG = """\
examples:
  python -m taisph dam_break                       # defaults; frames in out/dam_break
  python -m taisph dam_break --dx 0.01 --t-end 1 --frames 20 --out run1
  python -m taisph dam_break --set alpha=0.05 --integrator euler --dt 5e-5
  python -m taisph dam_break --solver dfsph           # incompressible: DFSPH (docs/dfsph.md)
Open OUT/CASE.pvd in ParaView (File > Open, Apply) to see the time series."""


def build_parser(case: str | None = None, target_help: str = "case name, or 'list'") -> Parser:
    """The parser of ``python -m taisph CASE [options]``; with a case, its help lists the
    case's parameters with their defaults and ranges, and its effects. `target_help`
    describes the positional argument (a case, or a scene file)."""
    description = "taisph: smoothed particle hydrodynamics on Taichi."
    if case:
        description = f"{case}: {inspect.getdoc(cases.find(case))}"
    parser = Parser(
        prog="python -m taisph" + (f" {case}" if case else ""),
        usage=None if case else USAGE,
        description=description,
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("case", nargs="?" if case else 1, help=target_help)
    g = parser.add_argument_group("resolution and time")
    g.add_argument("--dx", type=POSITIVE, help="particle spacing (m, > 0); sets the resolution")
    g.add_argument("--t-end", type=POSITIVE, help="simulated end time (s, > 0)")
    g.add_argument("--dt", type=POSITIVE, help="fixed time step (s, > 0); default: adaptive (CFL, force and viscous limits)")
    g.add_argument("--frames", type=FRAMES, help="frames to write after the initial one (>= 1; default: the case's)")
    g.add_argument("--courant", type=COURANT, metavar="C",
                   help="Courant number of the adaptive step dt = C h / max(c + |v|) (0 < C <= 1; default 0.25)")
    g = parser.add_argument_group("numerics")
    g.add_argument("--solver", choices=["wcsph", "dfsph"],
                   help="wcsph: weakly compressible (the default); dfsph: divergence-free SPH, an implicit "
                        "incompressible pressure solve (docs/dfsph.md); also --set solver=NAME")
    g.add_argument("--integrator", choices=["euler", "eulermid", "eulermom", "pc"], help="time integrator (wcsph)")
    g.add_argument("--kernel", choices=["spline", "gaussian", "wendland"], help="smoothing kernel")
    g.add_argument("--precision", choices=["f32", "f64"], default="f64", help="float precision (default f64)")
    g.add_argument("--neighbour-skin", type=SKIN, metavar="F",
                   help="reuse neighbour lists until a particle moves F/2 support radii (F in [0, 2]; default 0: "
                        "walk the cells every step, as fast on CPUs; see docs/performance.md)")
    g.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="set any case parameter (see CASE --help); repeatable")
    g = parser.add_argument_group("guards and restarts")
    g.add_argument("--max-density-error", type=NON_NEGATIVE, default=0.2,
                   help="stop when |rho/rho0 - 1| exceeds this fraction (>= 0; 0: off; default 0.2)")
    g.add_argument("--remove-escaped", action="store_true",
                   help="remove (and count) particles that leave the domain instead of stopping, and particles "
                        "whose density leaves the range, up to --max-out-of-range")
    g.add_argument("--max-out-of-range", type=FRACTION, default=0.001, metavar="F",
                   help="with --remove-escaped (or a case that removes escaped particles, as dam_break): the "
                        "fraction of the fluid particles that may be removed for their density before the next "
                        "one stops the run (0 to 1; default 0.001)")
    g.add_argument("--checkpoint-every", type=FRAMES, metavar="K",
                   help="write a checkpoint to OUT/checkpoint every K frames (K >= 1; resume with "
                        "'resume OUT/checkpoint')")
    g.add_argument("--deterministic", action="store_true",
                   help="serial cell sort at every size: bit-for-bit reproducible runs and restarts")
    g = parser.add_argument_group("output and machine")
    g.add_argument("--out", type=Path, help="output folder (default: out/CASE)")
    g.add_argument("--no-output", action="store_true", help="write no frames (benchmarking)")
    g.add_argument("--probe", action="append", default=[], metavar="KIND:NAME:WHERE[:EVERY]",
                   help="sample a probe into OUT/probes.csv (repeatable): pressure:P1:3.22,0.16 (a point), "
                        "elevation:gauge:0.6:10 (a vertical line at x = 0.6, every 10 steps), force:F:walls "
                        "(all wall particles; a scene file's wall group names); docs/scenes.md")
    g.add_argument("--arch", default="cpu", choices=["cpu", "cuda", "vulkan"], help="Taichi backend (default cpu)")
    g.add_argument("--threads", type=THREADS, help="CPU threads (>= 1; default: all cores)")
    g.add_argument("--no-progress", action="store_true", help="no progress bar")
    if case:
        try:
            effects = "\n".join(f"  {t.describe()}" for t in cases.find(case)().terms)
        except Exception as err:  # a case that cannot build with defaults still gets --help
            effects = f"  (could not build the default scene: {err})"
        parser.epilog = ("case parameters (--set NAME=VALUE), default and allowed range:\n"
                         + cases.describe_parameters(case)
                         + "\n\neffects (compiled in):\n" + effects + "\n\n" + EPILOG)
    return parser


def list_cases(out=None):
    out = sys.stdout if out is None else out
    registry = cases.registry()
    width = max(len(n) for n in registry)
    print("built-in cases (python -m taisph CASE --help for parameters):", file=out)
    for name, func in registry.items():
        doc = (inspect.getdoc(sys.modules[func.__module__]) or inspect.getdoc(func) or "").splitlines()[0]
        print(f"  {name:<{width}}  {doc}", file=out)
    from ..scenefile_build import list_scene_files

    list_scene_files(out)


def main(argv=None) -> int:
    """``python -m taisph ...``; returns the exit code (0 done, 1 an unstable seed run,
    2 input refused with nothing written, 3 a run stopped by a guard)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv or argv[0] in ("-h", "--help"):
        build_parser().print_help()
        return 0
    command = argv[0]
    if command == "list":
        list_cases()
        return 0
    if command == "resume":
        return resume(argv[1:])
    if command == "sweep":  # parameter sweeps on a Dask cluster: taisph/cli/sweep.py
        from .sweep import main as sweep_main

        return sweep_main(argv[1:])
    if command.endswith(".toml"):  # a scene file: taisph/scenefile.py
        from ..scenefile_build import main as run_scene_file

        return run_scene_file(argv)
    if command in ("run", "export"):  # the seed's file workflow
        from . import dat

        return (dat.run_main if command == "run" else dat.export_main)(argv[1:])
    if command not in cases.registry():
        print(f"taisph: unknown case or command {command!r}. Cases: {', '.join(cases.registry())}; "
              "commands: list, run, export, resume, sweep", file=sys.stderr)
        return 2
    return _guarded(run_case, command, argv)


def _guarded(func, *args) -> int:
    """Run a command; a refused input (nothing built or written) is exit code 2, a run
    stopped by a guard is 3, each with its message on stderr."""
    from ..simulation import SimulationError

    try:
        return func(*args)
    except SimulationError as err:
        print(f"taisph: {err}", file=sys.stderr)
        return 3
    except (ValueError, KeyError, TypeError, FileNotFoundError) as err:  # ParameterError, UsageError: ValueErrors
        print(f"taisph: error: {err}", file=sys.stderr)
        return 2


def run_case(name: str, argv) -> int:
    """``python -m taisph CASE [options]``: every option and parameter is checked (and
    the scene built) before anything is compiled or written."""
    args = build_parser(name).parse_args(argv)
    settings, solver = cases.solver_setting(args.set, args.solver)
    kwargs = cases.case_arguments(name, settings, dx=args.dx, integrator=args.integrator, kernel=args.kernel)
    scene = cases.find(name)(**kwargs)
    if solver is not None:
        scene.solver = solver
    if args.dt is not None:
        scene.dt = args.dt
    walls = {"walls": np.flatnonzero(scene.kind == WALL)}
    probes = command_line_probes(args, scene.dim, walls)
    out = output_folder(scene, args)
    writers = probe_writers(probes, walls, out)
    try:
        return simulate(scene, args, writers=writers, notes=probe_notes(probes, out))
    finally:
        for writer in writers:
            writer.close()


def command_line_probes(args, dim, walls) -> list:
    """The ``--probe`` options as probes, checked (wall groups included) before anything is built."""
    from ..probes import parse

    probes = [parse(text, dim) for text in args.probe]
    for p in probes:
        if p.kind == "force" and p.walls not in walls:
            raise ValueError(f"--probe force:{p.name}:{p.walls}: no wall group {p.walls!r}; wall groups: "
                             + (", ".join(walls) or "none"))
    return probes


def probe_notes(probes, out) -> list:
    """The line a run prints about its probes."""
    if not probes:
        return []
    if out is None:
        return ["probes: not sampled (--no-output)"]
    return [f"probes to {Path(out) / 'probes.csv'}: "
            + ", ".join(f"{p.name} ({p.kind}{f', every {p.every} steps' if p.every > 1 else ''})" for p in probes)]


def probe_writers(probes, walls, out) -> list:
    """A :class:`taisph.probes.Probes` writer into OUT/probes.csv, if there are probes and an output folder."""
    if not probes or out is None:
        return []
    from ..probes import Probes

    return [Probes(probes, walls=walls, path=Path(out) / "probes.csv")]


def output_folder(scene, args) -> Path | None:
    """Where a run writes (``--out``, default ``out/NAME``); None with ``--no-output``."""
    return None if args.no_output else (args.out or Path("out") / scene.name)


def simulate(scene, args, t_end=None, frames=None, notes=(), writers=(), controls=None) -> int:
    """Simulate `scene` as the case options `args` say (output folder, guards, machine,
    progress), print its description (and `notes`), the set-up time and the summary.
    `controls`: further simulation controls (a scene file's ``courant``); ``--courant``
    overrides."""
    import taisph

    if args.neighbour_skin is not None:
        scene.neighbour_skin = args.neighbour_skin
    out = output_folder(scene, args)
    print(scene.describe())
    for line in notes:
        print(f"  {line}")
    start = time.perf_counter()
    controls = dict(controls or {})
    if args.courant is not None:
        controls["courant"] = args.courant
    sim = taisph.Simulation(scene, arch=args.arch, precision=args.precision, threads=args.threads,
                            max_density_error=args.max_density_error, remove_escaped=args.remove_escaped or None,
                            max_out_of_range=args.max_out_of_range,
                            deterministic=args.deterministic, **controls)
    step = (f"fixed dt = {sim.dt:.3g} s" if sim.controls.dt
            else f"adaptive dt (Courant {sim.controls.courant:g}; first {sim.dt:.3g} s)")
    print(f"  {sim.runtime.arch}, {sim.runtime.precision}, {sim.runtime.threads} thread(s); {step}; "
          f"ready in {time.perf_counter() - start:.2f} s (kernel compilation included)")
    summary = sim.run(args.t_end if t_end is None else t_end, frames=args.frames if frames is None else frames,
                      out=out, progress=not args.no_progress, checkpoint_every=args.checkpoint_every,
                      writers=writers)
    where = f"; open {Path(summary.out) / (scene.name + '.pvd')} in ParaView" if summary.out else ""
    print(f"done: {summary}{where}")
    return 0


def resume(argv) -> int:
    """``python -m taisph resume OUT/checkpoint``: continue a checkpointed run."""
    return _guarded(_resume, argv)


def _resume(argv) -> int:
    parser = Parser(prog="python -m taisph resume",
                    description="Continue a run from a checkpoint folder written by --checkpoint-every "
                                "(OUT/checkpoint).")
    parser.add_argument("checkpoint", type=Path, help="checkpoint folder")
    parser.add_argument("--threads", type=THREADS, help="CPU threads (>= 1; default: all cores)")
    parser.add_argument("--no-progress", action="store_true")
    args = parser.parse_args(argv)
    from ..simulation import Simulation

    if not (args.checkpoint / "meta.pickle").exists():
        raise FileNotFoundError(f"{args.checkpoint} is not a checkpoint folder (no meta.pickle)")
    sim = Simulation.from_checkpoint(args.checkpoint, threads=args.threads)
    meta = sim.checkpoint_meta
    print(f"resuming {sim.scene.name} at step {sim.steps}, t = {sim.time:.6g} s "
          f"(to t = {meta['t_end']:.6g} s, {meta['frames_left']} frames left)")
    if not meta["frames_left"]:
        print("nothing left to do")
        return 0
    writer_state = meta["writer"]
    out = meta["out"]
    summary = sim.run(meta["t_end"], frames=meta["frames_left"], out=out, progress=not args.no_progress,
                      checkpoint_every=1, _writer_state=writer_state)
    print(f"done: {summary}")
    return 0
