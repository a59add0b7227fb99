"""Fuzzed readers (issue 24): scene files (TOML) and the seed's particle files, mutated at
random by hypothesis, are either read into a scene that validates or refused with the
project's own error (:class:`taisph.messages.InputError`) naming the file and the key (a
scene file) or the line (a seed file); a refused input given to the command line exits
with code 2 and leaves no output folder.

Scene files start from the shipped examples (``taisph.scene.catalogue.scene_files()``)
and three small files written here (every key of the schema; Lennard-Jones walls with
two fluids; a 3D DFSPH tank), and get 1-3 mutations each: keys deleted, renamed or
inserted at any level, values replaced by other types (strings, integers up to 10**400,
floats with nan, inf, +-1e300, 0, -0.0, dates, booleans, lists of other lengths, nested
tables), numbers scaled or shifted, keys set to plausible values of the schema (other
solvers, kernels, wall models, kinds...), arrays of tables emptied, entries duplicated,
values wrapped in a list or a table, strings replaced by the schema's other words or by
mesh files that are empty, binary, open, flat, malformed or a folder; written back with
a small TOML writer (inline tables). Seed files start from
``export_scene(dam_break_wedge(dx=0.2))`` and small 2D and 3D files, and get 1-3
corruptions: truncation, lines deleted, duplicated, swapped or blank, tokens replaced by
garbage (nan, inf, 1e309, 1_000, Arabic digits, 400-digit numbers...), counts changed or
fixed up to match, particles kept to 1-3, columns added or removed, one column set on
every line, line breaks (CRLF, CR, form feed, U+2028...), the whole file replaced by bytes.

A failure is a leak: an exception that is not an InputError (its traceback is chained
under the AssertionError), a refusal whose message lacks the file's name, the key or the
line, a line number that is not the offending line as an editor counts lines, an accepted
input whose scene does not validate, or (command line) an exit code other than 2 or an
output folder left behind. Accepted scene files above BUILD_BUDGET particles are read
but not built (an event in hypothesis' statistics).

- ``test_known_*``: the leaks found so far, minimal, as explicit examples (``@example``; all run,
  with the command line): they fail until fixed.
- CI: 300 derandomized (reproducible) examples per reader, the command line on about one
  refused input in 20 (~10-15); a few seconds.
- ``pytest -m slow``: 1 000 random examples per reader, the command line on one refused
  input in 16 (~50), and a ``Simulation`` made (not run) of every accepted input, which
  must succeed or refuse naming the file; the known leaks at that stage as examples.
"""

from __future__ import annotations

import ast
import contextlib
import copy
import datetime
import functools
import io
import math
import re
import shutil
import sys
import tempfile
import zlib
from pathlib import Path

import pytest
from hypothesis import HealthCheck, Phase, event, example, given, note, settings
from hypothesis import strategies as st

from taisph.cli.main import main as cli
from taisph.formats import dat as seedio
from taisph.formats import scenefile, scenefile_spec, seed
from taisph.formats.dat import SeedFileError
from taisph.formats.scenefile_spec import SceneFileError
from taisph.messages import InputError
from taisph.scene import catalogue

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

HEALTH = [HealthCheck.too_slow, HealthCheck.data_too_large, HealthCheck.filter_too_much,
          HealthCheck.large_base_example]
# CI: reproducible (derandomized), 300 examples per reader; slow: 1 000 random ones
CI = settings(max_examples=300, deadline=None, derandomize=True, database=None, suppress_health_check=HEALTH,
              print_blob=False)
SLOW = settings(max_examples=1000, deadline=None, derandomize=False, database=None, suppress_health_check=HEALTH,
                print_blob=True)
CLI_EVERY = {"ci": 20, "slow": 16}  # the command line checks about one refused input in this many
# an accepted scene file is built only below this many particles (the reader's own estimate,
# as taisph.formats.scenefile_spec._Checker.memory); above it a build takes seconds (the memory
# limit allows 80 M particles on this machine): only read() is checked, and counted as an event
BUILD_BUDGET = 200_000

SCENE = "fuzzed_scene.toml"
PARTICLES, BOUNDARY = "fuzzed_particles.dat", "fuzzed_boundary.dat"

# --- base scene files ----------------------------------------------------------------------
SMALL_2D = '''\
name = "small_2d"
description = "a small 2D scene with every kind of key"
dim = 2
dx = 0.05
t_end = 0.1
frames = 2
solver = "wcsph"
kernel = "wendland"
integrator = "euler"
h_factor = 2.0
courant = 0.2
domain = [[-0.5, -0.5], [1.5, 1.5]]
remove_escaped = false

[physics]
gravity = [0.0, -9.81]
alpha = 0.05
delta = 0.1
xsph = 0.1

[[materials]]
name = "water"
rho0 = 1000.0
c0 = 30.0
gamma = 7.0

[[fluid]]
box = [[0.0, 0.0], [0.4, 0.4]]
material = "water"
velocity = [0.5, 0.0]
hydrostatic = true

[[walls]]
name = "tank"
box = [[0.0, 0.0], [1.0, 0.8]]
kind = "tank"
open_top = false
model = "dummy"

[[walls]]
name = "block"
kind = "obstacle"
box = [[0.6, 0.0], [0.75, 0.15]]
open_top = false

[[walls]]
name = "rock"
polygon = [[0.0, 0.0], [0.3, 0.0], [0.15, 0.2]]
scale = 0.5
translate = [0.8, 0.3]

[[probes]]
name = "P"
kind = "pressure"
at = [1.0, 0.05]
to = [1.0, 0.2]
every = 2

[[probes]]
name = "gauge"
kind = "elevation"
at = [0.2]

[[probes]]
name = "F"
kind = "force"
walls = "block"
'''

