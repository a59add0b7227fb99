"""Checkpoints: the complete state of a run in a folder, to continue it exactly.

A checkpoint folder holds three files, no pickle:

``state.npz``
    every particle array of the device state in its current memory order, the device
    clock and dt history, the guard flags, the neighbour lists and the cells of their
    last rebuild (:meth:`taisph.engine.state.State.arrays`);
``scene.npz``
    the scene's particle arrays (:func:`taisph.scene.serialize.scene_to_data`);
``meta.json``
    ``format`` ("taisph-checkpoint"), ``schema`` (:data:`SCHEMA`, an integer), ``taisph``
    (the version that wrote it); ``scene`` (settings, materials, equation of state, terms
    by class name with their parameters and options: :mod:`taisph.scene.serialize`),
    ``controls`` (the :class:`taisph.engine.timestep.Controls` fields), ``runtime``
    (``arch``, ``precision``), ``grid`` (``lo``, ``cell``, ``shape``), ``serial_sort``, and
    ``run``: where the run was going (``t_end``, ``frames_left``, ``output_times``: the
    output times left, where the run's writers are called, or null; ``out``, ``writer``: the
    ParaView writer's next ``frame`` and its index ``entries``, [time, part, file name]),
    and what the command line needs to go on as it was (``checkpoint_every``, ``probes``:
    the :class:`taisph.probes.Probe` fields, ``wall_groups``: {name: particle ids}).

Written atomically: a temporary folder renamed over the old one. A resumed run continues
bit for bit in deterministic mode, to round-off otherwise. A folder of another schema
(the pickled ``meta.pickle`` of versions 1-3 included) is refused by :func:`read` with
:class:`CheckpointError`, saying which version it is and what to do.
"""

from __future__ import annotations

import contextlib
import dataclasses
import json
import os
import shutil
import signal
import zipfile
from importlib import metadata
from pathlib import Path

import numpy as np

from ..engine.neighbours import GridLayout
from ..engine.timestep import Controls
from ..messages import InputError
from ..probes.spec import Probe
from ..scene.serialize import SceneDataError, plain, scene_from_data, scene_to_data, unplain

FORMAT = "taisph-checkpoint"
# 1-3: meta.pickle (2: neighbour lists saved; 3: the engine's parameter layout of taisph 0.2);
# 4: meta.json and scene.npz, no pickle; 5: the run's end time in the device status (END_TIME)
SCHEMA = 5
FILES = ("meta.json", "state.npz", "scene.npz")


class CheckpointError(InputError):
    """A folder taisph cannot resume: one line naming the folder, what it holds and what to
    do (an :class:`taisph.messages.InputError`, so a ``ValueError``: exit code 2 on the
    command line)."""


class NoCheckpoint(CheckpointError, FileNotFoundError):
    """No checkpoint there at all (no such folder, or no meta.json in it)."""


def taisph_version() -> str:
    try:
        return metadata.version("taisph")
    except metadata.PackageNotFoundError:
        return "unknown"


# --- writing -------------------------------------------------------------------------
def probe_to_data(probe) -> dict:
    """A probe's fields as JSON values; ``walls`` a group name, or ``{"ids": [...]}``,
    ``{"mask": [...]}``, ``{"slice": [start, stop, step]}``, ``{"range": [...]}``."""
    data = {f.name: getattr(probe, f.name) for f in dataclasses.fields(probe)}
    walls = data["walls"]
    if isinstance(walls, (slice, range)):
        data["walls"] = {type(walls).__name__: [walls.start, walls.stop, walls.step]}
    elif walls is not None and not isinstance(walls, str):
        walls = np.asarray(walls)
        data["walls"] = {"mask": walls.tolist()} if walls.dtype == bool else {"ids": walls.astype(int).tolist()}
    return plain(data, f"probe {probe.name!r}")


def probe_from_data(data: dict) -> Probe:
    data = unplain(data)
    walls = data.get("walls")
    if isinstance(walls, dict):
        (kind, value), = walls.items()
        if kind in ("slice", "range"):
            data["walls"] = (slice if kind == "slice" else range)(*value)
        elif kind in ("mask", "ids"):
            data["walls"] = np.asarray(value, bool if kind == "mask" else int)
        else:
            raise ValueError(f"probe {data.get('name')!r}: walls of unknown kind {kind!r}")
    for key in ("at", "to"):
        if data.get(key) is not None:
            data[key] = tuple(data[key])
    return Probe(**data)


def wall_ids(group, n: int) -> np.ndarray:
    """A wall group's particle ids: `group` ids, a boolean mask, or a slice or range of the
    `n` particle ids (a scene file's groups)."""
    if isinstance(group, (slice, range)):
        return np.arange(n)[group]
    group = np.asarray(group)
    return np.flatnonzero(group) if group.dtype == bool else group.astype(int)


