"""``python -m taisph CASE [options]``: the options of a run (:func:`build_parser`), and
what every run command shares: the exit codes of refused input and stopped runs
(:func:`guarded`), probes from ``--probe``, the output folder and the run itself
(:func:`simulate`), used by the case and scene-file commands.

Exit codes: 0 done; 2 input refused (:class:`taisph.messages.InputError`: a parameter,
option, scene or file a user can correct; one line ``taisph: error: MESSAGE``, nothing
built or written); 3 a run stopped by a guard (:class:`taisph.SimulationError`); 1 any
other exception, with its traceback: a fault of taisph, not of the input."""

from __future__ import annotations

import argparse
import collections
import dataclasses
import inspect
import os
import sys
import time
from pathlib import Path

import numpy as np

from ..engine.layout import WALL
from ..engine.dfsph.method import DFSPH_COURANT, DFSPH_FORCE_FACTOR
from ..engine.timestep import SETTABLE, Controls
from ..messages import InputError
from ..scene import catalogue
from ..scene.names import INTEGRATORS, KERNELS, SOLVERS
from .case_help import describe_parameters, case_examples
from .parser import (COURANT, END_TIME, EVERY, FRACTION, NON_NEGATIVE, OUTPUT_FRAMES, POSITIVE, SKIN, THREADS,
                     Parser, UsageError, ranged)

# the simulation's own defaults (taisph.engine.timestep.Controls), for the options that set them
CONTROLS = {f.name: f.default for f in dataclasses.fields(Controls)}

USAGE = """\
python -m taisph CASE [options]     run a built-in case (e.g. dam_break)
python -m taisph CASE --help        the case's description and parameters
python -m taisph list               list the built-in cases
python -m taisph resume DIR [--t-end T]   continue a run from its checkpoint folder (resume --help)
python -m taisph sweep CASE --vary NAME=v1,v2 --out DIR   runs of every combination on a Dask cluster (sweep --help)
python -m taisph run INIT [BOUNDARY] TFINAL DT INTEGRATOR KERNEL   the seed's files (run --help)
python -m taisph export CASE --dat DIR    a case as the seed's files (export --help)
python -m taisph plot OUT           figures of a run's output folder (plot --help)
python -m taisph OUT                how the run in the output folder OUT was made (OUT/run.json)
python -m taisph --version          taisph's, Taichi's and Python's versions"""

EPILOG = """\
examples:
  python -m taisph dam_break                       # defaults; frames in out/dam_break
  python -m taisph dam_break --dx 0.01 --t-end 1 --frames 20 --out run1
  python -m taisph dam_break --set alpha=0.05 --integrator euler --dt 5e-5
  python -m taisph dam_break --solver dfsph           # incompressible: DFSPH (docs/dfsph.md)
  python -m taisph cases/dam_break_probes_2d.toml  # a scene file (docs/scenes.md)
Open OUT/CASE.pvd in ParaView (File > Open, Apply) to see the time series; python -m taisph
OUT says how OUT was made (OUT/run.json)."""


# DFSPH's controls on the command line (--dfsph-tolerance ...): name -> what it sets
DFSPH_OPTIONS = {
    "dfsph_tolerance": "mean density error (fraction of rho0) a density solve stops at",
    "dfsph_divergence_tolerance": "mean density change per step (fraction of rho0) a divergence solve stops at",
    "dfsph_min_iterations": "iterations of a density solve at least",
    "dfsph_max_iterations": "iterations of either solve at most",
    "dfsph_error_bound": "a solve that ends above its tolerance but within this many times it is kept and "
                         "counted; beyond, the step is retried with half the dt",
    "dfsph_retries": "retries of such a step, each with half the dt, before the run stops",
}
# the controls each run command passes on from its options (dt and courant: their own rules)
CONTROL_OPTIONS = ("dt_max", "force_factor", "max_speed", *DFSPH_OPTIONS)
assert set(CONTROL_OPTIONS) == set(SETTABLE)


