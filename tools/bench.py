"""Benchmark: dam break throughput at several particle counts.

    python tools/bench.py                      # 2D ~10k, 100k, 1M fluid particles + 3D ~60k
    python tools/bench.py --quick              # 2D ~10k and ~40k only
    python tools/bench.py --precision f32 --threads 1
    python tools/bench.py --compare --pysph-python /path/to/pysph-venv/bin/python
    python tools/bench.py --skin 0             # walk the cells every step (no neighbour lists)
    python tools/bench.py --steps 30 --repeat 5   # every size timed over the same early flow

--compare runs taisph's dam break and then PySPH's dam_break_2d example (through
tools/pysph_dam_break.py, which sets PySPH's particle mass and smoothing length from
the spacing) at the same spacing and end time, output off, OpenMP on, and prints
both throughputs, both wall seconds per simulated second, and their ratios. Both
sides exclude compilation and set-up (taisph: a first step; PySPH: the difference of
two runs to tf/4 and tf).

For each size it prints particles, steps, compile time (building the simulation and
its first step, which compiles the kernels unless Taichi's offline cache has them),
wall time of the timed steps (median of --repeat blocks, compilation excluded),
fluid particle-steps per second, and wall seconds per simulated second.
"""

import argparse
import math
import os
import platform
import json
import statistics
import subprocess
import sys
import time

import taichi as ti

import taisph


def sizes_2d(quick: bool):
    # column 1 m x 2 m: fluid particles = 2 / dx^2
    targets = (10_000, 40_000) if quick else (10_000, 100_000, 1_000_000)
    return [("dam_break", math.sqrt(2.0 / n)) for n in targets]


def sizes_3d(quick: bool):
    # column 1 x 2 x 1 m: fluid particles = 2 / dx^3
    return [] if quick else [("dam_break_3d", (2.0 / 60_000) ** (1 / 3))]


def bench(case: str, dx: float, steps: int, repeat: int, precision: str, threads: int | None, skin=None):
    scene = getattr(taisph.cases, case)(dx=dx)
    if skin is not None:
        scene.neighbour_skin = skin
    start = time.perf_counter()
    sim = taisph.Simulation(scene, precision=precision, threads=threads)
    sim.step(1)
    ti.sync()
    compile_time = time.perf_counter() - start
    times = []
    rebuilds0, steps0 = sim.list_rebuilds, sim.steps
    for _ in range(repeat):
        t0 = time.perf_counter()
        sim.step(steps)
        ti.sync()
        times.append(time.perf_counter() - t0)
    wall = statistics.median(times)
    row = dict(
        case=case,
        dim=scene.dim,
        dx=dx,
        fluid=sim.n_fluid,
        walls=sim.n - sim.n_fluid,
        steps=steps,
        compile=compile_time,
        wall=wall,
        rate=sim.n_fluid * steps / wall,
        per_sim_second=wall / (steps * sim.dt),
        dt=sim.dt,
        bytes=sim.bytes_per_particle(),
        steps_per_rebuild=(sim.steps - steps0) / max(1, sim.list_rebuilds - rebuilds0),
    )
    sim.close()
    return row