def meta_of(sim, t_end=None, frames_left=None, writer=None, checkpoint_every=None, probes=None,
            wall_groups=None, output_times=None) -> tuple[dict, dict]:
    """``(meta, scene arrays)`` of `sim` and its run (see the module docstring)."""
    scene, scene_arrays = scene_to_data(sim.scene)
    grid = sim.state.grid
    run = dict(t_end=t_end, frames_left=frames_left, output_times=output_times,
               out=str(writer.folder) if writer is not None else None,
               writer=dict(frame=writer.frame, entries=writer.entries) if writer is not None else None,
               checkpoint_every=checkpoint_every,
               probes=[probe_to_data(p) for p in probes] if probes is not None else None,
               wall_groups={k: wall_ids(v, sim.scene.n).tolist() for k, v in wall_groups.items()}
               if wall_groups is not None else None)
    meta = dict(format=FORMAT, schema=SCHEMA, taisph=taisph_version(), scene=scene,
                controls={f.name: getattr(sim.controls, f.name) for f in dataclasses.fields(sim.controls)},
                runtime=dict(arch=sim.runtime.arch, precision=sim.runtime.precision),
                grid=dict(lo=grid.lo, cell=grid.cell, shape=grid.shape), serial_sort=sim.serial_sort, run=run)
    return plain(meta, "checkpoint"), scene_arrays


def save(sim, folder, t_end=None, frames_left=None, writer=None, checkpoint_every=None, probes=None,
         wall_groups=None, output_times=None) -> Path:
    """Write `sim`'s complete state to `folder` (see the module docstring); `writer` is
    the run's :class:`taisph.run.vtk.VTKWriter`, `probes` its :class:`taisph.probes.Probe`
    list and `wall_groups` the particle ids of the wall groups they name."""
    folder = Path(folder)
    meta, scene_arrays = meta_of(sim, t_end, frames_left, writer, checkpoint_every, probes, wall_groups, output_times)
    arrays = sim.state.arrays()
    tmp = folder.with_name(folder.name + ".tmp")
    with _deferred_interrupt():  # Ctrl-C now lands after the checkpoint is whole, or before it began
        try:
            if tmp.exists():
                shutil.rmtree(tmp)
            tmp.mkdir(parents=True)
            np.savez(tmp / "state.npz", **arrays)
            np.savez(tmp / "scene.npz", **scene_arrays)
            (tmp / "meta.json").write_text(json.dumps(meta, indent=1, allow_nan=False) + "\n", encoding="utf-8")
        except BaseException:
            shutil.rmtree(tmp, ignore_errors=True)  # nothing half-written left behind
            raise
        if folder.exists():
            old = folder.with_name(folder.name + ".old")
            if old.exists():
                shutil.rmtree(old)
            os.replace(folder, old)
            os.replace(tmp, folder)
            shutil.rmtree(old)
        else:
            os.replace(tmp, folder)
    return folder


