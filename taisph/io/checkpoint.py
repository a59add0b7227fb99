"""Checkpoints: the complete state of a run in a folder, to continue it exactly.

A checkpoint folder holds ``state.npz`` (every particle array in its current memory
order, the device clock and dt history, the guard flags, the neighbour lists and
the cells of their last rebuild) and ``meta.pickle`` (the scene with its terms,
parameters and materials, the controls, the runtime, the grid, and where the run
was going: end time, frames left, the output folder and its frame index). Written
atomically: a temporary folder renamed over the old one. A resumed run continues
bit for bit in deterministic mode, to round-off otherwise.
"""

from __future__ import annotations

import os
import pickle
import shutil
from dataclasses import fields
from pathlib import Path

import numpy as np

VERSION = 3  # 2: neighbour lists saved; 3: the engine's parameter layout of taisph 0.2


def save(sim, folder, t_end=None, frames_left=None, writer=None) -> Path:
    """Write `sim`'s complete state to `folder` (see the module docstring)."""
    folder = Path(folder)
    tmp = folder.with_name(folder.name + ".tmp")
    if tmp.exists():
        shutil.rmtree(tmp)
    tmp.mkdir(parents=True)
    np.savez(tmp / "state.npz", **sim.state.arrays())
    meta = dict(
        version=VERSION,
        scene=sim.scene,
        controls=sim.controls,
        runtime=(sim.runtime.arch, sim.runtime.precision),
        grid=sim.state.grid,
        serial_sort=sim.serial_sort,
        t_end=t_end,
        frames_left=frames_left,
        out=str(writer.folder) if writer is not None else None,
        writer=(writer.frame, writer.entries) if writer is not None else None,
    )
    with open(tmp / "meta.pickle", "wb") as f:
        pickle.dump(meta, f)
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


def load(folder, arch=None, threads=None):
    """A :class:`taisph.Simulation` continuing exactly where :func:`save` stopped; its
    ``checkpoint_meta`` holds where the run was going."""
    from ..simulation import Simulation

    folder = Path(folder)
    if not (folder / "meta.pickle").exists():
        raise FileNotFoundError(f"{folder} is not a checkpoint folder (no meta.pickle)")
    with open(folder / "meta.pickle", "rb") as f:
        meta = pickle.load(f)
    if meta.get("version") != VERSION:
        raise ValueError(f"{folder}: checkpoint version {meta.get('version')}, this taisph reads version "
                         f"{VERSION}; resume it with the taisph that wrote it")
    saved_arch, precision = meta["runtime"]
    controls = {f.name: getattr(meta["controls"], f.name) for f in fields(meta["controls"])}
    with np.load(folder / "state.npz") as data:
        arrays = dict(data)
    sim = Simulation(meta["scene"], arch=arch or saved_arch, precision=precision, threads=threads,
                     _restore=(arrays, meta["grid"], meta["serial_sort"]), **controls)
    sim.checkpoint_meta = meta
    return sim


class CheckpointWriter:
    """A run writer: a checkpoint to `folder` every `every` frames (kept as
    ``every_frames``: a writer's ``every`` means "call on_steps every k steps",
    :meth:`taisph.Simulation.run`)."""

    def __init__(self, folder, every_frames: int, t_end: float, frames: int, frame_writer=None):
        self.folder, self.every_frames, self.t_end, self.frames = Path(folder), every_frames, t_end, frames
        self.frame_writer = frame_writer

    def on_start(self, sim):
        pass

    def on_frame(self, sim, k: int):
        if (k + 1) % self.every_frames == 0:
            save(sim, self.folder, t_end=self.t_end, frames_left=self.frames - k - 1, writer=self.frame_writer)