def build_parser(case: str | None = None, target_help: str = "case name, or 'list'") -> Parser:
    """The parser of ``python -m taisph CASE [options]``; with a case, its help lists the
    case's parameters with their defaults and ranges, and its effects. `target_help`
    describes the positional argument (a case, or a scene file)."""
    description = "taisph: smoothed particle hydrodynamics on Taichi."
    scene, failure = None, None
    if case:
        description = f"{case}: {inspect.getdoc(catalogue.find(case))}"
        try:
            scene = catalogue.find(case)()
        except Exception as err:  # a case that cannot build with its defaults still gets --help
            failure = err
    this = _case_defaults(scene)
    parser = Parser(
        prog="python -m taisph" + (f" {case}" if case else ""),
        usage=None if case else USAGE,
        description=description,
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("case", nargs="?" if case else 1, help=target_help)
    _time_options(parser, this)
    _dfsph_options(parser)
    _numerics_options(parser, this)
    _guard_options(parser)
    _output_options(parser)
    if case:
        effects = ("\n".join(f"  {t.describe()}" for t in scene.terms) if scene is not None
                   else f"  (could not build the default scene: {failure})")
        parser.epilog = ("case parameters (--set NAME=VALUE): default, allowed range, and what each is (from the "
                         "case's description):\n"
                         + describe_parameters(case)
                         + "\n\neffects (compiled in):\n" + effects + "\n\n" + case_examples(case, scene))
    return parser


def _time_options(parser, this) -> None:
    """The group "resolution and time": dx, the end time, frames and the time step's controls
    (`this`: the case's values, :func:`_case_defaults`)."""
    g = parser.add_argument_group("resolution and time")
    g.add_argument("--dx", type=POSITIVE, help=f"particle spacing (m, > 0); sets the resolution{this['dx']}")
    g.add_argument("--t-end", type=END_TIME, help=f"simulated end time (s, in (0, 1e5]){this['t_end']}")
    g.add_argument("--dt", type=POSITIVE,
                   help="fixed time step (s, > 0); default: adaptive (CFL, force and viscous limits)")
    g.add_argument("--frames", type=OUTPUT_FRAMES,
                   help=f"frames to write after the initial one (0 to 1e5; 0: the initial frame only; default: the "
                        f"case's){this['frames']}")
    g.add_argument("--courant", type=COURANT, metavar="C",
                   help="Courant number of the adaptive step dt = C h / max(c + |v|) (0 < C <= 1); default: a "
                        "scene file's courant, else the case's (dam_break: 0.4 in 2D), else "
                        f"{CONTROLS['courant']:g}; DFSPH: dt = C h / max |v|, {DFSPH_COURANT:g}{this['courant']}")
    g.add_argument("--dt-max", type=ranged(SETTABLE["dt_max"]), metavar="S",
                   help="cap on the adaptive step (s, > 0; default: none)")
    g.add_argument("--force-factor", type=ranged(SETTABLE["force_factor"]), metavar="C",
                   help="C in the force limit dt = C sqrt(h / max |a|) (0 < C <= 1; default "
                        f"{CONTROLS['force_factor']:g}, DFSPH {DFSPH_FORCE_FACTOR:g})")


def _dfsph_options(parser) -> None:
    """The group of DFSPH's pressure solves: one option per :data:`DFSPH_OPTIONS`."""
    g = parser.add_argument_group("DFSPH's pressure solves (docs/dfsph.md)")
    for name, about in DFSPH_OPTIONS.items():
        metavar = "N" * ("iter" in name or "retries" in name) or "E"
        g.add_argument("--" + name.replace("_", "-"), type=ranged(SETTABLE[name]), metavar=metavar,
                       help=f"{about} ({SETTABLE[name].describe()}; default {CONTROLS[name]:g})")


def _numerics_options(parser, this) -> None:
    """The group "numerics": solver, integrator, kernel, precision, neighbour lists, --set."""
    g = parser.add_argument_group("numerics")
    g.add_argument("--solver", choices=SOLVERS,
                   help="wcsph: weakly compressible (the default); dfsph: divergence-free SPH, an implicit "
                        "incompressible pressure solve (docs/dfsph.md); also --set solver=NAME")
    g.add_argument("--integrator", choices=INTEGRATORS, help=f"time integrator (wcsph){this['integrator']}")
    g.add_argument("--kernel", choices=KERNELS, help=f"smoothing kernel{this['kernel']}")
    g.add_argument("--precision", choices=["f32", "f64"], default="f64", help="float precision (default f64)")
    g.add_argument("--neighbour-skin", type=SKIN, metavar="F",
                   help="reuse neighbour lists until a particle moves F/2 support radii (F in [0, 2]; default 0: "
                        "walk the cells every step, as fast on CPUs; see docs/performance.md)")
    g.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="set any case parameter (see CASE --help); repeatable")


