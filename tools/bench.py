"""Benchmark: dam break throughput at several particle counts.

    python tools/bench.py                      # 2D ~10k, 100k, 1M fluid particles + 3D ~60k
    python tools/bench.py --quick              # 2D ~10k and ~40k only
    python tools/bench.py --precision f32 --threads 1

For each size it prints particles, steps, compile time (building the simulation and
its first step, which compiles the kernels unless Taichi's offline cache has them),
wall time of the timed steps (median of --repeat blocks, compilation excluded),
fluid particle-steps per second, and wall seconds per simulated second.
"""

import argparse
import math
import os
import platform
import statistics
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


def bench(case: str, dx: float, steps: int, repeat: int, precision: str, threads: int | None):
    scene = getattr(taisph.cases, case)(dx=dx)
    start = time.perf_counter()
    sim = taisph.Simulation(scene, precision=precision, threads=threads)
    sim.step(1)
    ti.sync()
    compile_time = time.perf_counter() - start
    times = []
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
    )
    sim.close()
    return row


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--quick", action="store_true", help="small sizes only")
    p.add_argument("--precision", choices=["f32", "f64"], default="f64")
    p.add_argument("--threads", type=int, default=None)
    p.add_argument("--repeat", type=int, default=3, help="timed blocks per size (median reported)")
    p.add_argument("--work", type=float, default=2e7,
                   help="fluid particle-steps per timed block (steps = work / particles, at least 5)")
    args = p.parse_args(argv)

    rt = taisph.runtime.init(precision=args.precision, threads=args.threads)
    print(f"# taisph {taisph.__version__}, taichi {ti.__version__}, {platform.python_version()}, "
          f"{platform.machine()}, {os.cpu_count()} cores, {rt.threads} thread(s), {rt.precision}, "
          f"arch {rt.arch}")
    print(f"# command: python tools/bench.py {' '.join(sys.argv[1:] if argv is None else argv)}")
    print("| case | fluid | walls | steps | compile s | wall s | M fluid particle-steps/s | wall s per simulated s |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for case, dx in sizes_2d(args.quick) + sizes_3d(args.quick):
        fluid_estimate = 2.0 / dx ** (2 if case == "dam_break" else 3)
        steps = max(5, int(args.work / fluid_estimate))
        r = bench(case, dx, steps, args.repeat, args.precision, args.threads)
        print(f"| {r['case']} | {r['fluid']} | {r['walls']} | {r['steps']} | {r['compile']:.2f} | "
              f"{r['wall']:.3f} | {r['rate'] / 1e6:.2f} | {r['per_sim_second']:.1f} |", flush=True)


if __name__ == "__main__":
    main()