def compare(dx: float, tf: float, pysph_python: str, precision: str, skin=None) -> None:
    scene = taisph.cases.dam_break(dx=dx)
    if skin is not None:
        scene.neighbour_skin = skin
    sim = taisph.Simulation(scene, precision=precision)
    sim.step(1)
    ti.sync()
    t1, s1 = sim.time, sim.steps
    start = time.perf_counter()
    sim.run(t_end=tf + t1, frames=1)
    wall = time.perf_counter() - start
    ours = dict(code="taisph", fluid=sim.n_fluid, steps=sim.steps - s1, sim_time=sim.time - t1, wall=wall,
                rate=sim.n_fluid * (sim.steps - s1) / wall)
    sim.close()
    here = os.path.dirname(os.path.abspath(__file__))
    cmd = [pysph_python, os.path.join(here, "pysph_dam_break.py"), "--dx", str(dx), "--tf", str(tf), "--openmp"]
    print(f"# PySPH: {' '.join(cmd)}", flush=True)
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"PySPH run failed ({out.returncode}):\n{out.stderr[-2000:]}")
    theirs = json.loads(out.stdout.strip().splitlines()[-1])
    print("| code | fluid | steps | simulated s | wall s | M fluid particle-steps/s | wall s per simulated s |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for r in (ours, theirs):
        print(f"| {r['code']} | {r['fluid']} | {r['steps']} | {r['sim_time']:.4f} | {r['wall']:.2f} | "
              f"{r['rate'] / 1e6:.2f} | {r['wall'] / r['sim_time']:.0f} |")
    print(f"taisph / PySPH: particle-steps/s x{ours['rate'] / theirs['rate']:.2f}, "
          f"wall time per simulated second x{(theirs['wall'] / theirs['sim_time']) / (ours['wall'] / ours['sim_time']):.2f} faster")


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--quick", action="store_true", help="small sizes only")
    p.add_argument("--precision", choices=["f32", "f64"], default="f64")
    p.add_argument("--threads", type=int, default=None)
    p.add_argument("--repeat", type=int, default=3, help="timed blocks per size (median reported)")
    p.add_argument("--work", type=float, default=2e7,
                   help="fluid particle-steps per timed block (steps = work / particles, at least 5)")
    p.add_argument("--compare", action="store_true", help="run PySPH's dam_break_2d after taisph (see above)")
    p.add_argument("--pysph-python", default="python", help="a Python with PySPH installed (for --compare)")
    p.add_argument("--dx", type=float, default=0.01, help="spacing for --compare (0.01: 20k fluid particles)")
    p.add_argument("--tf", type=float, default=0.05, help="simulated time for --compare")
    p.add_argument("--skin", type=float, default=None,
                   help="neighbour list skin as a fraction of the support radius (0: no lists; default: the case's)")
    p.add_argument("--cases", default="2d,3d", help="which sizes: 2d, 3d or both (default)")
    p.add_argument("--steps", type=int, default=None,
                   help="steps per timed block for every size (default: --work / particles). The same "
                        "count times every size over the same early flow, before the viscosity of "
                        "the developed flow adds cost; the default times small runs much later")
    args = p.parse_args(argv)

    rt = taisph.engine.runtime.init(precision=args.precision, threads=args.threads)
    print(f"# taisph {taisph.__version__}, taichi {ti.__version__}, {platform.python_version()}, "
          f"{platform.machine()}, {os.cpu_count()} cores, {rt.threads} thread(s), {rt.precision}, "
          f"arch {rt.arch}")
    print(f"# command: python tools/bench.py {' '.join(sys.argv[1:] if argv is None else argv)}")
    if args.compare:
        compare(args.dx, args.tf, args.pysph_python, args.precision, args.skin)
        return
    print("| case | fluid | walls | steps | compile s | wall s | M fluid particle-steps/s | wall s per simulated s "
          "| bytes per particle | steps per list rebuild |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    chosen = args.cases.split(",")
    sizes = (sizes_2d(args.quick) if "2d" in chosen else []) + (sizes_3d(args.quick) if "3d" in chosen else [])
    for case, dx in sizes:
        fluid_estimate = 2.0 / dx ** (2 if case == "dam_break" else 3)
        steps = args.steps or max(5, int(args.work / fluid_estimate))
        r = bench(case, dx, steps, args.repeat, args.precision, args.threads, args.skin)
        print(f"| {r['case']} | {r['fluid']} | {r['walls']} | {r['steps']} | {r['compile']:.2f} | "
              f"{r['wall']:.3f} | {r['rate'] / 1e6:.2f} | {r['per_sim_second']:.1f} | {r['bytes']} | "
              f"{r['steps_per_rebuild']:.1f} |", flush=True)


if __name__ == "__main__":
    main()
