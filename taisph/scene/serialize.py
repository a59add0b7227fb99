"""A :class:`Scene` as plain data and back: a dict of JSON values and a dict of numpy arrays.

    data, arrays = scene_to_data(scene)      # json.dumps(data); np.savez(path, **arrays)
    scene = scene_from_data(data, arrays)

No pickle: what is stored is the scene's settings, its materials (``{"class": "Material"
or "Gas", ...their fields}``), its equation of state (``{"name", "class", "options"}``:
the arguments of its constructor), and each term as ``{"name": term.name, "class":
class name, "params": {runtime parameter: value}, "options": {compile-time option:
value}}``, rebuilt as ``Class(**options, **params)`` through the registries below
(:data:`TERMS`, :data:`EOS`, :data:`MATERIALS`), by class name: moving a module changes
nothing. A term of a class outside the registry (a user's own) also records its module,
imported when the scene is rebuilt. The particle arrays (``position``, ``velocity``,
``mass``, ``density``, ``kind``, ``material``) and the further quantities
(``quantity.NAME``) are the arrays, in the scene's dtypes.

JSON has no infinity or NaN: such a float is written as ``{"float": "inf"}`` (``"-inf"``,
``"nan"``), see :func:`plain` and :func:`unplain`.
"""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import math

import numpy as np

from ..eos import IdealGas, Tait
from ..messages import InputError
from ..terms.base import Term  # (imports taisph.terms, and so every built-in term)
from .model import Gas, Material, Scene


def _subclasses(cls):
    for sub in cls.__subclasses__():
        yield sub
        yield from _subclasses(sub)


TERMS = dict(sorted((cls.__name__, cls) for cls in _subclasses(Term) if cls.__module__.startswith("taisph.terms.")))
EOS = {cls.__name__: cls for cls in (Tait, IdealGas)}
MATERIALS = {cls.__name__: cls for cls in (Material, Gas)}
ARRAYS = ("position", "velocity", "mass", "density", "kind", "material")
QUANTITY = "quantity."  # prefix of the further quantities' arrays
WALL_GROUP = "wall_group."  # prefix of the wall groups' particle indices
BODY = "body."  # prefix of a body's arrays (its particles, its motion table)
SPECIAL = set(ARRAYS) | {"quantities", "materials", "terms", "eos", "domain", "open_boundaries", "wall_groups",
                         "probes", "bodies"}  # Scene fields not plain


class SceneDataError(InputError):
    """Plain data that does not describe a scene (a missing class, a bad value...)."""


# --- plain values -----------------------------------------------------------------
def plain(value, what: str = "value"):
    """`value` as JSON values: numpy scalars and arrays, tuples -> numbers and lists, a
    non-finite float -> ``{"float": "inf"}``. TypeError naming `what` for anything else."""
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, np.bool_):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        value = float(value)
        return value if math.isfinite(value) else {"float": repr(value)}
    if isinstance(value, np.ndarray):
        return plain(value.tolist(), what)
    if isinstance(value, (list, tuple)):
        return [plain(v, what) for v in value]
    if isinstance(value, dict) and all(isinstance(k, str) for k in value):
        return {k: plain(v, f"{what}.{k}") for k, v in value.items()}
    raise TypeError(f"{what}: {value!r} ({type(value).__name__}) cannot be stored as plain data")


def unplain(value, tuples: bool = False):
    """The inverse of :func:`plain`; lists become tuples with `tuples`."""
    if isinstance(value, dict):
        if set(value) == {"float"}:
            return float(value["float"])
        return {k: unplain(v, tuples) for k, v in value.items()}
    if isinstance(value, list):
        items = [unplain(v, tuples) for v in value]
        return tuple(items) if tuples else items
    return value


# --- terms, equations of state, materials -------------------------------------------
def term_to_data(term) -> dict:
    """``{"name", "class", "params", "options"}`` (and ``"module"`` for a class outside
    :data:`TERMS`)."""
    cls = type(term)
    filled = getattr(term, "_default", None)  # a default the term filled in itself (Gravity.check)
    params = {k: plain(v, f"term {term.name!r} parameter {k}") for k, v in term.values.items()
              if filled is None or v is not filled}
    data = {"name": term.name, "class": cls.__name__, "params": params,
            "options": plain(dict(term.options), f"term {term.name!r} options")}
    if TERMS.get(cls.__name__) is not cls:
        data["module"] = cls.__module__
    if getattr(term, "choices", None):  # options the user chose (OpenBoundaries.choose), None: default
        data["choices"] = plain(dict(term.choices), f"term {term.name!r} choices")
    if getattr(term, "_resolved", None):  # what they resolved to in the validated scene, and why
        data["resolved"] = plain({k: list(v) for k, v in term._resolved.items()}, f"term {term.name!r} options")
    return data


