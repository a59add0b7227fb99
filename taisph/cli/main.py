"""Command line: ``python -m taisph CASE [options]``, ``python -m taisph list``."""

from __future__ import annotations

import argparse
import inspect
import sys
import time
from pathlib import Path

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
Open OUT/CASE.pvd in ParaView (File > Open, Apply) to see the time series."""


def _cases():
    import taisph

    return taisph.cases.CASES


def _case_parameters(func) -> dict:
    return {
        name: p.default
        for name, p in inspect.signature(func).parameters.items()
        if p.default is not inspect.Parameter.empty
    }


def _parse_value(text: str, default):
    """Convert a --set value to the type of the case parameter's default."""
    if isinstance(default, bool):
        if text.lower() in ("1", "true", "yes", "on"):
            return True
        if text.lower() in ("0", "false", "no", "off"):
            return False
        raise ValueError(f"expected true/false, got {text!r}")
    if isinstance(default, int):
        return int(text)
    if isinstance(default, float) or default is None:
        if default is None and text.lower() == "none":
            return None
        try:
            return float(text)
        except ValueError:
            if default is None:
                return text
            raise
    if isinstance(default, tuple):
        return tuple(float(v) for v in text.strip("()").split(","))
    return text


def build_parser(case: str | None = None) -> argparse.ArgumentParser:
    description = "taisph: smoothed particle hydrodynamics on Taichi."
    if case:
        func = _cases()[case]
        description = f"{case}: {inspect.getdoc(func)}"
    parser = argparse.ArgumentParser(
        prog="python -m taisph" + (f" {case}" if case else ""),
        usage=None if case else USAGE,
        description=description,
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("case", nargs="?" if case else 1, help="case name, or 'list'")
    g = parser.add_argument_group("resolution and time")
    g.add_argument("--dx", type=float, help="particle spacing (m); sets the resolution")
    g.add_argument("--t-end", type=float, help="simulated end time (s)")
    g.add_argument("--dt", type=float, help="fixed time step (s); default: adaptive (CFL, force and viscous limits)")
    g.add_argument("--frames", type=int, help="frames to write after the initial one (default: the case's)")
    g = parser.add_argument_group("numerics")
    g.add_argument("--integrator", choices=["euler", "eulermid", "eulermom", "pc"], help="time integrator")
    g.add_argument("--kernel", choices=["spline", "gaussian", "wendland"], help="smoothing kernel")
    g.add_argument("--precision", choices=["f32", "f64"], default="f64", help="float precision (default f64)")
    g.add_argument("--neighbour-skin", type=float, metavar="F",
                   help="reuse neighbour lists until a particle moves F/2 support radii (default 0: "
                        "walk the cells every step, as fast on CPUs; see docs/performance.md)")
    g.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="set any case parameter (see CASE --help); repeatable")
    g = parser.add_argument_group("guards and restarts")
    g.add_argument("--max-density-error", type=float, default=0.2,
                   help="stop when |rho/rho0 - 1| exceeds this fraction (0: off; default 0.2)")
    g.add_argument("--remove-escaped", action="store_true",
                   help="remove (and count) particles that leave the domain instead of stopping")
    g.add_argument("--checkpoint-every", type=int, metavar="K",
                   help="write a checkpoint to OUT/checkpoint every K frames (resume with 'resume OUT/checkpoint')")
    g.add_argument("--deterministic", action="store_true",
                   help="serial cell sort at every size: bit-for-bit reproducible runs and restarts")
    g = parser.add_argument_group("output and machine")
    g.add_argument("--out", type=Path, help="output folder (default: out/CASE)")
    g.add_argument("--no-output", action="store_true", help="write no frames (benchmarking)")
    g.add_argument("--arch", default="cpu", choices=["cpu", "cuda", "vulkan"], help="Taichi backend (default cpu)")
    g.add_argument("--threads", type=int, help="CPU threads (default: all cores)")
    g.add_argument("--no-progress", action="store_true", help="no progress bar")
    if case:
        params = _case_parameters(_cases()[case])
        lines = [f"  {k} = {v!r}" for k, v in params.items()]
        try:
            effects = "\n".join(f"  {t.describe()}" for t in _cases()[case]().terms)
        except Exception as err:  # a case that cannot build with defaults still gets --help
            effects = f"  (could not build the default scene: {err})"
        parser.epilog = ("case parameters (--set NAME=VALUE):\n" + "\n".join(lines)
                         + "\n\neffects (compiled in):\n" + effects + "\n\n" + EPILOG)
    return parser


