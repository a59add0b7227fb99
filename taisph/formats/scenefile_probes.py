"""Scene files: the ``[[probes]]`` blocks (:class:`taisph.probes.Probe`), checked for
:mod:`.scenefile_spec` after the walls and bodies they may name: pressure, elevation and
flow probes' points inside the domain (:func:`taisph.probes.spec.outside`, the one rule
of every probe), a force probe's wall group and a body probe's body among the file's.
Errors read ``FILE: probes[0].at = [5.0, 0.1]: x = 5 is outside the domain ...``, as the
other blocks'.
"""

from __future__ import annotations

from ..probes.spec import FACES, KINDS, Probe, face_problem, outside
from ..scene.names import UP
from ..scene.parameters import integer, one_of
from .scenefile_open import MISSING

PROBE_KEYS = {"name", "kind", "at", "to", "walls", "every", "body"}
RANGES = {"kind": one_of(*KINDS), "every": integer(at_least=1)}


def probes(check, entries, spec, lo, hi) -> list:
    """The checked blocks `entries` of the spec `spec` (`check`: the spec reader's checker),
    their points inside the box from `lo` to `hi` (the scene's domain)."""
    out, names = [], {}
    bodies = [b.name for b in spec.bodies or ()]
    groups = [w.name for w in spec.walls] + bodies  # a body is a wall group too
    for k, p in enumerate(entries):
        key = f"probes[{k}]"
        check.keys(key, p, PROBE_KEYS)
        name = check.text(f"{key}.name", p.get("name", MISSING))
        if name in names:
            check.fail(f"{key}.name", name, f"already the name of probes[{names[name]}]")
        names[name] = k
        kind = check.choice(f"{key}.kind", p.get("kind", MISSING), RANGES["kind"])
        probe = Probe(name, kind, every=check.number(f"{key}.every", p.get("every", 1), RANGES["every"]))
        needs, face = {"force": "walls", "body": "body"}.get(kind, "at"), kind in FACES  # faces: at and to (flow: both)
        for extra in sorted({"at", "to", "walls", "body"} - {needs} - ({"to"} if face else set())):
            if extra in p:
                check.fail(f"{key}.{extra}", p[extra], f"a {kind} probe takes {needs}{' (and to)' * face}, not {extra}")
        if kind == "body":  # a [[bodies]] block's name; default: the probe's
            probe.body = check.text(f"{key}.body", p.get("body", name))
            if probe.body not in bodies:
                what = ("no body of that name" if "body" in p else
                        f"required unless the probe's name, {name!r}, is a body's")
                check.fail(f"{key}.body", p.get("body", MISSING),
                           f"{what}; bodies: {', '.join(bodies) or 'none ([[bodies]] blocks)'}")
        elif kind == "force":
            probe.walls = check.text(f"{key}.walls", p.get("walls", MISSING))
            if probe.walls not in groups:
                check.fail(f"{key}.walls", probe.walls,
                           f"no wall group of that name; wall groups: {', '.join(groups) or 'none'}")
        else:
            axes = list(range(spec.dim)) if face else [a for a in range(spec.dim) if a != UP]
            for point in ("at", "to") if "to" in p or kind == "flow" else ("at",):
                setattr(probe, point, check.vector(f"{key}.{point}", p.get(point, MISSING), len(axes)))
            if kind == "flow" and (bad := face_problem(probe.at, probe.to, spec.dim)):
                check.fail(f"{key}.to", p["to"], bad)
            if (bad := outside(probe, (lo, hi))) is not None:  # the one rule of every probe
                check.fail(f"{key}.{bad[0]}", p[bad[0]], bad[1])
        out.append(probe)
    return out