TWO_FLUIDS_LJ = '''\
name = "two_fluids_lj"
dim = 2
dx = 0.05
t_end = 0.05
frames = 1
solver = "wcsph"
dt = 1e-4

[physics]
gravity = [0.0, -9.81]

[[materials]]
name = "water"
rho0 = 1000.0

[[materials]]
name = "oil"
rho0 = 800.0
c0 = 40.0

[[fluid]]
box = [[0.0, 0.0], [0.5, 0.2]]

[[fluid]]
box = [[0.0, 0.2], [0.5, 0.4]]
material = "oil"

[[walls]]
box = [[0.0, 0.0], [0.5, 0.5]]
model = "lj"
'''

SMALL_3D = '''\
name = "small_3d"
dim = 3
dx = 0.1
t_end = 0.1
frames = 1
solver = "dfsph"

[[fluid]]
box = [[0.0, 0.0, 0.0], [0.4, 0.4, 0.5]]

[[walls]]
name = "tank"
box = [[0.0, 0.0, 0.0], [1.0, 1.0, 0.5]]

[[walls]]
name = "pillar"
kind = "obstacle"
box = [[0.6, 0.0, 0.2], [0.8, 0.3, 0.4]]

[[probes]]
name = "g"
kind = "elevation"
at = [0.5, 0.25]
'''


@functools.cache
def scene_bases() -> dict:
    """name -> parsed TOML: the small files first (hypothesis shrinks towards them), then the shipped ones."""
    bases = {"small_2d": tomllib.loads(SMALL_2D), "two_fluids_lj": tomllib.loads(TWO_FLUIDS_LJ),
             "small_3d": tomllib.loads(SMALL_3D)}
    for path in catalogue.scene_files():
        bases[path.name] = tomllib.loads(path.read_text())
    return bases


# Files next to the fuzzed scene file a mutated `mesh = "..."` may name: the shipped meshes
# (copied), and meshes a user might give by mistake
DECOY_MESHES = ["empty.stl", "garbage.stl", "text.obj", "open.stl", "folder.stl", "flat.stl", SCENE]