def _guard_options(parser) -> None:
    """The group "guards and restarts": the run's guards, checkpoints and determinism."""
    g = parser.add_argument_group("guards and restarts")
    g.add_argument("--max-density-error", type=NON_NEGATIVE, default=CONTROLS["max_density_error"],
                   help="stop when |rho/rho0 - 1| exceeds this fraction (>= 0; 0: off; default "
                        f"{CONTROLS['max_density_error']:g})")
    g.add_argument("--max-speed", type=ranged(SETTABLE["max_speed"]), metavar="V",
                   help="stop when a fluid particle moves faster than V m/s (0: off; default: under DFSPH the "
                        "largest sound speed c0, 10x the flow's speed in the cases; under WCSPH off)")
    g.add_argument("--remove-escaped", action="store_true",
                   help="remove (and count) particles that leave the domain instead of stopping, and particles "
                        "whose density leaves the range, up to --max-out-of-range")
    g.add_argument("--max-out-of-range", type=FRACTION, default=CONTROLS["max_out_of_range"], metavar="F",
                   help="with --remove-escaped (or a case that removes escaped particles, as dam_break): the "
                        "fraction of the fluid particles that may be removed for their density before the next "
                        f"one stops the run (0 to 1; default {CONTROLS['max_out_of_range']:g})")
    g.add_argument("--checkpoint-every", type=EVERY, metavar="K",
                   help="write a checkpoint to OUT/checkpoint every K frames (K >= 1; resume with "
                        "'resume OUT/checkpoint')")
    g.add_argument("--deterministic", action="store_true",
                   help="serial cell sort at every size: bit-for-bit reproducible runs and restarts")


def _output_options(parser) -> None:
    """The group "output and machine": the output folder, probes, the backend and threads."""
    g = parser.add_argument_group("output and machine")
    g.add_argument("--out", type=Path, help="output folder (default: out/CASE)")
    g.add_argument("--no-output", action="store_true",
                   help="write no frames (benchmarking); probes are still written to OUT/probes.csv")
    g.add_argument("--probe", action="append", default=[], metavar="KIND:NAME:WHERE[:EVERY]",
                   help="sample a probe into OUT/probes.csv (repeatable): pressure:P1:3.22,0.16 (a point), "
                        "elevation:gauge:0.6:10 (a vertical line at x = 0.6, every 10 steps), force:F:walls "
                        "(all wall particles; a scene file's wall group names), flow:Q:2,0,2,1 (flow rate through the "
                        "face from (2, 0) to (2, 1)), body:B:box (the state of the body box); docs/scenes.md")
    g.add_argument("--arch", default="cpu", choices=["cpu", "cuda", "vulkan"], help="Taichi backend (default cpu)")
    g.add_argument("--threads", type=THREADS, help="CPU threads (>= 1; default: all cores)")
    g.add_argument("--no-progress", action="store_true",
                   help="no progress display (on a terminal a bar, else a line on stderr every 10 s; "
                        "TAISPH_PROGRESS_EVERY sets the seconds)")


def _case_defaults(scene) -> dict:
    """``"; this case: VALUE"`` for each option a case sets (its default scene's value),
    so that ``CASE --help`` shows what a run without the option does; "" without a case."""
    if scene is None:
        return collections.defaultdict(str)
    courant = (DFSPH_COURANT if scene.solver == "dfsph" else
               scene.courant if scene.courant is not None else CONTROLS["courant"])
    values = dict(dx=f"{scene.dx:g} m", t_end=f"{scene.t_end:g} s", frames=scene.frames, courant=f"{courant:g}",
                  integrator=scene.integrator, kernel=scene.kernel)
    return collections.defaultdict(str, {key: f"; this case: {value}" for key, value in values.items()})


