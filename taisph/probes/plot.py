"""Plot a run's probes (``OUT/probes.csv``) against time, one axis per quantity and unit
(pressure in Pa, surface elevation in m, force in N, flow rate in m^2/s or m^3/s, a body's
position, orientation, velocity, angular velocity and force), labelled from the sidecar
``OUT/probes.json`` (:func:`taisph.probes.read_units`). ``python -m taisph plot OUT`` is
the command (:mod:`taisph.cli.plot`); from Python::

    from taisph.probes.plot import figure
    fig, axes = figure("out/dam_break/probes.csv")   # axes: [Axis(label, unit, columns)]
    fig.savefig("probes.png")

A CSV written before taisph wrote sidecars has no units: a body's and a force's columns are
recognised by their names, the other columns go on axes labelled "unknown unit", split by
magnitude (below 100, and above). Needs matplotlib (the ``plot`` extra:
``pip install ".[plot]"`` in taisph's folder, or ``pip install matplotlib``).
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..messages import InputError
from .spec import BODY_UNITS
from .writer import read_units

UNKNOWN = "unknown unit"  # the quantity of a column whose unit no sidecar gives


@dataclass
class Axis:
    """One axis of the figure: its y label (``quantity (unit)``), quantity, unit and columns."""

    quantity: str
    unit: str
    columns: list = field(default_factory=list)

    @property
    def label(self) -> str:
        return f"{self.quantity} ({self.unit})" if self.unit else self.quantity


def csv_of(path) -> Path:
    """The probes.csv of `path`: a run's output folder (``OUT/probes.csv``) or the CSV itself;
    an :class:`taisph.messages.InputError` saying what is missing."""
    path = Path(path)
    if path.is_dir():
        path = path / "probes.csv"
        if not path.is_file():
            raise InputError(f"{path.parent}: no probes.csv in it (a run writes one with --probe, or a case's or "
                             "a scene file's probes)")
    elif not path.is_file():
        raise InputError(f"{path}: no such {'file' if path.suffix == '.csv' else 'folder'}")
    return path


def read_table(path) -> tuple[list, np.ndarray, np.ndarray]:
    """``(header, values, sampled)`` of a probes.csv: the column names, the values (rows x
    columns, NaN where empty or ``nan``) and whether each cell holds a sample (not empty)."""
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    if not rows or rows[0][0] != "time":
        raise InputError(f"{path}: not a probes.csv (its first line is not the header time,...)")
    header, body = rows[0], [r for r in rows[1:] if len(r) == len(rows[0])]
    try:
        values = np.array([[float(c) if c else math.nan for c in r] for r in body], float).reshape(-1, len(header))
    except ValueError as err:
        raise InputError(f"{path}: a cell is not a number ({err})") from None
    sampled = np.array([[c != "" for c in r] for r in body], bool).reshape(-1, len(header))
    return header, values, sampled


def guessed_units(header, values) -> dict:
    """Units for a CSV without a sidecar: a body's columns (NAME_angle or NAME_qw among them)
    and a force's (NAME_x, NAME_y) by their names, the rest unknown (split by magnitude)."""
    units = {}
    bodies = {c.rpartition("_")[0] for c in header if c.endswith(("_angle", "_qw"))}
    for k, c in enumerate(header[1:], 1):
        base, _, end = c.rpartition("_")
        if base in bodies and end in BODY_UNITS:
            quantity, unit = BODY_UNITS[end]
        elif end in ("x", "y", "z") and f"{base}_x" in header and f"{base}_y" in header:
            quantity, unit = "force", "N"
        else:
            big = np.nanmax(np.abs(values[:, k]), initial=0.0) >= 100.0
            quantity, unit = UNKNOWN, "no probes.json; |values| " + (">= 100" if big else "< 100")
        units[c] = {"probe": base or c, "quantity": quantity, "unit": unit}
    return units


def axes_of(header, units: dict, only=None) -> list:
    """The figure's axes: one per (quantity, unit) of the columns after ``time``, in the
    CSV's order; `only` (probe or column names) keeps those columns."""
    axes: dict = {}
    for c in header[1:]:
        u = units.get(c) or {"probe": c, "quantity": UNKNOWN, "unit": "not in probes.json"}
        if only and c not in only and u.get("probe") not in only:
            continue
        key = (u["quantity"], u["unit"])
        axes.setdefault(key, Axis(*key)).columns.append(c)
    return list(axes.values())


def figure(path, only=None):
    """``(fig, axes)``: the probes of the run folder or CSV `path` against time, an
    :class:`Axis` per quantity and unit (`only`: probe or column names to keep). A dry
    pressure probe (``nan``) is a gap in its line; a probe not sampled in a row (a larger
    ``every``) is left out of that row."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path = csv_of(path)
    header, values, sampled = read_table(path)
    units = read_units(path) or guessed_units(header, values)
    axes = axes_of(header, units, set(only) if only else None)
    if not axes:
        raise InputError(f"{path}: none of {', '.join(only)} among its probes ({', '.join(header[1:])})" if only
                         else f"{path}: no probe columns")
    fig, grid = plt.subplots(len(axes), 1, figsize=(9, 0.6 + 2.6 * len(axes)), squeeze=False, sharex=True)
    for ax, spec in zip(grid[:, 0], axes):
        draw(ax, spec, header, values, sampled)
    grid[-1, 0].set_xlabel("t (s)")
    fig.suptitle(str(path), fontsize=9)
    fig.tight_layout()
    return fig, axes


def draw(ax, spec: Axis, header, values, sampled):
    """Draw the columns of `spec` (an :class:`Axis`) against time on the matplotlib axis `ax`
    (`header`, `values`, `sampled`: :func:`read_table`'s), with its label, a legend, a grid."""
    t = values[:, 0]
    for c in spec.columns:
        k = header.index(c)
        ax.plot(t[sampled[:, k]], values[sampled[:, k], k], lw=0.8, label=c)
    ax.set_ylabel(spec.label)
    ax.legend(fontsize=8, loc="best")
    ax.grid(alpha=0.3)
