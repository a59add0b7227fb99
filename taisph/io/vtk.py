"""ParaView output: one binary ``.vtu`` per frame and a ``.pvd`` index.

Layout of an output folder::

    <case>.pvd            the time series; open this in ParaView
    <case>_00000.vtu ...  fluid particles of each frame (zero-padded frame number)
    walls.vtu             wall particles, written once (static walls) and listed in
                          the index at every time as part 1

Points always have three coordinates (z = 0 in 2D). Point arrays: ``velocity``
(3 components), ``pressure``, ``density``, ``mass``, ``id`` (persistent: data is
reordered by cell every step), ``material``, and any quantity the scene's terms list as an output (e.g. ``energy``).
The time of each frame is in the
``.pvd`` only. Every file is written under a temporary name and renamed, and the
index is rewritten after each frame, so an interrupted run leaves whole files and
an index that opens.
"""

from __future__ import annotations

import os
from pathlib import Path
from xml.sax.saxutils import quoteattr

import meshio
import numpy as np


def _points3(x: np.ndarray) -> np.ndarray:
    out = np.zeros((len(x), 3))
    out[:, : x.shape[1]] = x
    return out


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
    meshio.write(str(tmp), meshio.Mesh(points, cells, point_data=data), file_format="vtu", binary=True)
    os.replace(tmp, path)


def write_pvd(path: Path, entries) -> None:
    """Write a ParaView collection; `entries` are (time, part, file name) tuples."""
    path = Path(path)
    lines = ['<?xml version="1.0"?>',
             '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
             "  <Collection>"]
    for t, part, name in entries:
        lines.append(f'    <DataSet timestep="{t:.10g}" group="" part="{part}" file={quoteattr(name)}/>')
    lines += ["  </Collection>", "</VTKFile>", ""]
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text("\n".join(lines))
    os.replace(tmp, path)


def read_pvd(path) -> list[tuple[float, int, str]]:
    """(time, part, file) entries of a .pvd file."""
    import xml.etree.ElementTree as ET

    root = ET.parse(path).getroot()
    return [(float(e.get("timestep")), int(e.get("part", 0)), e.get("file")) for e in root.iter("DataSet")]


class VTKWriter:
    """Writes frames of a simulation to `folder` (created if needed)."""

    def __init__(self, folder, sim, resume=None):
        """`resume`: (next frame number, index entries) of a run being continued."""
        self.folder = Path(folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        self.name = sim.scene.name
        self.frame, self.entries = (0, []) if resume is None else (resume[0], list(resume[1]))
        self.walls_file = None
        walls = sim.wall
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
        self.write(sim)

    def write(self, sim) -> Path:
        fluid = sim.fluid
        name = f"{self.name}_{self.frame:05d}.vtu"
        write_vtu(self.folder / name, sim.positions()[fluid], self._arrays(sim, fluid))
        self.entries.append((sim.time, 0, name))
        if self.walls_file:
            self.entries.append((sim.time, 1, self.walls_file))
        write_pvd(self.folder / f"{self.name}.pvd", self.entries)
        self.frame += 1
        return self.folder / name
