"""``OUT/run.json``: how a run was made and how it ended, beside its output.

Every run of the command line (a case, a scene file, ``resume``, the seed's ``run``)
writes it, atomically (a temporary file renamed over the old one): once when the run
starts (``status`` "running"), once when it ends. Its keys:

``format``, ``schema``   "taisph-run", :data:`SCHEMA`
``command``      the command line, as a list of words (``python -m taisph ...``)
``cwd``          the folder it ran in
``status``       "running", "done", "interrupted" (Ctrl-C), "stopped by a guard: ..."
                 (:class:`taisph.SimulationError`), "unstable: ..." (the seed's ``run``),
                 or "failed: ..." (any other exception: a fault of taisph)
``versions``     taisph, Taichi, numpy, Python
``scene``        ``name``, how it was given (``case`` and its ``arguments`` after
                 defaults, or ``scene_file`` and its ``settings``, or ``seed_files``),
                 ``parameters`` (:meth:`taisph.Scene.parameters`) and ``description``
                 (:meth:`taisph.Scene.describe`)
``run``          ``t_end``, ``frames``, ``checkpoint_every``, ``out``
``controls``     the simulation's :class:`taisph.engine.timestep.Controls`
``machine``      platform, processor, CPU count, Taichi's arch, precision, threads
``start``, ``end``   local ISO times (``end`` None while running)
``steps``, ``sim_time``, ``wall_time``   steps taken, simulated time reached (s) and
                 wall time (s) of this run (a resume: since it resumed)
``summary``      the run's summary line (:class:`taisph.run.progress.RunSummary`)
``results``      the headline results printed at the end (:mod:`taisph.run.results`)
``resume_of``    a resumed run: the record it continues (that run's ``run.json``), and
                 ``checkpoint``, the folder it resumed from

``python -m taisph OUT`` prints it (:func:`describe`).
"""

from __future__ import annotations

import contextlib
import dataclasses
import datetime
import json
import math
import os
import platform
import shlex
import sys
import time
from pathlib import Path

from .atomic import write_text

FILE = "run.json"
FORMAT = "taisph-run"
SCHEMA = 1

# the command line of this process (set by taisph.cli.main.main); None: sys.argv
_COMMAND: list | None = None


def set_command(argv) -> None:
    """Record ``python -m taisph ARGV...`` as this process's command line."""
    global _COMMAND
    _COMMAND = ["python", "-m", "taisph", *[str(a) for a in argv]]


def command() -> list:
    return list(_COMMAND) if _COMMAND is not None else [sys.executable, *sys.argv]


def versions() -> dict:
    import numpy
    import taichi

    from .checkpoint import taisph_version

    return dict(taisph=taisph_version(), taichi=".".join(str(k) for k in taichi.__version__),
                numpy=numpy.__version__, python=platform.python_version())


def processor() -> str:
    """The CPU's name (Linux: ``model name`` of /proc/cpuinfo), else what Python knows."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as f:
            for line in f:
                key, _, value = line.partition(":")
                if key.strip() == "model name" and value.strip():
                    return value.strip()
    except OSError:
        pass
    return platform.processor() or platform.machine() or "unknown"


def machine(sim=None) -> dict:
    """Platform, processor, CPU count and (with `sim`) Taichi's arch, precision, threads."""
    out = dict(platform=platform.platform(), processor=processor(), cpus=os.cpu_count())
    if sim is not None:
        out.update(arch=sim.runtime.arch, precision=sim.runtime.precision, threads=sim.runtime.threads)
    return out


def plain(value):
    """`value` as JSON values: numpy numbers and arrays, tuples, paths; NaN and infinities
    as None; anything else as its text."""
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if hasattr(value, "tolist"):  # numpy
        return plain(value.tolist())
    if isinstance(value, bool) or value is None or isinstance(value, (int, str)):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, Path):
        return str(value)
    return str(value)


def now() -> str:
    return datetime.datetime.now().astimezone().isoformat(timespec="seconds")


def write(path: Path, data: dict) -> None:
    """`data` as JSON to `path`, atomically."""
    write_text(path, json.dumps(data, indent=1) + "\n")


def read(folder) -> dict:
    """The record in `folder` (``run.json``); :class:`taisph.messages.InputError` naming
    the file if there is none or it is not a run record."""
    from ..messages import InputError

    path = Path(folder) / FILE
    if not path.is_file():
        raise InputError(f"{folder}: no {FILE} (a run of taisph writes one into its output folder)")
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (ValueError, UnicodeDecodeError) as err:
        raise InputError(f"{path}: not JSON ({err})") from None
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise InputError(f"{path}: not a taisph run record (no format {FORMAT!r})")
    return data


