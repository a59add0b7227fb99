""":class:`Probes`: a run writer that samples probes every k steps, keeps the samples
as numpy and writes them, a row at a time, to a CSV file (``OUT/probes.csv``), with a
sidecar (``OUT/probes.json``) saying what each column measures and in which unit
(docs/probes.md); :func:`read_csv` and :func:`read_units` read them back."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np

from ..engine import status as st
from ..messages import InputError
from ..engine.integrators import PredictorCorrector
from ..engine.layout import WALL
from ..run.atomic import write_text
from .device import Sampler
from .spec import (MIN_FLUID_FRACTION, UP, Probe, check_bodies, check_inside, check_placement, face_normal,
                   face_points)

ELEVATION_FRACTION = 0.5  # the free surface: where the fluid fraction phi falls through 1/2
UNITS_FORMAT = "taisph probes 1"  # the sidecar's "format"


class Probes:
    """Sample `probes` (:class:`taisph.probes.Probe`) during a run; pass it as a
    writer, ``sim.run(t_end, writers=[probes])``.

    ``walls``    {group name: particle ids} for force probes that name a group (a
                 scene file's ``RunSettings.wall_groups``);
    ``path``     a CSV file written as samples are taken (a header, then one flushed
                 line per sample), or None;
    ``min_fluid_fraction``  a pressure probe reads NaN where the fluid fraction phi
                 at its point is below this (default 0.2; see :mod:`taisph.probes`);
    ``append``   continue an existing CSV at `path` (a resumed run) instead of
                 starting it anew;
    ``resume_time``  with `append`, the time of the checkpoint the run resumes from
                 (``sim.time``): the rows written after it (by the run that went on past
                 the checkpoint before it stopped) are dropped first, so the CSV goes on
                 exactly once, times increasing. Rows at that time were written before the
                 checkpoint (a sample is taken after its step, a checkpoint after the step
                 that reaches an output time) and are kept; with the Euler-type integrators,
                 whose rows are labelled with their step's start, it is written again.

    The probes are checked when the run starts (or at the first :meth:`sample`),
    before anything is sampled or written: a malformed probe, a wall group that does
    not exist, a point outside the scene's domain
    (:class:`taisph.probes.OutsideDomainError`) or inside a wall
    (:class:`taisph.probes.InsideWallError`, :func:`taisph.probes.check_placement`)
    raises an :class:`taisph.messages.InputError` (a ValueError) naming the probe.

    Beside the CSV, ``probes.json`` (the CSV's name with ``.json``) lists its columns with
    the quantity and unit of each (:meth:`units`, :func:`read_units`; docs/probes.md).

    A sample is taken when the run starts from a new simulation (its initial state)
    and after every ``every`` steps, ``every`` the greatest common divisor of the
    probes' own; a probe is sampled when its own ``every`` divides the steps since
    the run started, else its cell of that row is empty. Results: :attr:`times` (s),
    :attr:`values` ({name: array}, NaN where no value or not sampled; a force is
    (N, dim), a body (N, columns): :data:`taisph.probes.spec.BODY_COLUMNS`),
    :meth:`series` (one probe's own samples), :meth:`columns` (the CSV's).

    A ``body`` probe reads ``sim.bodies()`` (:class:`taisph.run.readout.BodyState`) when
    the sample is taken: the body's state after the step, and the fluid's force on it
    in that step. (With the Euler-type integrators a row is labelled with the step's
    start, the state the other probes read: the body's columns are then one step later.)
    A body probe naming a body the scene does not have is refused when the run starts.
    """

    def __init__(self, probes, walls=None, path=None, min_fluid_fraction: float = MIN_FLUID_FRACTION,
                 append: bool = False, resume_time: float | None = None):
        self.probes = [p if isinstance(p, Probe) else Probe(**p) for p in probes]
        names = [p.name for p in self.probes]
        if not self.probes:
            raise InputError("Probes needs at least one probe")
        if len(set(names)) != len(names):
            raise InputError(f"probe names must differ: {', '.join(names)}")
        self.walls = dict(walls or {})
        self.path = Path(path) if path is not None else None
        self.append = append  # a resumed run continues the file (the header stays)
        if resume_time is not None and not (isinstance(resume_time, (int, float)) and math.isfinite(resume_time)):
            raise InputError(f"resume_time = {resume_time!r}: expected a finite time (s), the checkpoint's")
        self.resume_time = None if resume_time is None else float(resume_time)
        if not 0 < min_fluid_fraction < 1:
            raise InputError(f"min_fluid_fraction = {min_fluid_fraction!r}: expected a number in (0, 1)")
        self.min_fluid_fraction = float(min_fluid_fraction)
        self.every = math.gcd(*[p.every for p in self.probes]) if all(
            isinstance(p.every, int) and p.every >= 1 for p in self.probes) else None
        self.sim = None
        self._sampler = None
        self._file = None
        self._times: list = []
        self._rows: list = []  # per sample: one float per column, NaN where no value
        self._taken: list = []  # per sample: one bool per probe
        self._steps = 0

    # --- the writer protocol (taisph.Simulation.run) ----------------------------------
    def on_start(self, sim):
        if self.sim is None:
            self._bind(sim)
        elif self.sim is not sim:
            raise ValueError("a Probes writer samples one simulation; make another for this one")
        self._steps = 0
        if self.resume_time is not None and sim.steps > 0:
            # a resumed run samples where the run it continues would have: its own every counts
            # the steps since that run's start; called every step unless the phase is the same
            self._steps = sim.steps
            if sim.steps % self.every:
                self.every = 1
        if sim.steps == 0:  # S holds the bootstrap evaluation of the initial state
            self.sample(sim, self.probes)

    def on_steps(self, sim):
        self._steps += self.every
        due = [p for p in self.probes if self._steps % p.every == 0]
        if due:
            self.sample(sim, due)

    def on_frame(self, sim, k):
        pass

    # --- set-up -----------------------------------------------------------------------
    def _bind(self, sim):
        dim = sim.dim
        for p in self.probes:
            p.check(dim)
        check_inside(self.probes, sim.scene.domain)  # before the first step: nothing sampled, no file
        check_bodies(self.probes, [b.name for b in getattr(sim.scene, "bodies", ())])
        check_placement(self.probes, sim.scene, self.walls, min_fluid_fraction=self.min_fluid_fraction)
        kinds = sim.scene.kind
        points, self._slices, groups, self._normals = [], {}, [], {}
        lo, hi = (np.asarray(v, float) for v in sim.scene.domain)
        spacing = sim.scene.dx / 2.0
        self._line = np.arange(lo[UP], hi[UP] + 0.5 * spacing, spacing)  # heights of elevation samples
        for p in self.probes:
            start = len(points)
            if p.kind == "pressure" and p.to is None:
                points.append(np.asarray(p.at, float))
            elif p.kind in ("pressure", "flow"):  # a face: the middles of its parts, at most dx/2 a side
                points += list(face_points(p.at, p.to, spacing))
                if p.kind == "flow":
                    self._normals[p.name] = face_normal(p.at, p.to)
            elif p.kind == "elevation":
                for y in self._line:
                    x = list(p.at)
                    x.insert(UP, y)
                    points.append(np.asarray(x, float))
            elif p.kind == "body":
                continue
            else:
                ids = self.walls.get(p.walls) if isinstance(p.walls, str) else p.walls
                if ids is None:
                    raise InputError(f"probe {p.name!r}: no wall group {p.walls!r}; groups: "
                                     f"{', '.join(self.walls) or 'none (pass walls={name: ids})'}")
                index = np.arange(sim.n)[ids]
                if len(index) == 0 or np.any(kinds[index] != WALL):
                    raise InputError(f"probe {p.name!r}: walls {p.walls!r} must be wall particles "
                                     f"({np.count_nonzero(kinds[index] != WALL)} of {len(index)} are not)")
                self._slices[p.name] = len(groups)
                groups.append(index)
                continue
            self._slices[p.name] = slice(start, len(points))
        # (no sampler without points or wall groups: body probes read the host's sim.bodies())
        self._sampler = Sampler(sim, np.reshape(points, (-1, dim)), groups) if points or groups else None
        self._time_lags = not isinstance(sim.solver.integrator, PredictorCorrector)
        self.sim = sim
        if self.path is not None:
            self._open()

    def _open(self):
        """Open the CSV (a new one with its header, or the one a resumed run continues,
        without the rows after `resume_time`) and write its sidecar of units."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        header = ",".join(["time", *self.columns()])
        old = self.append and self.path.exists() and self.path.stat().st_size > 0
        if old:
            lags = self._time_lags  # rows labelled with their step's start: the one at resume_time comes again
            continue_csv(self.path, header, self.resume_time, inclusive=not lags)
        write_text(units_path(self.path), json_lines(self.units()))
        self._file = open(self.path, "a" if old else "w", newline="")
        if not old:
            self._file.write(header + "\n")
        self._file.flush()

    def units(self) -> dict:
        """What the sidecar ``probes.json`` holds: the format, the dimension, the CSV's file
        name, its columns in order (``name``, ``probe``, ``kind``, ``quantity``, ``unit``;
        ``time`` first, in s) and the probes (name, kind, where, every)."""
        dim = self.sim.dim
        columns = [{"name": "time", "probe": None, "kind": "time", "quantity": "time", "unit": "s"}]
        columns += [{"name": c, "probe": p.name, "kind": p.kind, "quantity": q, "unit": u}
                    for p in self.probes for c, q, u in p.units(dim)]
        probes = [{"name": p.name, "kind": p.kind, "every": int(p.every),
                   **({"at": [float(v) for v in p.at]} if p.at is not None else {}),
                   **({"to": [float(v) for v in p.to]} if p.to else {}),
                   **({"walls": p.walls} if isinstance(p.walls, str) else {}),
                   **({"body": p.target} if p.kind == "body" else {})} for p in self.probes]
        return {"format": UNITS_FORMAT, "dim": dim, "csv": self.path.name if self.path else None,
                "columns": columns, "probes": probes}

    def columns(self) -> list:
        """The CSV's value columns (after ``time``): one per probe, x/y(/z) per force, a body's
        (:meth:`taisph.probes.Probe.columns`)."""
        dim = self.sim.dim if self.sim is not None else None
        return [c for p in self.probes for c in (p.columns(dim) if dim else [p.name])]

    # --- sampling ---------------------------------------------------------------------
    def sample(self, sim, probes=None):
        """Take a sample of `probes` (default all) from the state the last step's rates
        were computed from (see :mod:`taisph.probes`), and write its row."""
        probes = self.probes if probes is None else probes
        if self.sim is None:
            self._bind(sim)
        time = sim.device_time()
        if self._time_lags:  # Euler-type integrators: S is the state at the step's start
            time -= sim.state.read(st.DT)
        if self._times and time <= self._times[-1]:  # no new state (a guard froze the run)
            return
        due = {p.name for p in probes}
        sampler = self._sampler
        points = np.zeros(sampler.n_points if sampler else 0, bool)
        groups = np.zeros(sampler.n_groups if sampler else 0, bool)
        for p in self.probes:
            if p.name in due and p.kind != "body":
                if p.kind == "force":
                    groups[self._slices[p.name]] = True
                else:
                    points[self._slices[p.name]] = True
        if points.any() or groups.any():
            phi, pi, u, forces = sampler.sums(points, groups, time)
        bodies = sim.bodies() if any(p.kind == "body" and p.name in due for p in self.probes) else {}
        row, taken = [], []
        for p in self.probes:
            taken.append(p.name in due)
            width = self._width(p)
            if p.name not in due:
                row += [math.nan] * width
            elif p.kind == "pressure":
                part = self._slices[p.name]
                wet = phi[part] >= self.min_fluid_fraction
                values = np.where(wet, pi[part] / np.where(wet, phi[part], 1.0), 0.0)  # dry: the air's 0
                row.append(float(values.mean()) if wet.any() else math.nan)
            elif p.kind == "elevation":
                row.append(surface_height(self._line, phi[self._slices[p.name]]))
            elif p.kind == "flow":  # Q = sum over the face's equal parts of u . n times a part's measure
                part = self._slices[p.name]
                wet = phi[part] >= self.min_fluid_fraction
                normal, measure = self._normals[p.name]
                un = np.where(wet, (u[part] @ normal) / np.where(wet, phi[part], 1.0), 0.0)  # dry: no flow
                row.append(float(un.sum() * measure / len(un)))
            elif p.kind == "body":
                row += body_row(bodies[p.target])
            else:
                row += list(forces[self._slices[p.name]])
        self._times.append(time)
        self._rows.append(row)
        self._taken.append(taken)
        if self._file is not None:
            self._write(time, row, taken)

    def _write(self, time, row, taken):
        cells, k = [repr(float(time))], 0
        for p, was_taken in zip(self.probes, taken):
            width = self._width(p)
            for v in row[k : k + width]:
                cells.append(("nan" if math.isnan(v) else f"{v:.10g}") if was_taken else "")
            k += width
        self._file.write(",".join(cells) + "\n")  # one write of the whole line, then flush
        self._file.flush()

    def _width(self, p) -> int:
        """How many columns probe `p` has (1, or a force's or a body's several)."""
        return len(p.columns(self.sim.dim)) if p.kind in ("force", "body") else 1

    def close(self):
        """Close the CSV file (rows are flushed as they are written; this only frees it)."""
        if self._file is not None:
            self._file.close()
            self._file = None
        if self._sampler is not None:
            self._sampler.free()
            self._sampler = None

    def __del__(self):
        try:
            self.close()
        except Exception:
            pass

    # --- results ----------------------------------------------------------------------
    @property
    def times(self) -> np.ndarray:
        """Times of the samples (s): the time of the state each sample read."""
        return np.asarray(self._times, float)

    @property
    def values(self) -> dict:
        """{probe name: samples}, aligned with :attr:`times`; a force probe's are (N, dim),
        a body probe's (N, its columns: ``Probe.columns(dim)`` without the name)."""
        table = np.asarray(self._rows, float).reshape(len(self._rows), -1)
        out, k = {}, 0
        for p in self.probes:
            width = self._width(p)
            out[p.name] = table[:, k : k + width] if p.kind in ("force", "body") else table[:, k]
            k += width
        return out

    def series(self, name: str):
        """(times, values) of the samples probe `name` took (its own ``every``)."""
        index = [p.name for p in self.probes].index(name)
        taken = np.asarray(self._taken, bool).reshape(len(self._taken), -1)[:, index]
        return self.times[taken], self.values[name][taken]


def body_row(state) -> list:
    """A :class:`taisph.run.readout.BodyState` as a body probe's values, in the order of
    :data:`taisph.probes.spec.BODY_COLUMNS`: position, orientation, velocity, angular
    velocity, force."""
    parts = (state.position, state.orientation, state.velocity, state.angular_velocity, state.force)
    return [float(v) for part in parts for v in np.atleast_1d(np.asarray(part, float))]


def surface_height(heights, phi, fraction: float = ELEVATION_FRACTION) -> float:
    """The highest height where the fluid fraction `phi` sampled at `heights`
    (ascending) falls through `fraction` going up, linearly interpolated between
    samples; the top if phi there is still above it; NaN if phi never reaches it."""
    wet = np.flatnonzero(phi >= fraction)
    if len(wet) == 0:
        return math.nan
    k = wet[-1]
    if k == len(phi) - 1:
        return float(heights[k])
    return float(heights[k] + (phi[k] - fraction) / (phi[k] - phi[k + 1]) * (heights[k + 1] - heights[k]))


def read_csv(path) -> dict:
    """A probes.csv as {column: float array}; empty cells (not sampled) and ``nan``
    (no value) are NaN; lines starting with ``#`` are comments."""
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    if not rows:
        raise InputError(f"{path}: empty (no header line: time, then the probes' columns)")
    header, body = rows[0], rows[1:]
    return {name: np.array([float(r[k]) if r[k] else math.nan for r in body]) for k, name in enumerate(header)}


def units_path(path) -> Path:
    """The sidecar of the CSV `path`: the same name with ``.json`` (``OUT/probes.json``)."""
    path = Path(path)
    side = path.with_suffix(".json")
    return side if side != path else path.with_name(path.name + ".units.json")


def read_units(path) -> dict | None:
    """{column: {"probe", "kind", "quantity", "unit"}} of the probes.csv `path`, from its
    sidecar (:func:`units_path`); None if there is none (a CSV written before taisph wrote
    them). An unreadable sidecar is an :class:`taisph.messages.InputError` naming it."""
    side = units_path(path)
    if not side.is_file():
        return None
    try:
        data = json.loads(side.read_text())
        columns = {c["name"]: {k: c.get(k) for k in ("probe", "kind", "quantity", "unit")} for c in data["columns"]}
    except (ValueError, KeyError, TypeError) as err:
        raise InputError(f"{side}: not a probes sidecar ({type(err).__name__}: {err})") from None
    return columns


def json_lines(data: dict) -> str:
    """`data` (a dict of scalars and lists) as JSON with one line per scalar and per list item."""
    def item(key, value):
        if not isinstance(value, list):
            return f" {json.dumps(key)}: {json.dumps(value)}"
        return f" {json.dumps(key)}: [\n" + ",\n".join(f"  {json.dumps(v)}" for v in value) + "\n ]"
    return "{\n" + ",\n".join(item(k, v) for k, v in data.items()) + "\n}\n"


def continue_csv(path, header: str, resume_time: float | None, inclusive: bool = True):
    """Make the probes.csv `path` ready for a resumed run to append to: its header must be
    `header` (the same probes; else an InputError), a last line cut short by a stopped run
    is dropped, and with `resume_time` so is every row later than it (at it too unless
    `inclusive`), through :func:`taisph.run.atomic.write_text`; comment lines stay."""
    lines = Path(path).read_text().splitlines(keepends=True)
    body = [k for k, line in enumerate(lines) if not line.startswith("#")]
    if not body or lines[body[0]].rstrip("\r\n") != header:
        found = lines[body[0]].rstrip("\r\n") if body else "(no header)"
        raise InputError(f"{path}: its columns ({found}) are not the resumed run's probes' ({header}); move it "
                         "away to start a new one")
    keep = lines[: body[0] + 1]
    width = header.count(",") + 1
    for line in lines[body[0] + 1 :]:
        if line.startswith("#"):
            keep.append(line)
            continue
        if not line.endswith("\n") or line.count(",") + 1 != width:
            continue  # cut short
        try:
            t = float(line.split(",", 1)[0])
        except ValueError:
            continue
        if resume_time is None or t < resume_time or (inclusive and t == resume_time):
            keep.append(line)
    if keep != lines:
        write_text(path, "".join(keep))