@contextlib.contextmanager
def _deferred_interrupt():
    """SIGINT held back while the block runs (delivered after it), where the platform can
    (POSIX); elsewhere the block's own cleanup and :func:`check_folder`'s recovery of
    ``NAME.old`` cover an interruption."""
    block = getattr(signal, "pthread_sigmask", None)
    if block is None:
        yield
        return
    old = block(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        block(signal.SIG_SETMASK, old)


# --- reading -------------------------------------------------------------------------
def check_folder(folder) -> dict:
    """The raw ``meta.json`` of the checkpoint folder `folder`, its format and schema
    checked; :class:`CheckpointError` (one line) for anything else."""
    folder = Path(folder)
    redo = "resume it with the taisph that wrote it ({}), or rerun"
    old = folder.with_name(folder.name + ".old")
    if not folder.exists() and old.is_dir() and (old / "meta.json").exists():
        os.replace(old, folder)  # interrupted between save's two renames: the last complete one
    if not folder.is_dir():
        raise NoCheckpoint(f"{folder}: no such folder" if not folder.exists() else f"{folder} is not a folder")
    if not (folder / "meta.json").exists():
        if (folder / "meta.pickle").exists():
            raise CheckpointError(
                f"{folder}: a checkpoint of version 3 or earlier (meta.pickle), this taisph ({taisph_version()}) "
                f"reads version {SCHEMA} (meta.json): " + redo.format("one from before checkpoint version 4"))
        if (folder / "checkpoint" / "meta.json").exists() or (folder / "checkpoint" / "meta.pickle").exists():
            raise CheckpointError(f"{folder} is a run's output folder: resume {folder / 'checkpoint'}")
        raise NoCheckpoint(f"{folder} is not a checkpoint folder (no meta.json)")
    try:
        meta = json.loads((folder / "meta.json").read_text(encoding="utf-8"))
    except (ValueError, UnicodeDecodeError) as err:
        raise CheckpointError(f"{folder}: meta.json is not JSON ({err}); rerun") from None
    fmt, schema, writer = (meta.get("format"), meta.get("schema"), meta.get("taisph")) if isinstance(meta, dict) \
        else (None, None, None)
    if fmt != FORMAT:
        raise CheckpointError(f"{folder}: meta.json is not a taisph checkpoint (format {fmt!r}, version {schema!r}); "
                              f"this taisph reads format {FORMAT!r} version {SCHEMA}: rerun")
    if schema != SCHEMA:
        raise CheckpointError(f"{folder}: checkpoint version {schema!r} (written by taisph {writer}), this taisph "
                              f"({taisph_version()}) reads version {SCHEMA}: " + redo.format(f"version {writer}"))
    for name in FILES[1:]:
        if not (folder / name).exists():
            raise CheckpointError(f"{folder}: an incomplete checkpoint (no {name}); rerun")
    return meta


def read(folder) -> tuple[dict, dict]:
    """``(meta, arrays)`` of the checkpoint folder `folder` (see :func:`save`), checked:
    ``meta`` has the :class:`taisph.Scene` (``scene``), the controls as a dict, the runtime
    ``(arch, precision)``, the grid (a GridLayout), ``serial_sort``, and the run's ``t_end``,
    ``frames_left``, ``out``, ``writer`` (``(frame, entries)`` or None), ``checkpoint_every``,
    ``probes`` (a list of :class:`taisph.probes.Probe` or None), ``wall_groups`` ({name:
    ids} or None); ``arrays`` is the device state. :meth:`taisph.Simulation.from_checkpoint`
    builds the simulation from them."""
    folder = Path(folder)
    raw = check_folder(folder)
    try:
        with np.load(folder / "scene.npz") as data:
            scene = scene_from_data(raw["scene"], dict(data))
        with np.load(folder / "state.npz") as data:
            arrays = dict(data)
        meta = decode(raw)
    except (SceneDataError, KeyError, TypeError, ValueError, OSError, zipfile.BadZipFile) as err:
        what = f"no {err.args[0]!r}" if isinstance(err, KeyError) else str(err).splitlines()[0]
        raise CheckpointError(f"{folder}: a damaged checkpoint of version {SCHEMA}: {what}; rerun") from err
    meta["scene"] = scene
    return meta, arrays


def decode(raw: dict) -> dict:
    """The values of a checked ``meta.json`` (:func:`read`) as Python objects, the run's
    entries at the top level."""
    controls = unplain(raw["controls"])
    unknown = set(controls) - {f.name for f in dataclasses.fields(Controls)}
    if unknown:
        raise ValueError(f"controls this taisph does not have: {', '.join(sorted(unknown))}")
    grid = raw["grid"]
    run = unplain(raw["run"])
    writer = run["writer"]
    meta = dict(format=raw["format"], schema=raw["schema"], taisph=raw["taisph"], controls=controls,
                runtime=(raw["runtime"]["arch"], raw["runtime"]["precision"]),
                grid=GridLayout(lo=np.asarray(grid["lo"], float), cell=np.asarray(grid["cell"], float),
                                shape=tuple(int(k) for k in grid["shape"])),
                serial_sort=bool(raw["serial_sort"]))
    meta.update(run)
    meta["writer"] = (writer["frame"], [tuple(e) for e in writer["entries"]]) if writer is not None else None
    meta["probes"] = [probe_from_data(p) for p in run["probes"]] if run.get("probes") is not None else None
    groups = run.get("wall_groups")
    meta["wall_groups"] = {k: np.asarray(v, int) for k, v in groups.items()} if groups is not None else None
    return meta


# --- the run writer --------------------------------------------------------------------
def probes_of(writers) -> tuple[list | None, dict | None]:
    """``(probes, wall_groups)`` of the :class:`taisph.probes.Probes` among a run's
    `writers` (anything with ``probes`` and ``walls``), for :class:`CheckpointWriter`;
    ``(None, None)`` if there are none."""
    found = [w for w in writers if hasattr(w, "probes") and hasattr(w, "walls")]
    if not found:
        return None, None
    return [p for w in found for p in w.probes], {k: v for w in found for k, v in w.walls.items()}


class CheckpointWriter:
    """A run writer: a checkpoint to `folder` every `every` frames (kept as
    ``every_frames``: a writer's ``every`` means "call on_steps every k steps",
    :meth:`taisph.Simulation.run`), recording `every_frames` as the run's
    ``checkpoint_every`` and its `probes` and `wall_groups` (see :func:`save`)."""

    def __init__(self, folder, every_frames: int, t_end: float, frames, frame_writer=None, probes=None,
                 wall_groups=None):
        # frames: how many, or the run's output times (then those left are saved: output_times)
        self.output_times = list(frames) if not isinstance(frames, int) else None
        self.frames = frames if isinstance(frames, int) else len(self.output_times)
        self.folder, self.every_frames, self.t_end = Path(folder), every_frames, t_end
        self.frame_writer, self.probes, self.wall_groups = frame_writer, probes, wall_groups

    def on_start(self, sim):
        pass

    def on_frame(self, sim, k: int):
        if (k + 1) % self.every_frames == 0:
            left = self.output_times[k + 1:] if self.output_times is not None else None
            save(sim, self.folder, t_end=self.t_end, frames_left=max(self.frames - k - 1, 0), writer=self.frame_writer,
                 checkpoint_every=self.every_frames, probes=self.probes, wall_groups=self.wall_groups,
                 output_times=left)
