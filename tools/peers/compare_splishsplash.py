"""taisph's DFSPH against SPlisHSPlasH's on the 2D dam break, in the same run, the peer at its best.

    python -m tools.benchmarks.bench --compare-splishsplash --splishsplash-python /path/to/splash-venv/bin/python
    python -m tools.peers.compare_splishsplash --splishsplash-python ... --dx 0.01 --tf 0.2 1.0
    export TAISPH_SPLISHSPLASH_PYTHON=/path/to/splash-venv/bin/python   # instead of the option

Both simulate the 1 m x 2 m column in the 4 m tank at spacing dx from rest to each end
time (issue 25: dx = 0.01, ~20k fluid particles; 0.2 s, before the impact, and 1 s,
through it: the figure that counts), one after the other in the same minutes on the same
machine (2 threads each): taisph with its defaults (a 0.02 % mean density error; and at
the peer's 0.1 % with --also-tolerance 0.001), SPlisHSPlasH with its DFSPH at 0.1 % on
both solves, once per volume-map grid of its walls (``--maps``: its default 20 x 20 x 20
and finer ones; the fastest is kept, as a peer is compared at its best). Each figure is
wall seconds per simulated second of the stepping: taisph's ``Simulation.run`` after its
first (compiling) step, and SPlisHSPlasH's summed simulation steps ("Time sum: SimStep"
of its log; its volume-map construction and set-up excluded). SPlisHSPlasH runs in its
own Python (``--splishsplash-python``, or the environment variable
TAISPH_SPLISHSPLASH_PYTHON: one of them is required; tools/peers/splishsplash_dam_break.py),
with the system libGL preloaded (``--libgl``; default: the environment variable
TAISPH_SPLISHSPLASH_LIBGL, else the system's libGL by name, e.g. libGL.so.1), two
OpenMP threads that sleep at barriers. Prints every run, and for each end time the ratio
taisph / the fastest SPlisHSPlasH (below 1: taisph is faster).
"""

import argparse
import ctypes.util
import json
import os
import subprocess
import sys
import time
from importlib.util import find_spec

from tools.benchmarks.machine import cpu

SPLISHSPLASH_PYTHON_ENV = "TAISPH_SPLISHSPLASH_PYTHON"
LIBGL_ENV = "TAISPH_SPLISHSPLASH_LIBGL"


def splishsplash_python(given=None):
    """The Python with pysplishsplash: `given` (the command-line option), else
    $TAISPH_SPLISHSPLASH_PYTHON; exits with a message if neither is set."""
    python = given or os.environ.get(SPLISHSPLASH_PYTHON_ENV)
    if not python:
        sys.exit(f"no Python with pysplishsplash: give --splishsplash-python PATH or set {SPLISHSPLASH_PYTHON_ENV}")
    return python


def default_libgl():
    """The libGL to preload for SPlisHSPlasH: $TAISPH_SPLISHSPLASH_LIBGL if set ('' for
    none), else the system's libGL by name (e.g. libGL.so.1), else ''."""
    if LIBGL_ENV in os.environ:
        return os.environ[LIBGL_ENV]
    return ctypes.util.find_library("GL") or ""


def run_taisph(dx, tf, precision="f64", tolerance=None):
    import taichi as ti

    import taisph

    def simulation():
        scene = taisph.cases.dam_break(dx=dx)
        scene.solver = "dfsph"
        controls = {} if tolerance is None else {"dfsph_tolerance": tolerance}
        return taisph.Simulation(scene, precision=precision, **controls)

    warm = simulation()  # compiles the kernels, which the next simulation of the configuration reuses
    warm.step(1)
    warm.close()
    sim = simulation()
    t1 = sim.time
    start = time.perf_counter()
    summary = sim.run(t_end=tf, frames=1)
    ti.sync()
    wall = time.perf_counter() - start
    ps = summary.pressure_solve
    out = dict(code=f"taisph DFSPH, tolerance {100 * sim.controls.dfsph_tolerance:g} %, CFL {sim.controls.courant:g} h", fluid=sim.n_fluid, steps=summary.steps, sim_time=sim.time - t1, wall=wall,
               sim_step_s=summary.wall_time, dt_mean=summary.dt_mean,
               density_iterations=ps["density_iterations_mean"], divergence_iterations=ps["divergence_iterations_mean"],
               bytes_per_particle=sim.bytes_per_particle())
    sim.close()
    return out


