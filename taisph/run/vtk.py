"""ParaView output: one binary ``.vtu`` per frame and a ``.pvd`` index.

Layout of an output folder::

    <case>.pvd            the time series; open this in ParaView
    <case>_00000.vtu ...  fluid particles of each frame (zero-padded frame number)
    walls.vtu             wall particles, written once (static walls) and listed in
                          the index at every time as part 1
    <case>_bodies_NNNNN.vtu  the particles of moving and floating bodies of each frame
                          (scenes with bodies; part 2; their ``body`` array numbers them)

Points always have three coordinates (z = 0 in 2D). Point arrays: ``velocity``
(3 components), ``pressure``, ``density``, ``mass``, ``id`` (persistent: data is
reordered by cell every step), ``material``, and any quantity the scene's terms list as an output (e.g. ``energy``).
The time of each frame is in the
``.pvd`` only. Every file is written under a temporary name and renamed (a temporary
file an interruption leaves half-written is removed), and the index is rewritten, the
same way, after each frame's files: an interrupted run (Ctrl-C, a guard) leaves whole
files and an index that opens and lists only frames on disk.

A new series (not a resumed one) first removes an earlier series of the same name from
the folder: its frames ``<case>_NNNNN.vtu``, its ``<case>.pvd`` and the ``walls.vtu``
that index listed; no other file. The folder then holds one series, all of it listed
(a shorter rerun left the longer run's last frames beside it); the run's summary says
how many frames went.
"""

from __future__ import annotations

import contextlib
import os
import re
from pathlib import Path
from xml.sax.saxutils import quoteattr

import meshio
import numpy as np


def _points3(x: np.ndarray) -> np.ndarray:
    out = np.zeros((len(x), 3))
    out[:, : x.shape[1]] = x
    return out


@contextlib.contextmanager
def _replacing(tmp: Path, path: Path):
    """Write `tmp` in the block, then rename it to `path`; if the block ends in an exception
    (Ctrl-C included), `tmp` is removed and `path` left as it was."""
    try:
        yield
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def write_vtu(path: Path, positions, arrays: dict) -> None:
    """Write points with point arrays as a binary .vtu, atomically."""
    path = Path(path)
    points = _points3(np.asarray(positions, float))
    data = {}
    for name, values in arrays.items():
        values = np.asarray(values)
        if values.ndim == 2 and values.shape[1] != 3:
            values = _points3(values)
        data[name] = values
    cells = [("vertex", np.arange(len(points), dtype=np.int64).reshape(-1, 1))]
    tmp = path.with_name(path.name + ".tmp")
    with _replacing(tmp, path):
        meshio.write(str(tmp), meshio.Mesh(points, cells, point_data=data), file_format="vtu", binary=True)


# what each part of the index holds, named so in ParaView's pipeline browser (the DataSet's
# ``name`` attribute; unnamed, they read "Block 0", "Block 1"...)
BLOCK_NAMES = ("fluid", "walls", "bodies")


def write_pvd(path: Path, entries) -> None:
    """Write a ParaView collection; `entries` are (time, part, file name) tuples."""
    path = Path(path)
    lines = ['<?xml version="1.0"?>',
             '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
             "  <Collection>"]
    for t, part, name in entries:
        block = f' name="{BLOCK_NAMES[part]}"' if part < len(BLOCK_NAMES) else ""  # ParaView's block names
        lines.append(f'    <DataSet timestep="{float(t)!r}" group="" part="{part}"{block} file={quoteattr(name)}/>')
    lines += ["  </Collection>", "</VTKFile>", ""]
    tmp = path.with_name(path.name + ".tmp")
    with _replacing(tmp, path):
        tmp.write_text("\n".join(lines))


def read_pvd(path) -> list[tuple[float, int, str]]:
    """(time, part, file) entries of a .pvd file."""
    import xml.etree.ElementTree as ET

    root = ET.parse(path).getroot()
    return [(float(e.get("timestep")), int(e.get("part", 0)), e.get("file")) for e in root.iter("DataSet")]


