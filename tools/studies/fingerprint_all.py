"""State fingerprints of every built-in case and shipped scene file, to show that a
change of the code's structure changes no result.

    python -m tools.studies.fingerprint_all > before.txt
    (change the code)
    python -m tools.studies.fingerprint_all > after.txt && diff before.txt after.txt

Each line is one configuration: the case or scene file, its settings, the solver, and
the SHA-256 of the positions, velocities, densities, pressures (in particle-id order, as
float64 bytes), the particle count and the clock after `STEPS` deterministic steps
(serial cell sort: bit-reproducible). Every case runs at its defaults (a coarser dx
where the default would take minutes), with each solver it accepts; scene files as
shipped. ``--only NAME`` runs the lines whose label contains NAME.
"""

import argparse
import hashlib
import sys

import numpy as np

import taisph
from taisph.formats.scenefile import load
from taisph.scene import catalogue

STEPS = 40

# (case, settings): defaults unless a setting makes a run of STEPS steps short
CASES = [
    ("channel", dict(dx=5e-5)),
    ("couette", dict(dx=1e-4)),
    ("cylinder", dict(dx=0.01)),
    ("dam_break", dict(dx=0.04)),
    ("dam_break", dict(dx=0.04, seed_physics=True)),
    ("dam_break_3d", dict(dx=0.08)),
    ("dam_break_wedge", dict(dx=0.04)),
    ("drop_on_incline", dict()),
    ("drop_on_incline", dict(dim=3)),
    ("elliptical_drop", dict()),
    ("floating_box", dict()),
    ("floating_box", dict(dim=3, dx=0.05)),
    ("hydrostatic_tank", dict()),
    ("poiseuille", dict(dx=1e-4)),
    ("sedov", dict(dx=0.02)),
    ("sod", dict()),
    ("solitary_wave", dict(dx=0.02)),
    ("taylor_green", dict()),
    ("two_fluids", dict()),
    ("water_entry", dict(dx=0.01)),
    ("wave_flume", dict()),
]
DFSPH = {"dam_break", "dam_break_3d", "hydrostatic_tank", "couette", "poiseuille"}


def digest(sim) -> str:
    h = hashlib.sha256()
    for array in (sim.positions(), sim.velocities(), sim.density(), sim.pressure(), np.array([sim.time, sim.n])):
        h.update(np.ascontiguousarray(array, dtype=np.float64).tobytes())
    return h.hexdigest()[:16]


def configurations():
    for case, settings in CASES:
        solvers = ["wcsph", "dfsph"] if case in DFSPH and not settings.get("seed_physics") else ["wcsph"]
        for solver in solvers:
            label = f"{case} {settings} {solver}"
            yield label, lambda case=case, settings=settings, solver=solver: _case(case, settings, solver)
    for path in catalogue.scene_files():
        yield path.name, lambda path=path: _file(path)


def _case(case, settings, solver):
    scene = catalogue.find(case)(**settings)
    scene.solver = solver
    return taisph.Simulation(scene, deterministic=True)


def _file(path):
    scene, run = load(path)
    return taisph.Simulation(scene, deterministic=True, **run.controls,
                             **({"courant": run.courant} if run.courant else {}))


def main(argv=None):
    p = argparse.ArgumentParser(prog="python -m tools.studies.fingerprint_all", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--steps", type=int, default=STEPS)
    p.add_argument("--only", default="")
    args = p.parse_args(argv)
    for label, make in configurations():
        if args.only not in label:
            continue
        try:
            sim = make()
            sim.step(args.steps)
            line = f"{label}: {sim.steps} steps, n {sim.n}, t {sim.time!r}, state {digest(sim)}"
            sim.close()
        except Exception as err:  # a configuration that fails is a line too: the diff shows it
            line = f"{label}: failed: {type(err).__name__}: {err}"
        print(line, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
