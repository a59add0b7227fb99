"""Command line: ``python -m taisph ...`` dispatches to its commands: a case
(:mod:`taisph.cli.case`), a scene file (:mod:`taisph.cli.scenefile`), ``list``,
``resume``, ``sweep`` (:mod:`taisph.cli.sweep`), ``plot`` (:mod:`taisph.cli.plot`), the
seed's ``run`` and ``export`` (:mod:`taisph.cli.dat`), an output folder (what its
``run.json`` says, :mod:`taisph.run.record`) and ``--version``."""

from __future__ import annotations

import argparse
import inspect
import math
import platform
import sys
from pathlib import Path

import numpy as np

from ..engine.layout import WALL
from ..messages import InputError
from ..messages import install as install_messages
from ..scene import catalogue
from ..run import record
from .case import build_parser, guarded, run_case
from .case_help import first_sentence, list_entry
from .parser import END_TIME, THREADS, Parser
from .scenefile import list_scene_files


def list_cases(out=None):
    out = sys.stdout if out is None else out
    registry = catalogue.registry()
    width = max(len(n) for n in registry)
    print("built-in cases (python -m taisph CASE --help for parameters):", file=out)
    for name, func in registry.items():
        doc = first_sentence(inspect.getdoc(sys.modules[func.__module__]) or inspect.getdoc(func) or "")
        print(list_entry(name, width, doc), file=out)
    list_scene_files(out)


def version() -> str:
    """``taisph X.Y.Z (taichi A.B.C, Python P)``."""
    import taichi

    from ..run.checkpoint import taisph_version

    return (f"taisph {taisph_version()} (taichi {'.'.join(str(k) for k in taichi.__version__)}, "
            f"Python {platform.python_version()})")


def show_record(folder) -> int:
    """``python -m taisph OUT``: what OUT/run.json says of the run that wrote OUT."""
    print(record.describe(record.read(folder), folder))
    return 0


def main(argv=None) -> int:
    """``python -m taisph ...``; returns the exit code (0 done, 1 an unstable seed run,
    2 input refused with nothing written (:class:`taisph.messages.InputError`), 3 a run
    stopped by a guard, 130 a run stopped by Ctrl-C: one line naming its last checkpoint
    and the command that resumes it). Any other exception is a fault of taisph and
    propagates with its traceback (exit code 1 from ``python -m taisph``)."""
    install_messages()  # taisph's warnings as one line: taisph: warning: ...
    try:  # a log of stdout and stderr together (> log 2>&1) keeps their lines in order
        sys.stdout.reconfigure(line_buffering=True)
    except (AttributeError, ValueError):  # a stream that cannot (a test's capture, a closed one)
        pass
    argv = list(sys.argv[1:] if argv is None else argv)
    record.set_command(argv)  # for OUT/run.json
    if not argv or argv[0] in ("-h", "--help"):
        build_parser().print_help()
        return 0
    command = argv[0]
    if command == "--version":
        print(version())
        return 0
    if command == "list":
        list_cases()
        return 0
    if command == "resume":
        return resume(argv[1:])
    if command == "sweep":  # parameter sweeps on a Dask cluster: taisph/cli/sweep.py
        from .sweep import main as sweep_main

        return sweep_main(argv[1:])
    if command == "plot":  # figures of an output folder: taisph/cli/plot.py
        from .plot import main as plot_main

        return plot_main(argv[1:])
    if command.endswith(".toml"):  # a scene file: taisph/formats/scenefile_spec.py
        from .scenefile import main as run_scene_file

        return run_scene_file(argv)
    if command in ("run", "export"):  # the seed's file workflow
        from . import dat

        return (dat.run_main if command == "run" else dat.export_main)(argv[1:])
    if command not in catalogue.registry() and Path(command).is_dir():  # an output folder: its run.json
        return guarded(show_record, command)
    if Path(command).name == record.FILE and Path(command).is_file():
        return guarded(show_record, str(Path(command).parent))
    if command not in catalogue.registry():
        print(f"taisph: unknown case or command {command!r}. Cases: {', '.join(catalogue.registry())}; "
              "commands: list, run, export, resume, sweep, plot; or an output folder (its run.json), --version",
              file=sys.stderr)
        return 2
    return guarded(run_case, command, argv)


RESUME_HELP = """\
Continue a run from a checkpoint folder written by --checkpoint-every (OUT/checkpoint),
into the run's output folder, with its checkpoint interval and its probes: OUT/probes.csv
keeps its rows up to the checkpoint's time (rows after it, written before an interruption,
are dropped), then the resumed run appends its own, once; a line says so. OUT/run.json
records the resumed run, with the record of the run it continues.

Without --t-end the run goes on to its own end time, with the frames it had left; a
finished run has nothing left to do. With --t-end T (a time beyond the run's clock) it
continues to T instead, with frames at the run's own frame interval: round((T - t) /
interval) frames (at least 1), evenly spaced, the last one at T. The interval is the
saved run's: its end time minus the checkpoint's time, over the frames it had left; for
a finished run, the time between its last two frames."""


def resume(argv) -> int:
    """``python -m taisph resume OUT/checkpoint [--t-end T]``: continue a checkpointed run
    (:data:`RESUME_HELP`)."""
    return guarded(_resume, argv)


