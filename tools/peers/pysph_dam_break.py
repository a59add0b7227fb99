"""Run PySPH's dam_break_2d example at a chosen spacing and report its throughput.

Not part of taisph: run it with a Python that has PySPH installed
(`pip install pysph`, about 4 minutes to build). ``python -m tools.benchmarks.bench --compare``
calls it (by this file's path).

    /path/to/pysph-venv/bin/python -m tools.peers.pysph_dam_break --dx 0.01 --tf 0.05 --openmp

(from the repository root; it imports nothing from taisph or the rest of tools/).

PySPH's example changes the spacing with --dx but keeps its particle mass and
smoothing length at the dx = 0.03 values; this wrapper sets both from --dx (m = rho0
dx^2, h = 1.3 dx), as the example intends. Prints one JSON line: fluid particles,
steps, wall time of the run (compilation excluded: a first short run compiles), and
fluid particle-steps per second. PySPH's WCSPH scheme here uses its PEC integrator
(two rate evaluations per step) and a Wendland quintic kernel.
"""

import json
import sys
import time

from pysph.examples import dam_break_2d as db


def run(dx, tf, extra):
    db.dx = dx
    db.h = db.hdx * dx
    db.m = dx**2 * db.ro
    app = db.DamBreak2D()
    args = ["--dx", str(dx), "--tf", str(tf), "--disable-output", "--pfreq", "1000000", "-q"] + extra
    app.run(args)
    return app


def main():
    import argparse

    p = argparse.ArgumentParser(prog="python -m tools.peers.pysph_dam_break")
    p.add_argument("--dx", type=float, default=0.03)
    p.add_argument("--tf", type=float, default=0.05)
    args, extra = p.parse_known_args()
    run(args.dx, 1e-4, extra)  # compiles the generated code (cached afterwards)
    # two runs, tf/4 and tf: the difference cancels set-up (particles, neighbour
    # structures, loading the compiled module), as taisph's benchmark excludes it
    timed = []
    for tf in (args.tf / 4, args.tf):
        start = time.perf_counter()
        app = run(args.dx, tf, extra)
        timed.append((time.perf_counter() - start, app.solver.count))
    wall = timed[1][0] - timed[0][0]
    steps = timed[1][1] - timed[0][1]
    fluid = app.particles[0].get_number_of_particles()
    print(json.dumps(dict(code="pysph", dx=args.dx, fluid=fluid, steps=steps, sim_time=app.solver.t,
                          wall=wall, rate=fluid * steps / wall, setup_wall=timed[0][0] - wall / 3)))


if __name__ == "__main__":
    sys.exit(main())