def list_cases(out=None):
    out = sys.stdout if out is None else out
    cases = _cases()
    width = max(len(n) for n in cases)
    print("built-in cases (python -m taisph CASE --help for parameters):", file=out)
    for name, func in cases.items():
        doc = (inspect.getdoc(sys.modules[func.__module__]) or inspect.getdoc(func) or "").splitlines()[0]
        print(f"  {name:<{width}}  {doc}", file=out)


def main(argv=None) -> int:
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
    if command in ("run", "export"):  # the seed's file workflow: taisph/seed.py
        from .. import seed

        return (seed.run_main if command == "run" else seed.export_main)(argv[1:])
    cases = _cases()
    if command not in cases:
        print(f"taisph: unknown case or command {command!r}. Cases: {', '.join(cases)}; commands: list, run, export, resume",
              file=sys.stderr)
        return 2
    args = build_parser(command).parse_args(argv)
    return _guarded(run_case, command, args)


def _guarded(func, *args) -> int:
    from ..simulation import SimulationError

    try:
        return func(*args)
    except SimulationError as err:
        print(f"taisph: {err}", file=sys.stderr)
        return 3
    except (ValueError, KeyError, TypeError, FileNotFoundError) as err:
        print(f"taisph: error: {err}", file=sys.stderr)
        return 2


def run_case(name: str, args) -> int:
    import taisph

    func = _cases()[name]
    params = _case_parameters(func)
    kwargs = {}
    for key in ("dx", "integrator", "kernel"):
        value = getattr(args, key)
        if value is not None:
            if key not in params:
                raise ValueError(f"case {name} has no parameter {key!r}")
            kwargs[key] = value
    for item in args.set:
        if "=" not in item:
            raise ValueError(f"--set expects NAME=VALUE, got {item!r}")
        key, text = item.split("=", 1)
        key = key.strip().replace("-", "_")
        if key not in params:
            raise ValueError(f"case {name} has no parameter {key!r}; it has: {', '.join(params)}")
        try:
            kwargs[key] = _parse_value(text.strip(), params[key])
        except ValueError as err:
            raise ValueError(f"--set {key}: {err}") from None
    scene = func(**kwargs)
    if args.dt is not None:
        scene.dt = args.dt
    if args.neighbour_skin is not None:
        scene.neighbour_skin = args.neighbour_skin
    out = None if args.no_output else (args.out or Path("out") / name)
    print(scene.describe())
    start = time.perf_counter()
    sim = taisph.Simulation(scene, arch=args.arch, precision=args.precision, threads=args.threads,
                            max_density_error=args.max_density_error, remove_escaped=args.remove_escaped,
                            deterministic=args.deterministic)
    step = f"fixed dt = {sim.dt:.3g} s" if sim.controls.dt else f"adaptive dt (first {sim.dt:.3g} s)"
    print(f"  {sim.runtime.arch}, {sim.runtime.precision}, {sim.runtime.threads} thread(s); {step}; "
          f"ready in {time.perf_counter() - start:.2f} s (kernel compilation included)")
    summary = sim.run(args.t_end, frames=args.frames, out=out, progress=not args.no_progress,
                      checkpoint_every=args.checkpoint_every)
    where = f"; open {Path(summary.out) / (scene.name + '.pvd')} in ParaView" if summary.out else ""
    print(f"done: {summary}{where}")
    return 0


def resume(argv) -> int:
    parser = argparse.ArgumentParser(prog="python -m taisph resume",
                                     description="Continue a run from a checkpoint folder written by "
                                                 "--checkpoint-every (OUT/checkpoint).")
    parser.add_argument("checkpoint", type=Path, help="checkpoint folder")
    parser.add_argument("--threads", type=int, help="CPU threads (default: all cores)")
    parser.add_argument("--no-progress", action="store_true")
    args = parser.parse_args(argv)
    return _guarded(_resume, args)


def _resume(args) -> int:
    from ..simulation import Simulation
    from ..io.vtk import VTKWriter

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