def _find_class(data: dict, registry: dict, what: str):
    name = data.get("class")
    if name in registry:
        return registry[name]
    module = data.get("module")
    if module is None:
        raise SceneDataError(f"{what} of class {name!r}: this taisph has no such class (it has "
                             f"{', '.join(registry)})")
    try:
        cls = getattr(importlib.import_module(module), name)
    except (ImportError, AttributeError) as err:
        raise SceneDataError(f"{what} of class {name!r} from module {module!r}: {err}") from None
    return cls


def term_from_data(data: dict):
    """The term `data` (:func:`term_to_data`) describes, built by its class."""
    cls = _find_class(data, TERMS, f"term {data.get('name')!r}")
    try:
        term = cls(**unplain(data.get("options", {}), tuples=True), **unplain(data.get("params", {}), tuples=True))
    except (TypeError, ValueError) as err:
        raise SceneDataError(f"term {data.get('name')!r} ({cls.__name__}): {err}") from None
    if term.name != data.get("name", term.name):
        raise SceneDataError(f"term {data['name']!r}: class {cls.__name__} now makes a term named {term.name!r}")
    return term


def eos_to_data(eos) -> dict:
    """``{"name", "class", "options"}``: the arguments of its constructor, read back from
    the attributes of the same names."""
    cls = type(eos)
    options = {p.name: plain(getattr(eos, p.name), f"equation of state option {p.name}")
               for p in inspect.signature(cls).parameters.values()
               if p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)}
    data = {"name": getattr(eos, "name", cls.__name__), "class": cls.__name__, "options": options}
    if EOS.get(cls.__name__) is not cls:
        data["module"] = cls.__module__
    return data


def eos_from_data(data: dict):
    cls = _find_class(data, EOS, "equation of state")
    try:
        return cls(**unplain(data.get("options", {}), tuples=True))
    except (TypeError, ValueError) as err:
        raise SceneDataError(f"equation of state {cls.__name__}: {err}") from None


def material_to_data(material) -> dict:
    data = {"class": type(material).__name__}
    data.update({f.name: plain(getattr(material, f.name), f"material {f.name}") for f in dataclasses.fields(material)})
    return data


def material_from_data(data: dict):
    data = dict(data)
    cls = MATERIALS.get(data.pop("class", None))
    if cls is None:
        raise SceneDataError(f"material {data.get('name')!r}: class not one of {', '.join(MATERIALS)}")
    try:
        return cls(**unplain(data))
    except TypeError as err:
        raise SceneDataError(f"material {data.get('name')!r}: {err}") from None


def zone_to_data(zone, dim: int) -> dict:
    """An open boundary zone (:class:`taisph.terms.open_boundary.OpenBoundary`) as plain
    data; a velocity function is stored as its table (what the run uses)."""
    data = {f.name: getattr(zone, f.name) for f in dataclasses.fields(zone)}
    if callable(zone.velocity):
        table, step = zone.table(dim)
        data["velocity"] = {"tabulated": table, "step": step}
    return plain(data, f"open boundary {zone.name!r}")


def zone_from_data(data: dict):
    from .open_boundary import OpenBoundary

    data = unplain(data, tuples=True)
    velocity = data.get("velocity")
    if isinstance(velocity, dict):
        data["velocity"] = {"tabulated": np.asarray(velocity["tabulated"], float), "step": velocity["step"]}
    elif isinstance(velocity, tuple) and velocity and isinstance(velocity[0], tuple):
        data["velocity"] = np.asarray(velocity, float)  # a (t, u) table
    try:
        return OpenBoundary(**data)
    except TypeError as err:
        raise SceneDataError(f"open boundary {data.get('name')!r}: {err}") from None


def body_to_data(body) -> tuple[dict, dict]:
    """A body (:class:`taisph.scene.bodies.Body`) as plain data and its arrays (particles, table)."""
    data = {f.name: getattr(body, f.name) for f in dataclasses.fields(body) if f.name not in ("ids", "table")}
    arrays = {BODY + body.name + ".ids": np.asarray(body.ids)}
    if body.table is not None:
        arrays[BODY + body.name + ".table"] = np.asarray(body.table[0])
        data["table_dt"] = body.table[1]
    return plain(data, f"body {body.name!r}"), arrays


