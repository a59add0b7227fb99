"""Scene files: the ``[[open_boundaries]]`` blocks, inflow and outflow zones
(:meth:`taisph.Scene.add_open_boundary`, :mod:`taisph.scene.open_boundary`).

:func:`zones` checks the blocks for :mod:`.scenefile_spec` (every key, a velocity table's
CSV file included, before anything is built; what depends on the fluid, such as whether
the face borders it, is checked when the zone is added); :func:`add` adds them to the
built scene for :mod:`.scenefile`, naming the block if the scene refuses one. Errors read
``FILE: open_boundaries[0].pressure = 'high': expected a number``, as the other blocks'.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..engine import smoothing
from ..messages import InputError
from ..geometry.shapes import support_layers
from ..scene.open_boundary import face_sides, is_zone_name, perpendicular, whole_spacings
from ..scene.parameters import (BYTES_PER_PARTICLE, between, finite, integer, memory_shortage, one_of,
                                position_component, positive, velocity_component)
from ..terms.open_boundary import PROFILES

MISSING = object()  # a key the file does not have (the spec reader's too)
KEYS = {"name", "at", "to", "normal", "layers", "velocity", "profile", "period", "pressure", "material"}
RANGES = {"layers": integer(at_least=1, at_most=1000), "velocity": velocity_component, "profile": one_of(*PROFILES),
          "period": positive, "pressure": between(0, 1e9), "at": position_component}


@dataclass
class Zone:
    """A checked ``[[open_boundaries]]`` block: the arguments of ``Scene.add_open_boundary``."""

    key: str  # e.g. "open_boundaries[0]", for messages
    value: dict  # its face (and normal) as in the file, for messages
    name: str
    at: tuple
    to: tuple
    normal: tuple | None = None
    layers: int | None = None
    velocity: object = None  # None, a speed, a vector or an (M, 2) array of (t, speed) rows
    profile: str = "uniform"
    period: float | None = None
    pressure: float | None = None
    material: int = 0
    table: str | None = None  # the CSV file the velocity came from, as the file names it

    def arguments(self) -> dict:
        return {k: getattr(self, k) for k in ("name", "at", "to", "normal", "velocity", "pressure", "profile", "period",
                                              "layers", "material")}


def zones(check, entries, spec, material_names) -> list:
    """The checked blocks `entries` of the spec `spec` (`check`: the spec reader's checker)."""
    out, names = [], {}
    for k, entry in enumerate(entries):
        key = f"open_boundaries[{k}]"
        check.keys(key, entry, KEYS)
        name = check.text(f"{key}.name", entry.get("name", MISSING))
        if not is_zone_name(name):
            check.fail(f"{key}.name", name,
                       "expected a word of letters, digits and _ (it names the zone's parameters)")
        if name in names:
            check.fail(f"{key}.name", name, f"already the name of open_boundaries[{names[name]}]")
        names[name] = k
        at, to = (check.vector(f"{key}.{p}", entry.get(p, MISSING), spec.dim, RANGES["at"]) for p in ("at", "to"))
        zone = Zone(key, {p: entry[p] for p in ("at", "to", "normal") if p in entry}, name, at, to)
        counts = _face(check, zone, spec)  # particles along each side of the face
        if "normal" in entry:
            zone.normal = check.vector(f"{key}.normal", entry["normal"], spec.dim)
            _normal(check, zone, spec.dim)
        support = smoothing.KERNELS[spec.kernel].support * spec.h_factor * spec.dx
        least = support_layers(support, spec.dx)
        if "layers" in entry:
            zone.layers = check.number(f"{key}.layers", entry["layers"], RANGES["layers"])
            if zone.layers < least:
                check.fail(f"{key}.layers", zone.layers, f"a buffer {zone.layers} dx deep is less than the kernel "
                           f"support {support:g} m: at least {least} layers (default: one more)")
        count = math.prod(counts) * (zone.layers or least + 1)  # the buffer's particles, before any is made
        if problem := memory_shortage(count, BYTES_PER_PARTICLE):
            check.fail(f"{key}.to", zone.value["to"],
                       f"a buffer of {count:.3g} particles at dx = {spec.dx:g}, {problem}")
        zone.profile = check.choice(f"{key}.profile", entry.get("profile", "uniform"), RANGES["profile"])
        if "pressure" in entry:
            zone.pressure = check.number(f"{key}.pressure", entry["pressure"], RANGES["pressure"])
        if "velocity" in entry:
            zone.velocity = _velocity(check, key, entry["velocity"], spec)
            zone.table = entry["velocity"] if isinstance(entry["velocity"], str) else None
        if "period" in entry:
            zone.period = check.number(f"{key}.period", entry["period"], RANGES["period"])
            if zone.table is None:
                check.fail(f"{key}.period", entry["period"], 'repeats a velocity table: give velocity = "FILE.csv"')
        if "material" in entry:
            material = check.text(f"{key}.material", entry["material"])
            if material not in material_names:
                check.fail(f"{key}.material", material, f"no such material; defined: {', '.join(material_names)}")
            zone.material = material_names.index(material)
        out.append(zone)
    return out


def _face(check, zone, spec) -> list:
    """The face: a segment (2D) or a rectangle in a coordinate plane (3D), a whole number of dx along each
    side (the scene's checks, :mod:`taisph.scene.open_boundary`); returns the particles along each side."""
    sides = face_sides(zone.at, zone.to, spec.dim)
    if sides is None:
        check.fail(f"{zone.key}.to", zone.value["to"], "the face from at to to is " + (
            "a segment of non-zero length" if spec.dim == 2 else
            "a rectangle in a coordinate plane: at and to differ in exactly two coordinates"))
    for side in sides:
        if not whole_spacings(side, spec.dx):
            check.fail(f"{zone.key}.to", zone.value["to"], f"the face's side {side:g} m is not a whole number of "
                       f"particle spacings dx = {spec.dx:g} m (its buffer is dx-spaced rows of particles)")
    return [round(side / spec.dx) for side in sides]


def _normal(check, zone, dim):
    """The normal: a non-zero vector perpendicular to the face (the scene's check)."""
    if not float(np.linalg.norm(zone.normal)) > 0:
        check.fail(f"{zone.key}.normal", zone.value["normal"], "expected a non-zero vector (into the fluid)")
    if not perpendicular(zone.normal, zone.at, zone.to, dim):
        check.fail(f"{zone.key}.normal", zone.value["normal"], "not perpendicular to the face from at to to")


def _velocity(check, key, value, spec):
    """A speed along the normal, a vector of dim numbers, or a CSV file of (t, speed) rows."""
    key = f"{key}.velocity"
    if isinstance(value, list):
        return check.vector(key, value, spec.dim, RANGES["velocity"])
    if isinstance(value, str):
        return read_table(check, key, value, spec.path.parent / value)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        check.fail(key, value, f'expected a speed (m/s, along the normal), a list of {spec.dim} numbers or "FILE.csv"')
    return check.number(key, value, RANGES["velocity"])


def read_table(check, key, value, path: Path) -> np.ndarray:
    """The (t, speed) rows of the CSV file `path` (`value` as the scene file names it, relative to it):
    two numbers a line, commas between them; blank lines and lines starting with # are skipped."""
    try:
        text = path.read_text() if path.is_file() else None
    except (OSError, ValueError) as err:  # ValueError: a NUL in the name, UnicodeDecodeError
        check.fail(key, value, f"{path}: cannot be read: {err}")
    if text is None:
        check.fail(key, value, f"{path}: no such velocity table (a CSV file of t, speed rows)")
    rows, lines = [], []
    for number, line in enumerate(text.splitlines(), 1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        cells = [c.strip() for c in line.split(",")]
        if len(cells) != 2:
            check.fail(key, value,
                       f"{path}, line {number}: {line.strip()!r}: expected two numbers, t (s) and speed (m/s)")
        try:
            t, u = (float(c) for c in cells)
        except ValueError:
            check.fail(key, value, f"{path}, line {number}: {line.strip()!r}: not a number")
        if not (finite.accepts(t) and RANGES["velocity"].accepts(u)):
            check.fail(key, value, f"{path}, line {number}: {line.strip()!r}: t must be finite and the speed "
                       f"{RANGES['velocity'].describe()}")
        if t < 0 or (rows and t <= rows[-1][0]):
            check.fail(key, value, f"{path}, line {number}: t = {t:g} s: the times must increase from t >= 0"
                       + (f" (line {lines[-1]} has t = {rows[-1][0]:g} s)" if rows else ""))
        rows.append((t, u))
        lines.append(number)
    if len(rows) < 2:
        check.fail(key, value, f"{path}: {len(rows)} (t, speed) row(s); a table needs at least 2 (a constant: "
                   "velocity = SPEED)")
    return np.array(rows)


def add(spec, scene, zone: Zone, error):
    """Add the zone to the built scene; its refusal (:func:`taisph.scene.open_boundary.zone_problem`: a face
    that does not border the fluid, walls across its buffer...) raised as `error` naming the block:
    ``FILE: open_boundaries[k] = {its face}: open boundary 'NAME': problem``."""
    try:
        scene.add_open_boundary(**zone.arguments())
    except InputError as err:
        problem = str(err).split(": ", 1)[1] if str(err).startswith("scene ") else str(err)
        raise error(f"{spec.path}: {zone.key} = {zone.value!r}: {problem}") from None