def scene_entry(scene, **given) -> dict:
    """The record's ``scene``: its name, how it was given (`given`: ``case`` and
    ``arguments``, or ``scene_file`` and ``settings``...), parameters and description."""
    return plain(dict(name=scene.name, **given, parameters=scene.parameters(), description=scene.describe()))


class Interrupted(KeyboardInterrupt):
    """Ctrl-C during a recorded run: ``message`` is the one line the command line prints
    (where the run stopped, its last checkpoint and the command that resumes it)."""

    def __init__(self, message: str):
        super().__init__(message)
        self.message = message


@contextlib.contextmanager
def unrecorded(sim):
    """Around a run that writes nothing (``--no-output`` without probes): Ctrl-C raises
    :class:`Interrupted` with the line saying where the run stopped."""
    try:
        yield
    except KeyboardInterrupt:
        raise Interrupted(f"interrupted at t = {sim.time:.6g} s (step {sim.steps}); the run wrote nothing "
                          "(--no-output), nothing to resume") from None


class RunRecord:
    """``OUT/run.json`` of one run (see the module docstring): a context manager around
    the run that writes the record when it starts and when it ends, however it ends.

    `scene`: :func:`scene_entry`; `run`: ``t_end``, ``frames``, ``checkpoint_every``...;
    `checkpoint`: the folder the run checkpoints to (None: it does not), and `resumed`:
    the checkpoint folder a resumed run started from (any valid checkpoint there then
    resumes it; a new run's counts only once it writes one); `can_checkpoint` False: the
    command has no checkpoints (the seed's ``run``). On Ctrl-C the record says
    "interrupted" and :class:`Interrupted` is raised with the line to print."""

    def __init__(self, folder, sim, scene: dict, run: dict, checkpoint=None, resumed=None, can_checkpoint=True):
        self.folder, self.sim, self.can_checkpoint = Path(folder), sim, can_checkpoint
        self.checkpoint, self.resumed = (Path(checkpoint) if checkpoint else None), resumed
        self.path = self.folder / FILE
        self.previous = None  # a resumed run: the record of the run it continues, if readable
        if resumed is not None:
            try:
                self.previous = read(self.folder)
            except ValueError:  # no record, or not one: the resume still runs
                self.previous = None
        self.data = dict(format=FORMAT, schema=SCHEMA, command=command(), cwd=os.getcwd(), status="running",
                         versions=versions(), scene=scene, run=plain(run),
                         controls=plain({f.name: getattr(sim.controls, f.name)
                                         for f in dataclasses.fields(sim.controls)}),
                         machine=machine(sim), start=None, end=None, steps=0, sim_time=sim.time, wall_time=0.0,
                         summary=None, results=[])
        if resumed is not None:
            self.data["resume_of"] = dict(checkpoint=str(resumed), record=self.previous)
            given = (self.previous or {}).get("scene") or {}  # how the continued run's scene was given
            for key in ("case", "arguments", "scene_file", "settings", "seed_files"):
                if key in given:
                    scene.setdefault(key, given[key])
        self.steps0, self.started, self.start_clock = sim.steps, time.time(), time.perf_counter()

    def __enter__(self):
        self.folder.mkdir(parents=True, exist_ok=True)
        self.started, self.start_clock = time.time(), time.perf_counter()
        self.data["start"] = now()
        write(self.path, self.data)
        return self

    def finish(self, status: str, summary=None, results=()) -> None:
        """Write the record's end: `status`, the run's `summary` and `results` lines."""
        self.data.update(status=status, end=now(), steps=self.sim.steps - self.steps0, sim_time=self.sim.time,
                         wall_time=round(time.perf_counter() - self.start_clock, 3))
        if summary is not None:
            self.data["summary"] = str(summary)
        if results:
            self.data["results"] = [str(line) for line in results]
        write(self.path, self.data)

    def __exit__(self, kind, err, tb):
        if kind is None:
            if self.data["status"] == "running":
                self.finish("done")
            return False
        from ..engine.diagnosis import SimulationError

        if issubclass(kind, KeyboardInterrupt):
            self.finish("interrupted")
            raise Interrupted(self.interruption()) from None
        if issubclass(kind, SimulationError):
            self.finish("stopped by a guard: " + (str(err).splitlines() or [""])[0])
        else:
            self.finish(f"failed: {kind.__name__}: " + (str(err).splitlines() or [""])[0])
        return False

    def last_checkpoint(self) -> tuple[Path, float | None] | None:
        """(folder, time) of the checkpoint this run can be resumed from, or None."""
        from .checkpoint import CheckpointError, check_folder

        if self.checkpoint is None:
            return None
        try:
            meta = check_folder(self.checkpoint)
        except CheckpointError:
            return None
        if self.resumed is None and (self.checkpoint / "meta.json").stat().st_mtime < self.started:
            return None  # an earlier run's
        entries = ((meta.get("run") or {}).get("writer") or {}).get("entries") or []
        return self.checkpoint, (entries[-1][0] if entries else None)

    def interruption(self) -> str:
        """The line a Ctrl-C ends with: where the run stopped, and how to go on."""
        where = f"interrupted at t = {self.sim.time:.6g} s (step {self.sim.steps})"
        found = self.last_checkpoint()
        if found is not None:
            folder, at = found
            when = f" (t = {at:.6g} s)" if at is not None else ""
            return (f"{where}; last checkpoint {folder}{when}; continue with: python -m taisph resume "
                    f"{shlex.quote(str(folder))}")
        every = self.data["run"].get("checkpoint_every")
        if not self.can_checkpoint:
            return f"{where}; this command writes no checkpoints: rerun it; output so far in {self.folder}"
        if every and self.checkpoint is None:
            return (f"{where}; no checkpoint written (--checkpoint-every writes them with the frames, not with "
                    f"--no-output): rerun; probes so far in {self.folder}")
        if every:
            return (f"{where}; no checkpoint written yet (--checkpoint-every {every}: the first after {every} "
                    "frame(s)), nothing to resume; output so far in " + str(self.folder))
        return (f"{where}; no checkpoint was written (rerun with --checkpoint-every N to write one every N frames, "
                f"then 'python -m taisph resume OUT/checkpoint' continues it); output so far in {self.folder}")