def body_from_data(data: dict, arrays):
    from .bodies import Body

    data = unplain(data, tuples=True)
    name = data.get("name")
    step = data.pop("table_dt", None)
    try:
        body = Body(ids=np.asarray(arrays[BODY + name + ".ids"]), **data)
    except (TypeError, KeyError) as err:
        raise SceneDataError(f"body {name!r}: {err}") from None
    for key in ("centre", "velocity"):
        setattr(body, key, np.asarray(getattr(body, key), float))
    if isinstance(body.inertia, tuple):
        body.inertia = np.asarray(body.inertia, float)
    if isinstance(body.angular_velocity, tuple):
        body.angular_velocity = np.asarray(body.angular_velocity, float)
    if step is not None:
        body.table = (np.asarray(arrays[BODY + name + ".table"], float), step)
    return body


# --- the scene ----------------------------------------------------------------------
def scene_to_data(scene: Scene) -> tuple[dict, dict]:
    """``(data, arrays)``: the scene's settings, materials, equation of state and terms
    as JSON values, its particle arrays as numpy (see the module docstring)."""
    data = {f.name: plain(getattr(scene, f.name), f"scene setting {f.name}")
            for f in dataclasses.fields(scene) if f.name not in SPECIAL}
    data["domain"] = [plain(np.asarray(a, float), "scene domain") for a in scene.domain]
    data["materials"] = [material_to_data(m) for m in scene.materials]
    data["eos"] = eos_to_data(scene.eos)
    data["terms"] = [term_to_data(t) for t in scene.terms]
    data["quantities"] = list(scene.quantities)
    # open boundaries: the zones (a function of x and t as its table); their term is rebuilt from them
    data["open_boundaries"] = [zone_to_data(z, scene.dim) for z in scene.open_boundaries]
    data["wall_groups"] = sorted(scene.wall_groups)
    data["probes"] = [plain(dataclasses.asdict(p), f"probe {p.name!r}") for p in scene.probes]
    arrays = {name: np.asarray(getattr(scene, name)) for name in ARRAYS}
    data["bodies"] = []  # bodies: each one's settings, particles and table; their term is rebuilt from them
    for body in scene.bodies:
        body_data, body_arrays = body_to_data(body)
        data["bodies"].append(body_data)
        arrays.update(body_arrays)
    arrays.update({WALL_GROUP + name: np.asarray(ids) for name, ids in scene.wall_groups.items()})
    arrays.update({QUANTITY + name: np.asarray(v) for name, v in scene.quantities.items()})
    return data, arrays


def scene_from_data(data: dict, arrays) -> Scene:
    """The scene :func:`scene_to_data` gave `data` and `arrays` for (not validated: the
    scene as it was; :class:`taisph.Simulation` validates it)."""
    data = dict(data)
    missing = [k for k in ("name", "dim", "dx", "smoothing_length", "domain", "materials", "eos", "terms")
               if k not in data] + [
        k for k in ARRAYS if k not in arrays]
    if missing:
        raise SceneDataError(f"scene data without {', '.join(missing)}")
    quantities = {name: np.asarray(arrays[QUANTITY + name]) for name in data.pop("quantities", [])}
    zones = [zone_from_data(z) for z in data.pop("open_boundaries", [])]
    bodies = [body_from_data(b, arrays) for b in data.pop("bodies", [])]
    terms = []
    for t in data.pop("terms"):
        if t.get("class") == "RigidBodies":
            from ..terms.rigid_bodies import RigidBodies

            term = RigidBodies(bodies, int(data["dim"]))
            term.values.update(unplain(t.get("params", {}), tuples=True))
            terms.append(term)
        elif t.get("class") == "OpenBoundaries":
            from ..terms.open_boundary import OpenBoundaries

            term = OpenBoundaries(zones, int(data["dim"]), float(data["dx"])).refresh()
            term.values.update(unplain(t.get("params", {}), tuples=True))  # values set since (Scene.set)
            term.choose(**t.get("choices", {}))
            if "resolved" in t:
                term._resolved = {k: tuple(v) for k, v in t["resolved"].items()}
            terms.append(term)
        else:
            terms.append(term_from_data(t))
    from ..probes.spec import Probe

    special = dict(
        domain=tuple(np.asarray(a, float) for a in unplain(data.pop("domain"))),
        materials=[material_from_data(m) for m in data.pop("materials")],
        eos=eos_from_data(data.pop("eos")),
        terms=terms, open_boundaries=zones, bodies=bodies,
        wall_groups={name: np.asarray(arrays[WALL_GROUP + name]) for name in data.pop("wall_groups", [])},
        probes=[Probe(**unplain(p, tuples=True)) for p in data.pop("probes", [])],
    )
    known = {f.name for f in dataclasses.fields(Scene)}
    unknown = set(data) - known
    if unknown:
        raise SceneDataError(f"scene data with unknown setting(s) {', '.join(sorted(unknown))}")
    settings = {k: unplain(v, tuples=True) for k, v in data.items()}
    return Scene(**settings, **special, quantities=quantities, **{k: np.asarray(arrays[k]) for k in ARRAYS})