def run_splishsplash(python, dx, tf, libgl=None, map_resolution=(20, 20, 20), cfl_factor=1.0):
    libgl = default_libgl() if libgl is None else libgl
    env = dict(os.environ)
    if libgl:
        env["LD_PRELOAD"] = libgl
    # 2 OpenMP threads that sleep at barriers: with the default (spinning) policy, on this
    # shared 2-core VM, a step took 406 ms instead of 66 (other jobs held the cores)
    env.setdefault("OMP_NUM_THREADS", "2")
    env.setdefault("OMP_WAIT_POLICY", "passive")
    script = find_spec("tools.peers.splishsplash_dam_break").origin  # run as a file: its Python has no taisph
    cmd = [python, script, "--dx", str(dx), "--tf", str(tf), "--map-resolution", *map(str, map_resolution),
           "--cfl-factor", str(cfl_factor)]
    print(f"# SPlisHSPlasH: LD_PRELOAD={libgl} OMP_NUM_THREADS={env['OMP_NUM_THREADS']} "
          f"OMP_WAIT_POLICY={env['OMP_WAIT_POLICY']} {' '.join(cmd)}", flush=True)
    done = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if done.returncode != 0:
        sys.exit(f"SPlisHSPlasH run failed ({done.returncode}):\n{done.stderr[-2000:]}{done.stdout[-2000:]}")
    out = json.loads(done.stdout.strip().splitlines()[-1])
    out["code"] += f", tolerance 0.1 %, map {'x'.join(map(str, map_resolution))}, CFL {0.4 * cfl_factor:g} dx"
    return out


MAPS = ((20, 20, 20), (40, 40, 20), (80, 80, 20))  # SPlisHSPlasH's default grid, the 40 x 40, finer
# SPlisHSPlasH's cflFactor (dt = factor 0.4 dx / max |v|): the 1, and the step rule taisph's
# DFSPH uses (C h / max |v| = 0.5 x 1.3 dx = 0.65 dx: factor 1.625), so that a larger step is
# not an advantage the peer is denied; the fastest run is kept
CFL_FACTORS = (1.0, 1.625)


def per_second(row):
    return row["sim_step_s"] / row["sim_time"]


def compare(python, dx=0.01, tfs=(0.2, 1.0), precision="f64", libgl=None, tolerances=(None,), maps=MAPS,
            cfl_factors=CFL_FACTORS):
    """For each end time: taisph (at each tolerance, None: its default), then SPlisHSPlasH with
    each map; print the table and the ratios to the fastest SPlisHSPlasH; return the rows."""
    rows = []
    print("| code | end s | fluid | steps | mean dt (s) | density / divergence iterations per step | stepping wall s "
          "| wall s per simulated s |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|", flush=True)
    ratios = []
    for tf in tfs:
        ours = [run_taisph(dx, tf, precision, t) for t in tolerances]
        theirs = [run_splishsplash(python, dx, tf, libgl, m, f) for f in cfl_factors for m in maps]
        for r in (*ours, *theirs):
            print(f"| {r['code']} | {tf:g} | {r['fluid']} | {r['steps']} | {r['dt_mean']:.3g} | "
                  f"{r['density_iterations']:.1f} / {r['divergence_iterations']:.1f} | {r['sim_step_s']:.2f} | "
                  f"{per_second(r):.1f} |", flush=True)
        best = min(theirs, key=per_second)
        for r in ours:
            ratios.append(f"to {tf:g} s: {r['code']} / {best['code']}: x{per_second(r) / per_second(best):.2f}")
        rows += [dict(r, end=tf) for r in (*ours, *theirs)]
    for line in ratios:
        print(line + " (wall time per simulated second; target <= 1.0, goal <= 0.5)")
    return rows


def main(argv=None):
    p = argparse.ArgumentParser(prog="python -m tools.peers.compare_splishsplash",
                                description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--splishsplash-python", default=None,
                   help=f"a Python with pysplishsplash installed (default ${SPLISHSPLASH_PYTHON_ENV}; one is required)")
    p.add_argument("--dx", type=float, default=0.01)
    p.add_argument("--tf", type=float, nargs="+", default=[0.2, 1.0], help="end times (s; default 0.2 1.0)")
    p.add_argument("--also-tolerance", type=float, default=None,
                   help="also run taisph at this dfsph_tolerance (e.g. 0.001, the peer's 0.1 %%)")
    p.add_argument("--maps", default="20x20x20,40x40x20,80x80x20",
                   help="SPlisHSPlasH's volume-map grids to try, comma-separated (default %(default)s)")
    p.add_argument("--cfl-factors", default=",".join(f"{f:g}" for f in CFL_FACTORS),
                   help="SPlisHSPlasH's cflFactor values to try with each map (default %(default)s)")
    p.add_argument("--precision", choices=["f32", "f64"], default="f64")
    p.add_argument("--libgl", default=None,
                   help=f"preloaded for SPlisHSPlasH ('' for none; default ${LIBGL_ENV}, "
                        "else the system's libGL by name)")
    args = p.parse_args(argv)
    maps = [tuple(int(n) for n in m.split("x")) for m in args.maps.split(",")]
    tolerances = (None,) if args.also_tolerance is None else (None, args.also_tolerance)
    print(f"# processor: {cpu()}, {time.strftime('%Y-%m-%d %H:%M')}", flush=True)
    compare(splishsplash_python(args.splishsplash_python), args.dx, args.tf, args.precision, args.libgl,
            tolerances, maps, [float(f) for f in args.cfl_factors.split(",")])


if __name__ == "__main__":
    main()