def remove_series(folder, name: str, keep_walls: bool = False) -> int:
    """Remove the series `name` from `folder`: its frames (``name_NNNNN.vtu``), its index
    (``name.pvd``) and, if that index lists it and not `keep_walls`, ``walls.vtu``; no
    other file. Returns the number of frames removed."""
    folder = Path(folder)
    frame = re.compile(re.escape(name) + r"_(bodies_)?\d{5,}\.vtu")
    frames = [p for p in folder.iterdir() if frame.fullmatch(p.name) and p.is_file()]
    index = folder / f"{name}.pvd"
    walls = False
    if index.is_file():
        try:
            walls = any(file == "walls.vtu" for _, _, file in read_pvd(index))
        except Exception:  # noqa: BLE001 -- an index that does not parse lists nothing
            walls = False
    for path in frames:
        path.unlink()
    if index.is_file():
        index.unlink()
    if walls and not keep_walls:
        (folder / "walls.vtu").unlink(missing_ok=True)
    return sum(1 for path in frames if "_bodies_" not in path.name[len(name):])


class VTKWriter:
    """Writes frames of a simulation to `folder` (created if needed).

    ``removed``: frames of an earlier series of the scene's name that starting this one
    removed from `folder` (see the module docstring; none when resuming)."""

    def __init__(self, folder, sim, resume=None, initial_only: bool = False):
        """`resume`: (next frame number, index entries) of a run being continued;
        `initial_only`: write the initial frame and no other (a run of 0 frames)."""
        self.folder, self.initial_only = Path(folder), initial_only
        self.folder.mkdir(parents=True, exist_ok=True)
        self.name = sim.scene.name
        self.frame, self.entries = (0, []) if resume is None else (resume[0], list(resume[1]))
        self.walls_file = None
        # moving and floating bodies' particles: a file per frame; the other walls once
        self.bodies = sim.wall & (sim.quantity("body") > 0) if "bodies" in sim.solver.device_arrays else None
        walls = sim.wall if self.bodies is None else sim.wall & ~self.bodies
        self.removed = 0 if resume is not None else remove_series(self.folder, self.name, keep_walls=walls.any())
        if walls.any():
            self.walls_file = "walls.vtu"
            write_vtu(self.folder / self.walls_file, sim.positions()[walls], self._arrays(sim, walls))

    @staticmethod
    def _arrays(sim, select):
        arrays = {
            "velocity": sim.velocities()[select],
            "pressure": sim.pressure()[select],
            "density": sim.density()[select],
            "mass": sim.masses()[select],
            "id": sim.ids()[select].astype(np.int32),
            "material": sim.materials()[select].astype(np.int32),
        }
        for name in sim.solver.outputs:  # e.g. energy, when a term stores it
            arrays[name] = sim.quantity(name)[select]
        return arrays

    # a run writer (taisph.Simulation.run): the initial frame, then one per output time
    def on_start(self, sim):
        if sim.steps == 0:
            self.write(sim)

    def on_frame(self, sim, k: int):
        if not self.initial_only:
            self.write(sim)

    def write(self, sim) -> Path:
        fluid = sim.fluid
        name = f"{self.name}_{self.frame:05d}.vtu"
        write_vtu(self.folder / name, sim.positions()[fluid], self._arrays(sim, fluid))
        self.entries.append((sim.time, 0, name))
        if self.walls_file:
            self.entries.append((sim.time, 1, self.walls_file))
        if self.bodies is not None:
            bodies = f"{self.name}_bodies_{self.frame:05d}.vtu"
            write_vtu(self.folder / bodies, sim.positions()[self.bodies], self._arrays(sim, self.bodies))
            self.entries.append((sim.time, 2, bodies))
        write_pvd(self.folder / f"{self.name}.pvd", self.entries)
        self.frame += 1
        return self.folder / name