def make_decoys(folder: Path) -> None:
    for mesh in catalogue.cases_folder().glob("*.stl"):
        shutil.copy(mesh, folder / mesh.name)
    (folder / "empty.stl").write_bytes(b"")
    (folder / "garbage.stl").write_bytes(bytes(range(256)) * 4)
    (folder / "text.obj").write_text("v 0 0 0\nv 1 0 0\nf 1 2 7\nthis is not a mesh\n")
    (folder / "open.stl").write_text("solid open\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                                     "vertex 0 1 0\nendloop\nendfacet\nendsolid open\n")
    (folder / "flat.stl").write_text("solid flat\n" + "".join(
        f"facet normal 0 0 1\nouter loop\nvertex {a}\nvertex {b}\nvertex {c}\nendloop\nendfacet\n"
        for a, b, c in (("0 0 0", "1 0 0", "0 1 0"), ("1 0 0", "1 1 0", "0 1 0"))) + "endsolid flat\n")
    (folder / "folder.stl").mkdir(exist_ok=True)


# --- a tiny TOML writer (everything as `key = value` lines with inline tables) ------------------
_BARE = re.compile(r"[A-Za-z0-9_-]+")


def _toml_string(text: str) -> str:
    out = []
    for ch in text:
        if ch in '"\\':
            out.append("\\" + ch)
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:
            out.append(f"\\u{ord(ch):04x}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def _toml_key(key: str) -> str:
    return key if _BARE.fullmatch(key) else _toml_string(key)


def toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return _toml_string(v)
    if isinstance(v, (datetime.date, datetime.time)):  # datetime is a date
        return v.isoformat()
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_toml_key(k)} = {toml_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(f"no TOML for {v!r}")


def toml_dumps(doc: dict) -> str:
    return "".join(f"{_toml_key(k)} = {toml_value(v)}\n" for k, v in doc.items() if v is not None)


def test_toml_writer_round_trips_the_bases():
    for name, doc in scene_bases().items():
        assert tomllib.loads(toml_dumps(doc)) == doc, name
    odd = {"a b": [1, 2.5, "x\"\\\n\x7f", [], {}], "n": [float("inf"), -0.0, 10**400],
           "t": [datetime.date(2024, 2, 29), datetime.time(7, 32), datetime.datetime(1979, 5, 27, 7, 32)],
           "": {"ä": [{"k": True}]}}
    assert tomllib.loads(toml_dumps(odd)) == odd
    assert math.isnan(tomllib.loads(toml_dumps({"x": float("nan")}))["x"])


# --- values and mutations ----------------------------------------------------------------------
SPECIAL_FLOATS = [math.nan, math.inf, -math.inf, 1e300, -1e300, 1e30, -1e30, 0.0, -0.0, 5e-324, 1e-300,
                  2.2250738585072014e-308, 1.7976931348623157e308, 0.5, 1.0, -1.0, 2.0, 3.0, 0.04, 1e-4]
SPECIAL_INTS = [0, 1, -1, 2, 3, 4, 7, 100_000, 100_001, 2**31, 2**53 + 1, 2**63 - 1, -(2**63), 10**30, 10**400,
                -(10**400)]
WORDS = ["wcsph", "dfsph", "isph", "spline", "gaussian", "wendland", "cubic", "pc", "euler", "eulermid", "eulermom",
         "rk4", "dummy", "lj", "tank", "obstacle", "pressure", "elevation", "force", "water", "oil", "block", "rock",
         "P", "walls[0]", "obstacle_kleefsman.stl", "missing.stl", "", " ", ".", "..", "/", "nan", "inf", "0", "1e300",
         "true", "wäter", "x" * 300, "a\nb", "\x00", *DECOY_MESHES]
KNOWN_KEYS = sorted(scenefile_spec.TOP_KEYS | scenefile_spec.PHYSICS_KEYS | scenefile_spec.MATERIAL_KEYS
                    | scenefile_spec.FLUID_KEYS | scenefile_spec.WALL_KEYS | scenefile_spec.PROBE_KEYS)
NEAR_MISSES = ["Name", "DX", "dx ", "fluids", "wall", "material_", "box2", "gravity_", "open-top", "openTop", "solid",
               "remove-escaped", "h", "c", "rho", "obstacle", "tank"]
DATES = [datetime.date(2024, 2, 29), datetime.time(7, 32), datetime.datetime(1979, 5, 27, 7, 32),
         datetime.datetime(1979, 5, 27, 7, 32, tzinfo=datetime.timezone.utc)]

keys = st.one_of(st.sampled_from(KNOWN_KEYS), st.sampled_from(NEAR_MISSES), st.text(max_size=8))
numbers = st.one_of(st.sampled_from(SPECIAL_FLOATS), st.sampled_from(SPECIAL_INTS), st.floats(),
                    st.integers(-(2**70), 2**70), st.floats(-2.0, 2.0))
small = st.sampled_from([-1.0, 0.0, 0.05, 0.1, 0.25, 0.5, 0.75, 1.0, 1.5])
vectors = st.lists(st.one_of(small, numbers), max_size=4)
shaped = st.one_of(
    vectors,
    st.lists(st.lists(small, min_size=2, max_size=3), min_size=2, max_size=2),  # boxes, some valid
    st.lists(st.lists(small, min_size=2, max_size=2), min_size=0, max_size=5),  # polygons
    st.lists(st.fixed_dictionaries({"box": st.lists(st.lists(small, min_size=2, max_size=3), min_size=2,
                                                             max_size=2)}), max_size=2),  # arrays of tables
)
scalars = st.one_of(numbers, st.booleans(), st.sampled_from(WORDS), st.text(max_size=12), st.sampled_from(DATES))
values = st.one_of(scalars, shaped, st.recursive(scalars, lambda inner: st.lists(inner, max_size=4)
                                                 | st.dictionaries(keys, inner, max_size=3), max_leaves=8))


def _numbers_like(v):
    """Numbers near `v` (and `v` as a string, in a list, in a table), or any number."""
    near = [-v, 2 * v, str(v), [v], {"value": v}]
    with contextlib.suppress(OverflowError, ValueError):  # 10**400 has no float; nan, inf no int
        near += [float(v), v / 2, float(v) * 1e-3, math.nextafter(float(v), math.inf), int(v), v + 1]
    return st.one_of(st.sampled_from(near), numbers)


# Plausible values of each key (valid and borderline ones): settings that combine into valid and
# invalid scenes deeper than a value of the wrong type does
PLAUSIBLE = {
    "name": ["tank", "block", "water", "x", "walls[0]"], "description": ["", "x"], "dim": [2, 3],
    "dx": [0.02, 0.05, 0.1, 0.5, 1.0, 5.0], "t_end": [1e-4, 1e5, 100000.5], "frames": [0, 1, 100_000, 100_001],
    "solver": ["wcsph", "dfsph"], "kernel": ["spline", "gaussian", "wendland"],
    "integrator": ["pc", "euler", "eulermid", "eulermom"], "h_factor": [0.5, 0.51, 1.0, 3.0, 3.01],
    "dt": [1e-5, 1e-3, 1.0, 1e5], "courant": [1.0, 1e-9, 0.5, 1.01], "remove_escaped": [True, False],
    "domain": [[[-1.0, -1.0], [2.0, 2.0]], [[-1.0, -1.0, -1.0], [2.0, 2.0, 2.0]], [[0.0, 0.0], [0.1, 0.1]],
               [[0.5, 0.5], [0.4, 2.0]]],
    "gravity": [[0.0, 0.0], [0.0, 0.0, 0.0], [9.81, 0.0], [0.0, -9.81, 0.0], [0.0, 1e6]],
    "alpha": [0.0, 2.0, 2.01], "delta": [0.0, 1.0], "xsph": [0.0, 1.0],
    "rho0": [1.0, 500.0, 800.0, 1000.0, 1e6], "c0": [1e-3, 10.0, 1e6], "gamma": [1.0, 7.0, 15.0],
    "model": ["dummy", "lj"], "kind": ["tank", "obstacle", "pressure", "elevation", "force"],
    "open_top": [True, False], "hydrostatic": [True, False], "velocity": [[1.0, 0.0], [0.0, 0.0, 0.0], [100.0, 0.0]],
    "material": ["water", "oil"], "scale": [0.5, 2.0, 1e-3, 1e-9],
    "translate": [[0.1, 0.1], [0.0, 0.0, 0.0], [1e3, 0.0], [0.0, 1e16]],
    "box": [[[0.0, 0.0], [0.2, 0.2]], [[0.5, 0.0, 0.0], [0.7, 0.2, 0.2]], [[0.2, 0.2], [0.1, 0.1]],
            [[0.0, 0.0], [1.0, 1.0]], [[-0.5, 0.0], [0.2, 0.1]]],
    "polygon": [[[0.0, 0.0], [0.2, 0.0], [0.1, 0.2]], [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0], [1.0, 0.0]],
                [[0.0, 0.0], [0.0, 0.0], [0.0, 0.0]], [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]],
    "mesh": ["obstacle_kleefsman.stl", "missing.stl", *DECOY_MESHES],
    "at": [[0.5, 0.5], [0.5], [0.5, 0.5, 0.5], [-100.0, 0.5]], "to": [[0.5, 0.6], [0.6, 0.5, 0.5], [0.5, 0.5]],
    "walls": ["tank", "block", "walls[0]", "nothing", [{"box": [[0.0, 0.0], [1.0, 1.0]]}]], "every": [1, 10**6],
    "materials": [[{"name": "oil", "rho0": 800.0}], [{"name": "water"}, {"name": "water"}]],
    "fluid": [[{"box": [[0.0, 0.0], [0.2, 0.2]]}], [{"box": [[0.0, 0.0, 0.0], [0.2, 0.2, 0.2]]}],
              [{"mesh": "obstacle_kleefsman.stl"}], [{"polygon": [[0.0, 0.0], [0.2, 0.0], [0.1, 0.2]]}]],
    "probes": [[{"name": "F", "kind": "force", "walls": "tank"}],
               [{"name": "p", "kind": "pressure", "at": [0.1, 0.1]}]],
    "physics": [{}, {"gravity": [0.0, 0.0]}],
}
plausible_keys = st.sampled_from(sorted(PLAUSIBLE))


def _paths(node, path=()):
    yield path
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _paths(v, path + (k,))
    elif isinstance(node, list):
        for k, v in enumerate(node):
            yield from _paths(v, path + (k,))


def _get(doc, path):
    for k in path:
        doc = doc[k]
    return doc


def _is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


# operation -> which nodes it applies to (doc, path -> bool)
MUTATIONS = {
    "delete": lambda d, p: bool(p),
    "rename": lambda d, p: bool(p) and isinstance(_get(d, p[:-1]), dict),
    "replace": lambda d, p: bool(p),
    "insert": lambda d, p: isinstance(_get(d, p), dict),
    "number": lambda d, p: _is_number(_get(d, p)),
    "perturb": lambda d, p: _is_number(_get(d, p)),
    "plausible": lambda d, p: bool(p) and isinstance(p[-1], str) and p[-1] in PLAUSIBLE,
    "set": lambda d, p: isinstance(_get(d, p), dict),
    "word": lambda d, p: isinstance(_get(d, p), str),
    "resize": lambda d, p: isinstance(_get(d, p), list),
    "empty": lambda d, p: bool(p) and isinstance(_get(d, p), (list, dict)),
    "duplicate": lambda d, p: bool(p) and isinstance(_get(d, p[:-1]), list),
    "wrap": lambda d, p: bool(p),
    "unwrap": lambda d, p: bool(p) and isinstance(_get(d, p), list) and len(_get(d, p)) > 0,
}


def _mutate(draw, doc) -> str:
    op = draw(st.sampled_from(list(MUTATIONS) + ["perturb", "plausible", "set"] * 2))
    where = [p for p in _paths(doc) if MUTATIONS[op](doc, p)]
    if not where:
        return f"{op}: nowhere"
    path = draw(st.sampled_from(where))
    node = _get(doc, path)
    parent = _get(doc, path[:-1]) if path else None
    last = path[-1] if path else None
    if op == "delete":
        del parent[last]
    elif op == "rename":
        new = draw(keys)
        parent[new] = parent.pop(last)
        return f"rename {path} -> {new!r}"
    elif op == "replace":
        parent[last] = draw(values)
    elif op == "insert":
        key = draw(keys)
        node[key] = draw(values)
        return f"insert {path + (key,)} = {node[key]!r}"
    elif op == "number":
        parent[last] = draw(_numbers_like(node))
    elif op == "perturb":  # mostly still valid: geometry that combines differently
        factor, shift = draw(st.sampled_from([0.5, 0.9, 1.1, 1.5, 2.0, -1.0])), draw(
            st.sampled_from([0.0, 0.0, -0.1, 0.05, 0.1]))
        try:
            parent[last] = node * factor + shift
        except OverflowError:  # an integer too large for a float
            parent[last] = -node
    elif op == "plausible":
        parent[last] = copy.deepcopy(draw(st.sampled_from(PLAUSIBLE[last])))
    elif op == "set":
        key = draw(plausible_keys)
        node[key] = copy.deepcopy(draw(st.sampled_from(PLAUSIBLE[key])))
        return f"set {path + (key,)} = {node[key]!r}"
    elif op == "word":
        parent[last] = draw(st.one_of(st.sampled_from(WORDS), st.text(max_size=12)))
    elif op == "resize":
        if node and draw(st.booleans()):
            del node[draw(st.integers(0, len(node) - 1))]
        else:
            node.append(copy.deepcopy(draw(st.sampled_from(node))) if node and draw(st.booleans()) else draw(values))
    elif op == "empty":
        parent[last] = draw(st.sampled_from([[], {}]))
    elif op == "duplicate":
        parent.insert(last, copy.deepcopy(node))
    elif op == "wrap":
        parent[last] = draw(st.sampled_from([[node], {"value": node}, [node, node]]))
    elif op == "unwrap":
        parent[last] = node[0]
    if op in ("delete", "resize", "duplicate"):
        return f"{op} {path}"
    return f"{op} {path} -> {_get(doc, path)!r}"[:300]


@st.composite
def scene_texts(draw) -> str:
    """A shipped or small scene file with 1-3 mutations, as TOML."""
    bases = scene_bases()
    name = draw(st.sampled_from(list(bases)))
    doc = copy.deepcopy(bases[name])
    done = [_mutate(draw, doc) for _ in range(draw(st.integers(1, 3)))]
    note(f"base {name}; " + "; ".join(done))
    return toml_dumps(doc)


# --- the properties --------------------------------------------------------------------------
def particle_estimate(spec) -> float:
    """The particles a checked spec's blocks hold: the reader's own memory estimate."""
    layers = scenefile_spec.wall_layers_needed(spec) * spec.dx
    filled = [(b, spec.dx, 0.0) for b in spec.fluid] + [
        (b, spec.dx / 2.0, 0.0) if b.model == "lj" else (b, spec.dx, 2.0 * layers) for b in spec.walls] + [
        (b, spec.dx, 0.0) for b in spec.bodies or ()]  # a body: its shape filled on the lattice
    return sum(math.prod(float(hi - lo + pad) / spacing + 1.0 for lo, hi in zip(*b.bounds))
               for b, spacing, pad in filled)


def _leak(what, path, err) -> AssertionError:
    return AssertionError(f"LEAK ({what}): {path.name} raised {type(err).__name__}: {err}")


def check_scene_refusal(path: Path, doc: dict, err: InputError) -> None:
    msg = str(err)
    assert path.name in msg, f"LEAK (refusal without the file name): {type(err).__name__}: {msg}"
    if isinstance(err, SceneFileError):
        prefix = f"{path}: "
        assert msg.startswith(prefix), f"LEAK (a scene-file error not starting with the file): {msg}"
        rest = msg[len(prefix):]
        names = set(doc) | scenefile_spec.TOP_KEYS
        keyed = " = " in rest and any(rest.startswith(k) and rest[len(k):len(k) + 1] in (".", "[", " ") for k in names)
        assert keyed or rest.startswith("not valid TOML"), f"LEAK (a scene-file error naming no key): {msg}"


def scene_outcome(path: Path, doc: dict, overrides=None):
    """('refused' | 'accepted' | 'not built', scene or None): load() in its two halves, read() and
    build(), so that an accepted scene above BUILD_BUDGET particles is not built."""
    try:
        spec = scenefile_spec.read(path, overrides)
        if particle_estimate(spec) > BUILD_BUDGET:
            return "not built", None
        scene, settings = scenefile.build(spec)
    except InputError as err:
        check_scene_refusal(path, doc, err)
        return "refused", None
    except Exception as err:  # noqa: BLE001 - any other exception is a leak
        raise _leak("not an InputError", path, err) from err
    try:
        scene.validate()
    except InputError as err:
        raise _leak("accepted, but the scene does not validate", path, err) from err
    assert settings.t_end == spec.t_end and settings.frames == spec.frames
    return "accepted", scene


def check_simulation(scene, files: list) -> None:
    """(slow part) A scene the reader accepted makes a Simulation (not run), or is refused naming the file."""
    import taisph

    try:
        sim = taisph.Simulation(scene)
    except InputError as err:
        assert any(f.name in str(err) for f in files), \
            f"LEAK (accepted by the reader, refused by Simulation without the file): {err}"
        event("accepted, refused by Simulation")
        return
    except Exception as err:  # noqa: BLE001 - any other exception is a leak
        raise _leak("Simulation of an accepted input: not an InputError", files[0], err) from err
    del sim
    event("accepted, Simulation built")


def run_cli(argv) -> tuple[int, str]:
    err = io.StringIO()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
        code = cli(argv)
    return code, err.getvalue()


def check_scene_text(folder: Path, text: str, cli_every: int, simulate: bool = False) -> None:
    """The property for a scene file's text; the command line for one refused input in `cli_every`; with
    `simulate`, a Simulation of an accepted one."""
    path = folder / SCENE
    path.write_text(text, encoding="utf-8")
    doc = tomllib.loads(text)
    outcome, scene = scene_outcome(path, doc)
    event(f"scene file {outcome}")
    if simulate and scene is not None:
        check_simulation(scene, [path])
    if outcome != "refused" or zlib.crc32(text.encode()) % cli_every:
        return
    # the command line, on a sample of refused inputs (with --t-end 1e-4: unless that fixes the file)
    if scene_outcome(path, doc, {"t_end": 1e-4})[0] != "refused":
        return
    event("scene file refused: command line checked")
    out = folder / "out"
    shutil.rmtree(out, ignore_errors=True)
    code, stderr = run_cli([str(path), "--out", str(out), "--no-progress", "--t-end", "1e-4"])
    assert code == 2 and not out.exists(), f"LEAK (command line): exit code {code}, {out} exists: {out.exists()}"
    assert stderr.startswith("taisph: error: ") and path.name in stderr, f"LEAK (command line message): {stderr}"


# --- seed files -----------------------------------------------------------------------------
@functools.cache
def seed_bases() -> dict:
    """name -> (particle file, boundary file or None) as bytes."""
    import numpy as np

    import taisph

    bases = {}
    tiny = b"3\n0 0.1 0.1 0 0 10 1000 0 0\n1 0.3 0.1 0 0 10 1000 0 0\n2 0.1 0.3 0.5 0 10 1001 0 0\n"
    walls = b"4\n0 0 0 0 0 10 1000 0 0\n1 0.1 0 0 0 10 1000 0 0\n2 0.2 0 0 0 10 1000 0 0\n3 0.3 0 0 0 10 1000 0 0\n"
    bases["tiny_2d"] = (tiny, walls)
    with tempfile.TemporaryDirectory() as tmp:
        seed.export_scene(taisph.cases.dam_break_wedge(dx=0.2), tmp)
        wedge = (Path(tmp) / "particles.dat").read_bytes(), (Path(tmp) / "boundary.dat").read_bytes()
        grid = np.stack(np.meshgrid(*[[0.05, 0.15]] * 3, indexing="ij"), -1).reshape(-1, 3)
        seedio.write_particles(Path(tmp) / "p3.dat", grid + 0.1, 0.0, 1.0, 1000.0, 0.0)
        row = [0.0, 0.1, 0.2, 0.3]
        floor = np.stack(np.meshgrid(row, [0.0], row, indexing="ij"), -1).reshape(-1, 3)
        seedio.write_particles(Path(tmp) / "b3.dat", floor, 0.0, 1.0, 1000.0, 0.0)
        block = (Path(tmp) / "p3.dat").read_bytes(), (Path(tmp) / "b3.dat").read_bytes()
    bases["wedge"] = wedge
    bases["block_3d"] = block
    bases["wedge_no_boundary"] = (wedge[0], None)
    return bases


GARBAGE = ["abc", "nan", "NaN", "-nan", "inf", "-inf", "Infinity", "1e300", "-1e300", "1e309", "-1e309", "0", "-0",
           "-0.0", "-1", "1e-300", "5e-324", "0x10", "1_000", "1,5", "١٢", "٣.٥", "+1", ".5", "5.", "1e", "--1", "1e2",
           "2.0", "9" * 400, "1" + "0" * 400, "1e18", "1e19", "9223372036854775808", "—", "\x00", "0b1", "True", "1e-5",
           "40", "1000", "1100", "1e6"]
LINE_BREAKS = ["\r\n", "\r", "\x0c", "\x0b", "\u2028", "\x85", "\x1c"]


def _text_lines(data: bytes) -> list[str]:
    return data.decode("utf-8", "surrogateescape").split("\n")


def _join(lines: list[str]) -> bytes:
    return "\n".join(lines).encode("utf-8", "surrogateescape")


def _body(lines):
    """Indices of the non-blank lines after the first non-blank one (the particle lines)."""
    full = [k for k, line in enumerate(lines) if line.split()]
    return full[1:]


def _corrupt(draw, data: bytes) -> tuple[bytes, str]:
    op = draw(st.sampled_from(["truncate", "delete", "duplicate", "swap", "blank", "token", "token", "token", "count",
                               "fix_count", "keep", "column", "all_column", "replace_file", "line_break"]))
    lines = _text_lines(data)
    body = _body(lines)
    if op == "truncate":
        cut = draw(st.integers(0, len(data)))
        return data[:cut], f"truncate at byte {cut}"
    if op == "replace_file":
        new = draw(st.one_of(st.binary(max_size=64), st.sampled_from(
            [b"", b"\n", b"   \n\t\n", b"\xff\xfe2\x00\n", b"\x00" * 10, b"\xef\xbb\xbf" + data,
             data.replace(b"\n", b"\x00")])))
        return new, f"file replaced by {new[:40]!r}"
    if op in ("delete", "duplicate", "blank", "token", "column") and not body:
        return data, f"{op}: no particle line"
    k = draw(st.sampled_from(body)) if body else 0
    if op == "delete":
        del lines[k]
    elif op == "duplicate":
        lines.insert(k, lines[k])
    elif op == "swap" and len(lines) > 1:
        j = draw(st.integers(0, len(lines) - 1))
        lines[k], lines[j] = lines[j], lines[k]
    elif op == "blank":
        lines.insert(k, draw(st.sampled_from(["", "   ", "\t"])))
    elif op == "token":
        tokens = lines[k].split()
        c = draw(st.integers(0, len(tokens) - 1))
        tokens[c] = draw(st.one_of(st.sampled_from(GARBAGE), st.text(min_size=1, max_size=6)))
        lines[k] = " ".join(tokens)
        return _join(lines), f"line {k + 1} column {c + 1} -> {tokens[c]!r}"
    elif op == "count":
        first = ([i for i, line in enumerate(lines) if line.split()] or [0])[0]
        n = len(body)
        lines[first] = str(draw(st.sampled_from([n - 1, n + 1, 0, -1, -n, 2**63, 10**30, f"{n}.0", f"{n}e0",
                                                 f"{n}.5", "nan", f" {n} {n}", "1e400"])))
    elif op in ("fix_count", "keep"):
        first = ([i for i, line in enumerate(lines) if line.split()] or [0])[0]
        if op == "keep" and body:
            kept = draw(st.integers(1, min(len(body), 3)))
            lines = lines[:first + 1] + [lines[i] for i in body[:kept]]
            # renumber the indices so that the kept lines are a valid file but for what else was done
            lines = lines[:first + 1] + [" ".join([str(j)] + line.split()[1:])
                                         for j, line in enumerate(lines[first + 1:])]
        lines[first] = str(len(_body(lines)))
    elif op == "column":
        tokens = lines[k].split()
        if draw(st.booleans()) and tokens:
            tokens.pop()
        else:
            tokens.append(draw(st.sampled_from(GARBAGE)))
        lines[k] = " ".join(tokens)
    elif op == "all_column":
        width = len(lines[body[0]].split()) if body else 0
        if width < 2:
            return data, "all_column: no columns"
        c = draw(st.integers(1, width - 1))
        value = draw(st.sampled_from(["0", "1", "-1", "0.1", "1e300", "1e-300", "1000", "1e-5", "40"]))
        for i in body:
            tokens = lines[i].split()
            if c < len(tokens):
                tokens[c] = value
                lines[i] = " ".join(tokens)
        return _join(lines), f"column {c + 1} of every line -> {value}"
    elif op == "line_break":
        brk = draw(st.sampled_from(LINE_BREAKS))
        if brk == "\r\n" and draw(st.booleans()):
            return _join(lines).replace(b"\n", b"\r\n"), "CRLF line endings"
        pos = draw(st.integers(0, len(lines[k])))
        lines[k] = lines[k][:pos] + brk + lines[k][pos:]
        return _join(lines), f"line {k + 1}: {brk!r} at {pos}"
    return _join(lines), f"{op} line {k + 1}"


@st.composite
def seed_files(draw) -> tuple[bytes, bytes | None]:
    """A base pair of seed files with 1-3 corruptions, each in one of the two files."""
    bases = seed_bases()
    name = draw(st.sampled_from(list(bases)))
    files = list(bases[name])
    done = []
    for _ in range(draw(st.integers(1, 3))):
        which = draw(st.sampled_from([0, 1] if files[1] is not None else [0]))
        files[which], what = _corrupt(draw, files[which])
        done.append(f"{('particles', 'boundary')[which]}: {what}")
    note(f"base {name}; " + "; ".join(done))
    return files[0], files[1]


WHOLE_FILE = ("is empty", "is not a text file", "D but the particle file", "no such", "is a directory", "cannot read")


def check_seed_refusal(err: InputError, files: dict) -> None:
    """`files`: path -> content of the files given."""
    msg = str(err)
    assert any(p.name in msg for p in files), f"LEAK (refusal naming no file): {type(err).__name__}: {msg}"
    if not isinstance(err, SeedFileError):
        return
    path = Path(err.path)
    assert path in files and msg.startswith(f"{path}"), f"LEAK (a seed-file error not starting with the file): {msg}"
    if err.line is None:
        assert any(w in err.reason for w in WHOLE_FILE), f"LEAK (a seed-file error without a line number): {msg}"
        return
    assert f"{path}, line {err.line}: " in msg
    # the lines as editors, grep -n, sed and Python's text mode count them (\n, \r\n or \r ends a line)
    lines = re.split(r"\r\n|\r|\n", files[path].decode("utf-8", "replace"))
    named = lines[err.line - 1] if 1 <= err.line <= len(lines) else None
    off = f"LEAK (line number off: line {err.line} of {path.name}, as an editor counts lines, is"
    assert named is not None and named.strip(), f"{off} {'blank' if named is not None else 'beyond its end'}): {msg}"
    for quoted in re.findall(r"""is ('(?:[^'\\]|\\.)*'|"(?:[^"\\]|\\.)*")""", err.reason):
        token = ast.literal_eval(quoted)
        assert token in named, f"{off} {named[:80]!r}, which does not hold {token!r}): {msg}"


def check_seed_files(folder: Path, particles: bytes, boundary: bytes | None, cli_every: int,
                     simulate: bool = False) -> None:
    """The property for a particle file (and boundary file); the command line `run` for one refused input
    in `cli_every`; with `simulate`, a Simulation of an accepted one."""
    p, b = folder / PARTICLES, folder / BOUNDARY
    p.write_bytes(particles)
    b.unlink(missing_ok=True)
    if boundary is not None:
        b.write_bytes(boundary)
    files = {p: particles} | ({b: boundary} if boundary is not None else {})
    try:
        scene, energy = seed.load_scene(p, b if boundary is not None else None)
    except InputError as err:
        check_seed_refusal(err, files)
        outcome = "refused"
    except Exception as err:  # noqa: BLE001 - any other exception is a leak
        raise _leak("not an InputError", p, err) from err
    else:
        try:
            scene.validate()
        except InputError as err:
            raise _leak("accepted, but the scene does not validate", p, err) from err
        assert len(energy) == scene.n_fluid
        outcome = "accepted"
        if simulate:
            check_simulation(scene, list(files))
    event(f"seed files {outcome}")
    if outcome != "refused" or zlib.crc32(particles + (boundary or b"")) % cli_every:
        return
    event("seed files refused: command line checked")
    out = folder / "out"
    shutil.rmtree(out, ignore_errors=True)
    code, stderr = run_cli(["run", *map(str, files), "1e-3", "1e-4", "pc", "spline", "--out", str(out),
                            "--no-progress"])
    assert code == 2 and not out.exists(), f"LEAK (command line): exit code {code}, {out} exists: {out.exists()}"
    assert stderr.startswith("taisph run: error: ") and any(f.name in stderr for f in files), \
        f"LEAK (command line message): {stderr}"


# --- the tests ---------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    path = tmp_path_factory.mktemp("fuzz")
    make_decoys(path)
    return path


def with_examples(examples: dict, name: str):
    """Decorate a @given test with each of `examples` as an explicit example."""
    def decorate(test):
        for value in reversed(list(examples.values())):
            test = example(**{name: value})(test)
        return test
    return decorate


# Known leaks: the inputs this test found (issue 24), minimal, run as explicit examples (all of them, the
# command line too) so that they fail until fixed. The fuzzing tests below run whatever these do.
KNOWN = settings(phases=[Phase.explicit], deadline=None, database=None, report_multiple_bugs=True)
_HEAD = 'name = "s"\ndim = {dim}\ndx = 0.05\nt_end = 0.1\nframes = 1\n'
_BOX = 'fluid = [{box = [[0.0, 0.0], [0.2, 0.2]]}]\n'
_ROCK = 'walls = [{polygon = [[0.0, 0.0], [0.3, 0.0], [0.15, 0.2]], '
SCENE_LEAKS = {
    # OverflowError in taisph.scene.parameters.Number.accepts (math.isfinite of an int beyond the float
    # range), for any number of the file: tomllib reads TOML integers of any size
    "integer beyond the float range": "dim = 1" + "0" * 400 + "\n",
    # IndexError in taisph.geometry.fill._within (from scenefile._wall_points -> volume_points(depth=...)):
    # at y = 1e16 the polygon is narrower than the float spacing and no lattice point is left
    "polygon translated to y = 1e16": _HEAD.format(dim=2) + _BOX + _ROCK + "translate = [0.0, 1e16]}]\n",
    # IndexError in taisph.geometry.mesh.load_surface, line `points.shape[1] == 3` (no points)
    "empty mesh file": _HEAD.format(dim=3) + 'fluid = [{mesh = "empty.stl"}]\n',
    # IndexError in taisph.geometry.mesh.load_surface, `inverse.reshape(-1)[cells]`: a face naming vertex 7
    "mesh face naming a missing vertex": _HEAD.format(dim=3) + 'fluid = [{mesh = "text.obj"}]\n',
    # accepted by the reader; Scene.validate() (taisph.run.solvers.check_dfsph) refuses the Lennard-Jones
    # wall term or the two fluids' sharp-interface terms, naming neither the file nor the key
    "dfsph with lj walls": _HEAD.format(dim=2) + 'solver = "dfsph"\n' + _BOX
    + 'walls = [{box = [[0.0, 0.0], [0.5, 0.5]], model = "lj"}]\n',
    "dfsph with two fluids": _HEAD.format(dim=2) + 'solver = "dfsph"\n'
    'materials = [{name = "water"}, {name = "oil", rho0 = 800.0}]\n'
    'fluid = [{box = [[0.0, 0.0], [0.2, 0.2]]}, {box = [[0.0, 0.2], [0.2, 0.4]], material = "oil"}]\n',
    # accepted with 0 wall particles; Scene.validate(): "dummy_walls: the scene has no wall particles"
    "obstacle smaller than dx": _HEAD.format(dim=2) + _BOX + _ROCK + "scale = 1e-9}]\n",
}
TWO = b"2\n0 0 0 0 0 1 1000 0 0\n1 0 1 0 0 1 1000 0 0\n"  # two fluid particles, one above the other
SEED_LEAKS = {
    # taisph.formats.dat.read_particles splits lines with str.splitlines, which also ends a line at \x0b,
    # \x0c, \x1c-\x1e, \x85, U+2028, U+2029: its line numbers are not an editor's or grep -n's (here
    # "line 3: extra particle line" in a file of 2 lines), and such a file may even be accepted
    "form feed inside a line": (b"1\n0 0 0 0 0 1 1000 0 0\x0c0\n", None),
    # InputErrors of taisph.formats.seed.load_scene that name no file (some with a wrong reason):
    # H = 0 (one particle, or all at the lowest height) and no velocity: "no gravity and no initial velocity"
    "one fluid particle, no walls": (b"1\n0 0 0 0 0 1 1000 0 0\n", None),
    # seed._wall_spacing: "one wall particle gives no spacing; set --lj-cutoff"
    "one wall particle": (TWO, b"1\n0 0 0 0 0 1 1000 0 0\n"),
    # the wall spacing (the default --lj-cutoff) refused by LennardJonesWall's check in Scene.validate():
    # "lj_cutoff r0 = inf must be positive and within the kernel support radius ..."
    "wall particles on one point": (TWO, b"2\n0 0 0 0 0 1 1000 0 0\n1 0 0 0 0 1 1000 0 0\n"),
    "wall spacing beyond the kernel support": (TWO, b"2\n0 0 0 0 0 1 1000 0 0\n1 5 0 0 0 1 1000 0 0\n"),
    # x = 1e300: the domain's lo and hi (positions -+ dx) are equal: "scene 'fuzzed_particles': domain ... is empty"
    "positions at x = 1e300": (b"2\n0 1e300 0 0 0 1 1000 0 0\n1 1e300 1 0 0 1 1000 0 0\n", None),
    # |v| overflows: "material 'water': c0 must be a positive number, got inf" (Material.check)
    "velocity 1e300": (b"1\n0 0 0 0 1e300 1 1000 0 0\n", None),
    # the fluid at or below the lowest wall particle: g H <= 0, "cannot choose the wall strength without gravity"
    "fluid below the walls": (b"1\n0 0 -1 0.5 0 1 1000 0 0\n", b"2\n0 0 0 0 0 1 1000 0 0\n1 0.1 0 0 0 1 1000 0 0\n"),
}
# Accepted by the readers, refused or failing when a Simulation is made (the slow part's check)
SCENE_SIMULATION_LEAKS = {
    # OverflowError "Python integer 15384615384618 out of bounds for int32" in taisph.engine.state._write_sizes:
    # GridLayout.n_cells (taisph.engine.neighbours, np.prod of the shape) wraps around in int64, so the grid
    # check of State._check_grid passes
    "domain of 2e12 m": _HEAD.format(dim=2) + "domain = [[-1e12, -1e12], [1e12, 1e12]]\n" + _BOX,
    # InputError of State._check_grid naming neither the file nor `domain`: "the neighbour grid would need
    # 236686471005924 cells of 0.13 m for 16 particles (...); the domain is too large for the smoothing length"
    # (also for a polygon translated to y = 1e15, through the default domain)
    "domain of 2e6 m": _HEAD.format(dim=2) + "domain = [[-1e6, -1e6], [1e6, 1e6]]\n" + _BOX,
}
SEED_SIMULATION_LEAKS = {
    # OverflowError in taisph.engine.assembly.param_table, `self.sigma / h ** (dim + 2)`: dx = sqrt(m / rho0)
    # = 3e148 m, h**4 overflows
    "mass 1e300": (b"2\n0 0 0 0 0 1e300 1000 0 0\n1 0 1 0 0 1e300 1000 0 0\n", None),
    # "the neighbour grid would need 1.8e21 cells ...; the domain is too large" without the file
    "position x = 1e19": (b"2\n0 1e19 0 0 0 1 1000 0 0\n1 0 1 0 0 1 1000 0 0\n", None),
}


@with_examples(SCENE_LEAKS, "text")
@given(text=scene_texts())
@KNOWN
def test_known_scene_file_leaks(folder, text):
    check_scene_text(folder, text, cli_every=1)


@with_examples(SEED_LEAKS, "files")
@given(files=seed_files())
@KNOWN
def test_known_seed_file_leaks(folder, files):
    check_seed_files(folder, *files, cli_every=1)


@given(text=scene_texts())
@CI
def test_fuzzed_scene_files_run_or_are_refused_with_the_file_and_key(folder, text):
    check_scene_text(folder, text, CLI_EVERY["ci"])


@given(files=seed_files())
@CI
def test_fuzzed_seed_files_run_or_are_refused_with_the_file_and_line(folder, files):
    check_seed_files(folder, *files, CLI_EVERY["ci"])


@pytest.mark.slow
@given(text=scene_texts())
@SLOW
def test_fuzzed_scene_files_run_or_are_refused_with_the_file_and_key_slow(folder, text):
    check_scene_text(folder, text, CLI_EVERY["slow"], simulate=True)


@pytest.mark.slow
@given(files=seed_files())
@SLOW
def test_fuzzed_seed_files_run_or_are_refused_with_the_file_and_line_slow(folder, files):
    check_seed_files(folder, *files, CLI_EVERY["slow"], simulate=True)


@pytest.mark.slow
@with_examples(SCENE_SIMULATION_LEAKS, "text")
@given(text=scene_texts())
@KNOWN
def test_known_scene_file_leaks_at_the_simulation_slow(folder, text):
    check_scene_text(folder, text, cli_every=1, simulate=True)


@pytest.mark.slow
@with_examples(SEED_SIMULATION_LEAKS, "files")
@given(files=seed_files())
@KNOWN
def test_known_seed_file_leaks_at_the_simulation_slow(folder, files):
    check_seed_files(folder, *files, cli_every=1, simulate=True)