def guarded(func, *args) -> int:
    """Run a command: a refused input (:class:`taisph.messages.InputError`: ParameterError,
    UsageError, SceneFileError, SeedFileError, a scene's refusal...) is exit code 2 and a
    run stopped by a guard 3, each with its message on stderr; Ctrl-C is exit code 130
    with one line: where the run stopped and how to resume it
    (:class:`taisph.run.record.Interrupted`). Any other exception is a fault of taisph, not
    of the input: it propagates with its traceback (exit code 1)."""
    from ..run.simulation import SimulationError

    try:
        return func(*args)
    except SimulationError as err:
        print(f"taisph: {err}", file=sys.stderr)
        return 3
    except InputError as err:
        print(f"taisph: error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as err:
        print(f"taisph: {interrupted(err)}", file=sys.stderr)
        return INTERRUPTED


INTERRUPTED = 130  # the exit code of a command stopped by Ctrl-C (128 + SIGINT), as a shell's


def interrupted(err: KeyboardInterrupt) -> str:
    """The line a Ctrl-C ends a command with: a run's (:class:`taisph.run.record.Interrupted`),
    or, before a run began, that nothing can be resumed."""
    message = getattr(err, "message", None)
    return message or "interrupted before the run began (while building or compiling); no checkpoint to resume"


def run_case(name: str, argv) -> int:
    """``python -m taisph CASE [options]``: every option and parameter is checked (and
    the scene built) before anything is compiled or written."""
    args = build_parser(name).parse_args(argv)
    settings, solver = catalogue.solver_setting(args.set, args.solver)
    # a case that builds what a solver needs (drop_on_incline: dummy walls for DFSPH) is told the solver
    told = solver if "solver" in catalogue.parameters(name) else None
    kwargs = catalogue.case_arguments(name, settings, dx=args.dx, integrator=args.integrator, kernel=args.kernel,
                                      solver=told)
    scene = catalogue.find(name)(**kwargs)
    if solver is not None:
        scene.solver = solver
    if args.dt is not None:
        scene.dt = args.dt
    walls = {"walls": np.flatnonzero(scene.kind == WALL), **scene.wall_groups}  # a case may name groups
    probes = list(scene.probes) + command_line_probes(args, scene, walls)  # its own probes, then --probe's
    folder = probe_folder(scene, args)  # OUT, also with --no-output (which writes no frames)
    writers = probe_writers(probes, walls, folder)
    bound = inspect.signature(catalogue.find(name)).bind(**kwargs)
    bound.apply_defaults()  # the case's arguments as it ran: for OUT/run.json
    try:
        return simulate(scene, args, writers=writers, notes=probe_notes(probes, folder),
                        source=dict(case=name, arguments=dict(bound.arguments)))
    finally:
        for writer in writers:
            writer.close()


def command_line_probes(args, scene, walls) -> list:
    """The ``--probe`` options as probes for `scene`, checked (wall groups, and points
    inside the scene's domain) before anything is compiled or written."""
    from ..probes import check_bodies, check_inside, parse

    probes = [parse(text, scene.dim) for text in args.probe]
    for p in probes:
        if p.kind == "force" and p.walls not in walls:
            raise UsageError(f"--probe force:{p.name}:{p.walls}: no wall group {p.walls!r}; wall groups: "
                             + (", ".join(walls) or "none"))
    check_bodies(probes, [b.name for b in scene.bodies], "--probe")  # body:NAME:BODY
    check_inside(probes, scene.domain, "--probe", scene=scene, walls=walls)  # also not in a wall
    return probes


def probe_notes(probes, out) -> list:
    """The line a run prints about its probes."""
    if not probes:
        return []
    return [f"probes to {Path(out) / 'probes.csv'}: "
            + ", ".join(f"{p.name} ({p.kind}{f', every {p.every} steps' if p.every > 1 else ''})" for p in probes)]


def probe_writers(probes, walls, out) -> list:
    """A :class:`taisph.probes.Probes` writer into OUT/probes.csv, if there are probes and an output folder."""
    if not probes or out is None:
        return []
    from ..probes import Probes

    return [Probes(probes, walls=walls, path=Path(out) / "probes.csv")]


def probe_folder(scene, args) -> Path:
    """Where a run writes its probes: ``--out``, default ``out/NAME``, also with ``--no-output``;
    refused before anything is compiled if it cannot be a folder (:func:`folder_problem`)."""
    folder = Path(args.out) if args.out else Path("out") / scene.name
    problem = folder_problem(folder)
    if problem:
        raise InputError(f"--out {folder}: {problem}")
    return folder


def folder_problem(folder: Path) -> str | None:
    """Why `folder` cannot be made or written to (a file where a folder must be, a parent
    that is a file or not writable), or None. Nothing is created."""
    if folder.exists() and not folder.is_dir():
        return "is a file, not a folder"
    parent = folder
    while not parent.exists():
        parent = parent.parent
    if not parent.is_dir():
        return f"{parent} is a file, not a folder"
    if not os.access(parent, os.W_OK | os.X_OK):
        return f"{parent} cannot be written to"
    return None


def output_folder(scene, args) -> Path | None:
    """Where a run writes its frames (``--out``, default ``out/NAME``); None with ``--no-output``."""
    return None if args.no_output else probe_folder(scene, args)


def simulate(scene, args, t_end=None, frames=None, notes=(), writers=(), controls=None, source=None) -> int:
    """Simulate `scene` as the case options `args` say (output folder, guards, machine,
    progress), print its description (and `notes`), the set-up time, the summary and the
    headline results (:func:`taisph.run.results.report`), and record the run in
    OUT/run.json (:mod:`taisph.run.record`; `source`: how the scene was given, e.g.
    ``case`` and its ``arguments``). `controls`: further simulation controls (a scene
    file's ``courant``, ``dt_max``...); the options (``--courant``, ``--dt-max``,
    ``--dfsph-tolerance``...) override."""
    from ..run.record import RunRecord, scene_entry, unrecorded
    from ..run.results import report

    if args.neighbour_skin is not None:
        scene.neighbour_skin = args.neighbour_skin
    out = output_folder(scene, args)
    print(scene.describe())
    for line in notes:
        print(f"  {line}")
    sim = build_simulation(scene, args, controls)
    t_end = next(v for v in (t_end, args.t_end, scene.t_end) if v is not None)  # given, else the option's, else
    frames = next(v for v in (frames, args.frames, scene.frames) if v is not None)  # the scene's
    folder = out if out is not None else (probe_folder(scene, args) if writers else None)  # where it writes
    run = dict(t_end=t_end, frames=frames, checkpoint_every=args.checkpoint_every, out=out)
    checkpoint = out / "checkpoint" if out is not None and args.checkpoint_every else None
    record = RunRecord(folder, sim, scene_entry(scene, **(source or {})), run, checkpoint) if folder else None
    with record if record is not None else unrecorded(sim):
        summary = sim.run(t_end, frames=frames, out=out, progress=not args.no_progress,
                          checkpoint_every=args.checkpoint_every, writers=writers)
        where = f"; open {Path(summary.out) / (scene.name + '.pvd')} in ParaView" if summary.out else ""
        print(f"done: {summary}{where}")
        results = report(scene, sim, folder)
        for line in results:
            print(line)
        if record is not None:
            record.finish("done", summary, results)
    return 0


def build_simulation(scene, args, controls=None):
    """The :class:`taisph.Simulation` of `scene` as the options `args` say (machine,
    guards, the controls: `controls`, then the options'), with a line saying what it is
    and how long it took to build (its kernels compiled)."""
    import taisph

    start = time.perf_counter()
    controls = dict(controls or {})
    for name in ("courant", *CONTROL_OPTIONS):
        if getattr(args, name, None) is not None:
            controls[name] = getattr(args, name)
    sim = taisph.Simulation(scene, arch=args.arch, precision=args.precision, threads=args.threads,
                            max_density_error=args.max_density_error, remove_escaped=args.remove_escaped or None,
                            max_out_of_range=args.max_out_of_range,
                            deterministic=args.deterministic, **controls)
    step = (f"fixed dt = {sim.dt:.3g} s" if sim.controls.dt
            else f"adaptive dt (Courant {sim.controls.courant:g}; first {sim.dt:.3g} s)")
    print(f"  {sim.runtime.arch}, {sim.runtime.precision}, {sim.runtime.threads} thread(s); {step}; "
          f"ready in {time.perf_counter() - start:.2f} s (kernel compilation included)")
    return sim