def _settings(values: dict) -> str:
    return ", ".join(f"{k}={v!r}" if isinstance(v, str) else f"{k}={v}" for k, v in values.items())


def _scene_line(scene: dict) -> str:
    if "case" in scene:
        return f"{scene.get('name')}, the case {scene['case']}: {_settings(scene.get('arguments') or {})}"
    if "scene_file" in scene:
        settings = scene.get("settings") or {}
        return (f"{scene.get('name')}, from the scene file {scene['scene_file']}"
                + (f" with {_settings(settings)}" if settings else ""))
    if "seed_files" in scene:
        return f"{scene.get('name')}, from the seed's files {', '.join(map(str, scene['seed_files']))}"
    return str(scene.get("name"))


def _run_line(data: dict) -> str:
    run = data.get("run") or {}
    wanted = []
    if run.get("t_end") is not None:
        wanted.append(f"end time {run['t_end']:g} s")
    if run.get("frames") is not None:
        wanted.append(f"{run['frames']} frames")
    if run.get("checkpoint_every"):
        wanted.append(f"a checkpoint every {run['checkpoint_every']} frames")
    sim_time = data.get("sim_time")
    reached = f"t = {sim_time:.6g} s" if isinstance(sim_time, (int, float)) else "t = ?"
    return f"{data.get('steps')} steps to {reached}" + (f" ({', '.join(wanted)})" if wanted else "")


def describe(data: dict, folder) -> str:
    """A run record (:func:`read`) as a few lines, for ``python -m taisph OUT``."""
    import textwrap

    def field(label, text):
        return textwrap.fill(str(text), width=100, initial_indent=f"  {label:<10}", subsequent_indent=" " * 12,
                             break_long_words=False, break_on_hyphens=False)

    v, m = data.get("versions") or {}, data.get("machine") or {}
    wall = data.get("wall_time")
    lines = [f"{folder}: {shlex.join(data.get('command') or [])}",
             field("status", data.get("status")),
             field("started", f"{data.get('start')}; ended {data.get('end') or '-'}"
                   + (f" in {wall:.1f} s wall" if isinstance(wall, (int, float)) else "")),
             field("scene", _scene_line(data.get("scene") or {})),
             field("run", _run_line(data))]
    lines += [f"  {'results' if k == 0 else '':<10}{line.strip()}" for k, line in enumerate(data.get("results") or [])]
    lines.append(field("versions", f"taisph {v.get('taisph')}, Taichi {v.get('taichi')}, numpy {v.get('numpy')}, "
                                   f"Python {v.get('python')}"))
    lines.append(field("machine", f"{m.get('processor')}, {m.get('cpus')} CPUs, {m.get('platform')}; "
                                  f"{m.get('arch')}, {m.get('precision')}, {m.get('threads')} thread(s)"))
    resumed = data.get("resume_of")
    if resumed:
        before = resumed.get("record") or {}
        what = (f"the run '{shlex.join(before.get('command') or [])}' of {before.get('start')} ({before.get('status')})"
                if before else "a run with no record")
        lines.append(field("resumes", f"{resumed.get('checkpoint')}: {what}"))
    lines.append(f"  (all of it: {Path(folder) / FILE})")
    return "\n".join(lines)