def _resume(argv) -> int:
    parser = Parser(prog="python -m taisph resume", usage="python -m taisph resume DIR [--t-end T] [options]",
                    description=RESUME_HELP, formatter_class=argparse.RawDescriptionHelpFormatter,
                    epilog="examples:\n  python -m taisph dam_break --checkpoint-every 5 --out run1   # Ctrl-C, then:\n"
                           "  python -m taisph resume run1/checkpoint\n"
                           "  python -m taisph resume run1/checkpoint --t-end 3   # a finished run, on to t = 3 s")
    parser.add_argument("checkpoint", type=Path, help="checkpoint folder (OUT/checkpoint)")
    parser.add_argument("--t-end", type=END_TIME, metavar="T",
                        help="continue to T (s) instead of the run's own end time: extends a finished run")
    parser.add_argument("--threads", type=THREADS, help="CPU threads (>= 1; default: all cores)")
    parser.add_argument("--no-progress", action="store_true", help="no progress display")
    args = parser.parse_args(argv)
    folder = args.checkpoint
    from ..run.simulation import Simulation

    # a folder that is not there, a run's output folder, another checkpoint version: an InputError
    # (taisph.run.checkpoint.CheckpointError) saying what to do, before anything is built
    sim = Simulation.from_checkpoint(folder, threads=args.threads)
    meta = sim.checkpoint_meta
    t_end, frames = meta["t_end"], meta["frames_left"]
    if args.t_end is not None:
        if args.t_end <= sim.time:
            raise InputError(f"--t-end {args.t_end:g}: the run is at t = {sim.time:.6g} s; continue it to a later "
                             "time")
        frames = max(1, round((args.t_end - sim.time) / frame_interval(meta, sim.time)))
        t_end = args.t_end
    print(f"resuming {sim.scene.name} at step {sim.steps}, t = {sim.time:.6g} s "
          f"(to t = {t_end:.6g} s, {frames} frame(s) left)")
    if not frames:
        print(f"nothing left to do: the run reached its end time; 'resume {folder} --t-end T' continues it to T")
        return 0
    writers, notes = resumed_probes(meta, sim, meta["out"])
    for line in notes:
        print(f"  {line}")
    try:
        return run_resumed(sim, folder, t_end, frames, writers, progress=not args.no_progress)
    finally:
        for writer in writers:
            writer.close()


def run_resumed(sim, folder, t_end: float, frames: int, writers, progress: bool = True) -> int:
    """Run the resumed `sim` (from the checkpoint `folder`) to `t_end` with `frames` frames
    into its run's output folder, recorded in OUT/run.json (with the record it continues)."""
    from ..run.record import RunRecord, scene_entry
    from ..run.results import report

    meta, out = sim.checkpoint_meta, Path(sim.checkpoint_meta["out"])
    every = meta.get("checkpoint_every") or 1
    run = dict(t_end=t_end, frames=frames, checkpoint_every=every, out=out)
    rec = RunRecord(out, sim, scene_entry(sim.scene), run, checkpoint=out / "checkpoint", resumed=folder)
    if rec.previous:
        print(f"  continues the run '{' '.join(rec.previous.get('command') or [])}' of {rec.previous.get('start')} "
              f"({out / record.FILE})")
    with rec:
        summary = sim.run(t_end, frames=frames, out=out, progress=progress, checkpoint_every=every, writers=writers,
                          _writer_state=meta["writer"],
                          _output_times=meta.get("output_times") if t_end == meta["t_end"] else None)
        print(f"done: {summary}")
        results = report(sim.scene, sim, out)
        for line in results:
            print(line)
        rec.finish("done", summary, results)
    return 0


def frame_interval(meta: dict, time: float) -> float:
    """The saved run's time between frames: what was left of it over the frames left,
    else (a finished run) the time between its last two frames; else (no two frames)
    infinite: one frame, at the new end time."""
    if meta["frames_left"]:
        return (meta["t_end"] - time) / meta["frames_left"]
    times = sorted(t for t, part, _ in (meta["writer"] or (0, []))[1] if part == 0)
    if len(times) >= 2 and times[-1] > times[-2]:
        return times[-1] - times[-2]
    return math.inf


def resumed_probes(meta: dict, sim, out) -> tuple[list, list]:
    """(writers, notes): the run's probes as a :class:`taisph.probes.Probes` writer
    continuing OUT/probes.csv from the checkpoint's time (its later rows dropped), if the
    checkpoint has probes."""
    probes = meta.get("probes")
    if not probes:
        return [], []
    from ..probes import Probes

    names = ", ".join(p.name if hasattr(p, "name") else p["name"] for p in probes)
    path = Path(out) / "probes.csv"
    walls = meta.get("wall_groups")
    if walls is None:  # a case's force probes name all the wall particles "walls"
        walls = {"walls": np.flatnonzero(sim.scene.kind == WALL)}
    return ([Probes(probes, walls=walls, path=path, append=True, resume_time=sim.time)],
            [f"probes ({names}): appended to {path} (its rows after t = {sim.time:.6g} s, if any, dropped first)"])
