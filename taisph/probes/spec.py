"""What a probe is: :class:`Probe` (also what a scene file's ``[[probes]]`` become) and
the constructors :func:`pressure`, :func:`elevation`, :func:`force`. Plain Python."""

from __future__ import annotations

import math
from dataclasses import dataclass

KINDS = ("pressure", "elevation", "force")
UP = 1  # the vertical axis: y, in 2D and 3D


@dataclass
class Probe:
    """A measurement: ``pressure`` at the point `at` (dim numbers), or averaged over
    the segment from `at` to `to` (a sensor's face), ``elevation``
    (free-surface height) along the vertical line through `at` (x in 2D, (x, z) in
    3D), ``force`` on the wall group `walls` (its name in a scene file, or in Python
    a name the :class:`taisph.probes.Probes` writer is given ids for, or the particle
    ids themselves: a slice, range, boolean mask or integer array); taken every
    `every` steps."""

    name: str
    kind: str
    at: tuple | None = None
    walls: object = None
    every: int = 1
    to: tuple | None = None

    def columns(self, dim: int) -> list:
        """Its columns in probes.csv: the name, or ``name_x, name_y(, name_z)`` for a force."""
        return [f"{self.name}_{a}" for a in "xyz"[:dim]] if self.kind == "force" else [self.name]

    def check(self, dim: int):
        """ValueError naming the probe if it is malformed for a `dim`-D scene."""
        if not (isinstance(self.name, str) and self.name) or any(c in self.name for c in ',"\n'):
            raise ValueError(f"probe name {self.name!r}: expected a non-empty name without commas or quotes")
        if self.kind not in KINDS:
            raise ValueError(f"probe {self.name!r}: kind {self.kind!r}; expected one of {', '.join(KINDS)}")
        if not (isinstance(self.every, int) and not isinstance(self.every, bool) and self.every >= 1):
            raise ValueError(f"probe {self.name!r}: every = {self.every!r}; expected an integer >= 1 (steps)")
        if self.kind == "force":
            if self.walls is None:
                raise ValueError(f"probe {self.name!r}: a force probe needs walls (a wall group)")
            return
        n = dim if self.kind == "pressure" else dim - 1
        for key in ("at", "to"):
            value = getattr(self, key)
            if key == "to" and (value is None or self.kind != "pressure"):
                if value is not None:
                    raise ValueError(f"probe {self.name!r}: to = {value!r}; only a pressure probe takes to")
                continue
            if not (isinstance(value, (tuple, list)) and len(value) == n and all(_finite(v) for v in value)):
                what = "a point" if self.kind == "pressure" else "the horizontal position of its vertical line"
                raise ValueError(f"probe {self.name!r}: {key} = {value!r}; a {self.kind} probe in {dim}D takes "
                                 f"{what}, {n} number(s)")


def _finite(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def pressure(name: str, at, every: int = 1, to=None) -> Probe:
    """Pressure at the point `at` (Shepard interpolation of the fluid's pressure), or
    its mean over the segment from `at` to `to` (a sensor's face; dry parts count as 0)."""
    return Probe(name, "pressure", at=tuple(float(v) for v in at), every=every,
                 to=None if to is None else tuple(float(v) for v in to))


def elevation(name: str, at, every: int = 1) -> Probe:
    """Free-surface height along the vertical line through `at` (x, or (x, z) in 3D)."""
    at = (at,) if isinstance(at, (int, float)) else at
    return Probe(name, "elevation", at=tuple(float(v) for v in at), every=every)


def force(name: str, walls, every: int = 1) -> Probe:
    """Pressure force of the fluid on the wall particles `walls` (ids or a group name)."""
    return Probe(name, "force", walls=walls, every=every)


def parse(text: str, dim: int) -> Probe:
    """A probe from the command line's ``--probe KIND:NAME:WHERE[:EVERY]``:
    ``pressure:P1:3.22,0.16`` (a point), ``elevation:gauge:0.6:10`` (the vertical line at
    x = 0.6, every 10 steps), ``force:F:walls`` (a wall group: ``walls``, all wall
    particles of a case, or a scene file's group name). ValueError naming the text."""
    parts = text.split(":")
    if len(parts) not in (3, 4) or parts[0] not in KINDS or not parts[1]:
        raise ValueError(f"--probe {text}: expected KIND:NAME:WHERE[:EVERY], KIND one of {', '.join(KINDS)} "
                         "(e.g. pressure:P1:3.22,0.16, elevation:gauge:0.6:10, force:F:walls)")
    kind, name, where = parts[:3]
    every = 1
    if len(parts) == 4:
        try:
            every = int(parts[3])
        except ValueError:
            every = parts[3]
    if kind == "force":
        probe = Probe(name, kind, walls=where, every=every)
    else:
        try:
            at = tuple(float(v) for v in where.split(","))
        except ValueError:
            raise ValueError(f"--probe {text}: {where!r} is not comma-separated numbers") from None
        probe = Probe(name, kind, at=at, every=every)
    try:
        probe.check(dim)
    except ValueError as err:
        raise ValueError(f"--probe {text}: {err}") from None
    return probe
