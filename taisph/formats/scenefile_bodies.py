"""Scene files: the ``[[bodies]]`` blocks, moving and floating rigid bodies
(:meth:`taisph.Scene.add_body`, :mod:`taisph.scene.bodies`).

:func:`blocks` checks the blocks for :mod:`.scenefile_spec` (every key, a wave maker's
parameters and a trajectory's CSV file included, before anything is built); :func:`add`
adds a body to the built scene for :mod:`.scenefile`: its shape filled with wall
particles on the scene's lattice (a solid body, as a fluid block is filled), after the
fluid and the walls, naming the block if the scene refuses it (a body overlapping the
water or the walls). Errors read ``FILE: bodies[0].density = -1.0: must be ...``, as the
other blocks'.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..messages import InputError
from ..scene import wave_makers
from ..scene.bodies import FIXABLE, MOTIONS
from ..scene.parameters import (BYTES_PER_PARTICLE, Number, between, end_time, memory_shortage, one_of,
                                position_component, velocity_component)
from .scenefile_open import MISSING  # a key the file does not have (the spec reader's too)

SHAPES = ("box", "mesh", "polygon")  # the keys that give a block its shape (fluid, walls and bodies)
WAVE_MAKERS = {"piston": ("height", "period", "depth", "ramp"), "flap": ("height", "period", "depth", "ramp"),
               "solitary": ("height", "depth")}
FLOATING = ("density", "mass", "inertia", "velocity", "angular_velocity", "fixed", "hinge")  # a floating body's own
PRESCRIBED = ("wave_maker", "trajectory", "height", "period", "depth", "ramp", "axis", "until")  # a prescribed one's
KEYS = {"name", "motion", *SHAPES, "scale", "translate", "centre", *FLOATING, *PRESCRIBED}
RANGES = {"motion": one_of(*MOTIONS), "wave_maker": one_of(*WAVE_MAKERS), "density": between(1e-3, 1e5),
          "mass": between(1e-9, 1e12), "inertia": between(1e-12, 1e15), "velocity": velocity_component,
          "angular_velocity": between(-1e4, 1e4), "centre": position_component, "height": Number(0, 1e4, low_open=True),
          "period": Number(0, 1e4, low_open=True), "depth": Number(0, 1e4, low_open=True), "ramp": between(0, 1e3),
          "until": end_time, "axis": between(-1e6, 1e6), "trajectory": position_component, "hinge": position_component}


@dataclass
class BodyBlock:
    """A checked ``[[bodies]]`` block: its shape and the arguments of ``Scene.add_body``."""

    key: str  # e.g. "bodies[0]", for messages
    name: str
    shape: str  # which key gave the shape: box, mesh or polygon
    value: object  # its value in the file, for messages
    box: tuple | None = None
    surface: object = None
    motion: str = "floating"
    arguments: dict = field(default_factory=dict)  # Scene.add_body's keyword arguments
    given: dict = field(default_factory=dict)  # the block's keys as in the file, for messages

    @property
    def bounds(self):
        return self.box if self.box is not None else self.surface.bounds


def blocks(check, entries, spec, wall_names) -> list:
    """The checked blocks `entries` of the spec `spec` (`check`: the spec reader's checker;
    `wall_names`: the wall groups', which a body's name must not repeat)."""
    out, names = [], {}
    for k, entry in enumerate(entries):
        key = f"bodies[{k}]"
        check.keys(key, entry, KEYS)
        name = check.text(f"{key}.name", entry.get("name", MISSING))
        if name in names or name in wall_names:
            check.fail(f"{key}.name", name, f"already the name of bodies[{names[name]}]" if name in names else
                       "already the name of a wall group (a body's name is its wall group's, for force probes)")
        names[name] = k
        shapes = [s for s in SHAPES if s in entry]
        if len(shapes) != 1:
            check.fail(key, {s: entry[s] for s in shapes} if shapes else MISSING,
                       "give exactly one of box = [lo, hi], mesh = \"file\" or polygon = [[x, y], ...]")
        shape = shapes[0]
        block = BodyBlock(key, name, shape, entry[shape] if shape != "polygon" else "[...]", given=entry)
        if shape == "box":
            for extra in sorted({"scale", "translate"} & set(entry)):
                check.fail(f"{key}.{extra}", entry[extra], "applies to a mesh or polygon, not a box")
            block.box = check.box(f"{key}.box", entry["box"], spec.dim)
        else:
            block.surface = check.surface(key, shape, entry, spec.dim)
        _memory(check, block, spec)
        block.motion = check.choice(f"{key}.motion", entry.get("motion", "floating"), RANGES["motion"])
        args = block.arguments
        if "centre" in entry:
            args["centre"] = check.vector(f"{key}.centre", entry["centre"], spec.dim, RANGES["centre"])
        (_floating if block.motion == "floating" else _prescribed)(check, key, entry, spec, args)
        out.append(block)
    return out


def _memory(check, block, spec):
    lo, hi = block.bounds
    count = math.prod(float(b - a) / spec.dx + 1.0 for a, b in zip(lo, hi))
    if problem := memory_shortage(count, BYTES_PER_PARTICLE):
        check.fail(f"{block.key}.{block.shape}", block.value, f"fills a body with {count:.3g} particles, {problem}")


def _floating(check, key, entry, spec, args):
    """A floating body's keys: density or mass, inertia, velocity, angular_velocity, fixed,
    hinge (and with it in 3D the hinge's axis)."""
    for extra in PRESCRIBED:
        if extra == "axis" and "hinge" in entry and spec.dim == 3:
            continue  # a 3D hinge's axis
        if extra in entry:
            check.fail(f"{key}.{extra}", entry[extra], "a floating body takes no " + extra
                       + '; a body that follows a given motion has motion = "prescribed"')
    if ("density" in entry) == ("mass" in entry):
        what = "give its density or its mass, not both" if "mass" in entry else \
            "a floating body needs its density (kg/m^3, of its particles' volume) or its mass (kg; per metre in 2D)"
        check.fail(f"{key}.mass" if "mass" in entry else f"{key}.density", entry.get("mass", MISSING), what)
    for k in ("density", "mass"):
        if k in entry:
            args[k] = check.number(f"{key}.{k}", entry[k], RANGES[k])
    d = spec.dim
    if "inertia" in entry:
        value = entry["inertia"]
        if d == 2 or not isinstance(value, list) or len(value) != 3 or not all(isinstance(r, list) for r in value):
            args["inertia"] = (check.number(f"{key}.inertia", value, RANGES["inertia"]) if d == 2 else
                               check.vector(f"{key}.inertia", value, 3, RANGES["inertia"]))
        else:  # a 3 x 3 matrix (symmetric positive: Scene.add_body checks)
            args["inertia"] = [check.vector(f"{key}.inertia[{r}]", row, 3, between(-1e15, 1e15))
                               for r, row in enumerate(value)]
    if "velocity" in entry:
        args["velocity"] = check.vector(f"{key}.velocity", entry["velocity"], d, RANGES["velocity"])
    if "angular_velocity" in entry:
        value, rng = entry["angular_velocity"], RANGES["angular_velocity"]
        args["angular_velocity"] = (check.number(f"{key}.angular_velocity", value, rng) if d == 2 else
                                    check.vector(f"{key}.angular_velocity", value, 3, rng))
    if "fixed" in entry:
        value = entry["fixed"]
        if not isinstance(value, list):
            check.fail(f"{key}.fixed", value,
                       f"expected a list of the degrees of freedom held, of {', '.join(FIXABLE[d])}")
        for k, v in enumerate(value):
            if v not in FIXABLE[d]:
                check.fail(f"{key}.fixed[{k}]", v, f"not a degree of freedom of a {d}D body: {', '.join(FIXABLE[d])}")
        args["fixed"] = tuple(value)
    if "hinge" in entry:
        args["hinge"] = check.vector(f"{key}.hinge", entry["hinge"], d, RANGES["hinge"])
        if "axis" in entry:
            args["axis"] = check.vector(f"{key}.axis", entry["axis"], 3, RANGES["axis"])


def _prescribed(check, key, entry, spec, args):
    """A prescribed body's keys: a wave maker and its parameters, or a trajectory file; axis, until."""
    for extra in FLOATING:
        if extra in entry:
            check.fail(f"{key}.{extra}", entry[extra], f"a prescribed body takes no {extra} (its motion is given); "
                       'a body the water moves has motion = "floating"')
    if ("wave_maker" in entry) == ("trajectory" in entry):
        check.fail(f"{key}.trajectory" if "trajectory" in entry else f"{key}.wave_maker",
                   entry.get("trajectory", MISSING),
                   'a prescribed body follows either a wave maker (wave_maker = "piston", "flap" or "solitary") '
                   'or a trajectory file (trajectory = "FILE.csv"): exactly one of them')
    if "axis" in entry:
        args["axis"] = check.vector(f"{key}.axis", entry["axis"], spec.dim, RANGES["axis"])
        if not any(args["axis"]):
            check.fail(f"{key}.axis", entry["axis"], "expected a non-zero direction")
    if "until" in entry:
        args["until"] = check.number(f"{key}.until", entry["until"], RANGES["until"])
    if "trajectory" in entry:
        for extra in WAVE_MAKERS["piston"]:
            if extra in entry:
                check.fail(f"{key}.{extra}", entry[extra],
                           "a wave maker's parameter; the trajectory file gives the motion")
        value = check.text(f"{key}.trajectory", entry["trajectory"])
        args["trajectory"] = read_trajectory(check, f"{key}.trajectory", value, spec.path.parent / value, spec.dim)
        return
    maker = check.choice(f"{key}.wave_maker", entry["wave_maker"], RANGES["wave_maker"])
    keys = WAVE_MAKERS[maker]
    for extra in WAVE_MAKERS["piston"]:
        if extra in entry and extra not in keys:
            check.fail(f"{key}.{extra}", entry[extra], f"a {maker} wave maker takes {', '.join(keys)}, not {extra}")
    values = {k: check.number(f"{key}.{k}", entry.get(k, 2.0 if k == "ramp" else MISSING), RANGES[k]) for k in keys}
    if maker == "flap" and "centre" not in entry:
        check.fail(f"{key}.centre", MISSING, "a flap turns about its hinge: give centre, the hinge's position")
    g = float(np.linalg.norm(spec.gravity)) or wave_makers.G
    try:
        args["trajectory"] = (wave_makers.solitary_piston(values["height"], values["depth"], g) if maker == "solitary"
                              else getattr(wave_makers, maker)(**values, g=g))
    except (InputError, ArithmeticError, RuntimeError) as err:  # a wave too steep, a dispersion relation unsolved
        check.fail(f"{key}.height", values["height"], f"{maker} wave maker: {err}")


def read_trajectory(check, key, value, path: Path, dim: int) -> np.ndarray:
    """The (M, dim + 2) rows (t, x, y(, z), angle) of the CSV file `path` (`value` as the
    scene file names it, relative to it): a header line naming the columns, then a row of
    numbers a line, commas between them; blank lines and lines starting with # are skipped.
    x, y(, z) is the body's displacement from its start (m), angle its rotation (rad)."""
    columns = ["t", *"xyz"[:dim], "angle"]
    try:
        text = path.read_text() if path.is_file() else None
    except (OSError, ValueError) as err:  # ValueError: a NUL in the name, UnicodeDecodeError
        check.fail(key, value, f"{path}: cannot be read: {err}")
    if text is None:
        check.fail(key, value,
                   f"{path}: no such trajectory file (a CSV file: a header {', '.join(columns)}, then rows)")
    rows, lines, header = [], [], None
    for number, line in enumerate(text.splitlines(), 1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        cells = [c.strip() for c in line.split(",")]
        if header is None:
            header = [c.lower() for c in cells]
            if header != columns:
                check.fail(key, value, f"{path}, line {number}: {line.strip()!r}: expected the header "
                           f"{', '.join(columns)} (a {dim}D body's columns)")
            continue
        if len(cells) != len(columns):
            check.fail(key, value, f"{path}, line {number}: {line.strip()!r}: expected {len(columns)} numbers, "
                       f"{', '.join(columns)}")
        try:
            row = [float(c) for c in cells]
        except ValueError:
            check.fail(key, value, f"{path}, line {number}: {line.strip()!r}: not a number")
        if not all(RANGES["trajectory"].accepts(v) for v in row):
            check.fail(key, value, f"{path}, line {number}: {line.strip()!r}: every value must be "
                       f"{RANGES['trajectory'].describe()}")
        if rows and row[0] <= rows[-1][0]:
            check.fail(key, value, f"{path}, line {number} (row {len(rows) + 1}): t = {row[0]:g} s: the times must "
                       f"increase (line {lines[-1]} has t = {rows[-1][0]:g} s)")
        rows.append(row)
        lines.append(number)
    if len(rows) < 2:
        check.fail(key, value, f"{path}: {len(rows)} row(s) of numbers; a trajectory needs at least 2")
    return np.array(rows)


def add(spec, scene, block: BodyBlock, points, error):
    """Add the body of `block`, made of the wall particles `points` (its shape filled on the
    scene's lattice), to the built scene; returns its particles' ids (its wall group). A
    refusal of the scene (:func:`taisph.scene.bodies.add`: a body overlapping the water or
    the walls, a trajectory out of the domain...) is raised as `error` naming the block's key:
    ``FILE: bodies[0].box = [[...]]: body 'box' overlaps the fluid at t = 0: ...``."""
    if len(points) == 0:
        raise error(f"{spec.path}: {block.key}.{block.shape} = {block.value!r}: no body particle fits in it at "
                    f"dx = {spec.dx:g} (it is thinner than the lattice); make it larger or dx smaller")
    try:
        return scene.add_body(block.name, np.asarray(points, float), block.motion, **block.arguments).ids
    except InputError as err:
        rest = str(err).removeprefix(f"body {block.name!r}").lstrip(":").split()
        word = rest[0].rstrip(":,") if rest else ""
        if word in block.given and word not in SHAPES:  # a key of the block (inertia, trajectory...)
            k, value = word, block.given[word]
        elif word == "trajectory":  # a wave maker's motion
            k, value = "wave_maker", block.given.get("wave_maker")
        else:  # its particles: where it lies
            k, value = block.shape, block.value
        raise error(f"{spec.path}: {block.key}.{k} = {value!r}: {err}") from None
