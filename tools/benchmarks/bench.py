"""Benchmark: the flagship dam break's throughput, against a hand-fused reference loop.

    python -m tools.benchmarks.bench                      # 2D ~10k, 20k, 100k, 1M fluid particles + 3D ~60k
    python -m tools.benchmarks.bench --quick              # 2D ~10k and 20k only
    python -m tools.benchmarks.bench --precision f32 --threads 1
    python -m tools.benchmarks.bench --compare --pysph-python /path/to/pysph-venv/bin/python
    python -m tools.benchmarks.bench --skin 0.3           # with neighbour lists (no reference then)
    python -m tools.benchmarks.bench --compare-splishsplash --splishsplash-python /path/to/splash-venv/bin/python
                                           # or TAISPH_SPLISHSPLASH_PYTHON set (tools/peers/compare_splishsplash.py)

For each size the engine's whole step (``taisph.Simulation.step``: sort, passes,
force, adaptive dt, guards) and ``tools/benchmarks/bench_reference.py`` (a hand-fused loop with
exactly the same physics and integrator, from the same particles) run in the same
process, in alternating blocks of steps; each prints its best block. The VM this was
developed on drifts up to 2x within minutes, so the ratio engine/reference (speed of
the engine over the reference's: 1.0 means as fast) is the figure to trust, not either
throughput alone.

Columns: fluid and wall particles; steps per block; ns per fluid particle-step and
M fluid particle-steps per second of the engine and of the reference; their ratio;
the engine's wall seconds per simulated second (at the block's mean dt); compile s
(building the simulation and its first step: kernels compile once per configuration
and size class, or load from Taichi's offline cache); bytes per particle.

--compare runs taisph's dam break and then PySPH's dam_break_2d example (through
tools/peers/pysph_dam_break.py, which sets PySPH's particle mass and smoothing length from
the spacing) at the same spacing and end time, output off, OpenMP on, and prints
both throughputs, both wall seconds per simulated second, and their ratios. Both
sides exclude compilation and set-up (taisph: a first step; PySPH: the difference of
two runs to tf/4 and tf).
"""

import argparse
import json
import math
import os
import platform
import subprocess
import sys
import time
from importlib.util import find_spec

import taichi as ti

import taisph
from tools.benchmarks.bench_reference import flagship, setup as reference_setup
from tools.benchmarks.machine import cpu
from tools.peers.compare_splishsplash import SPLISHSPLASH_PYTHON_ENV, splishsplash_python
from tools.peers.compare_splishsplash import compare as compare_splishsplash

SIZES_2D = (10_000, 20_000, 100_000, 1_000_000)  # fluid particles: 2 / dx^2 (1 m x 2 m column)
SIZE_3D = 60_000  # 2 / dx^3


def sizes(quick: bool, cases):
    out = []
    if "2d" in cases:
        out += [(2, math.sqrt(2.0 / n)) for n in (SIZES_2D[:2] if quick else SIZES_2D)]
    if "3d" in cases and not quick:
        out.append((3, (2.0 / SIZE_3D) ** (1 / 3)))
    return out


def timed_block(step, steps: int) -> float:
    """Wall seconds of `steps` steps (synchronised before and after)."""
    ti.sync()
    start = time.perf_counter()
    step(steps)
    ti.sync()
    return time.perf_counter() - start


def bench(dim: int, dx: float, steps: int, repeat: int, precision: str, skin=None, with_reference=True) -> dict:
    scene = flagship(dim, dx)
    if skin is not None:
        scene.neighbour_skin = skin
    start = time.perf_counter()
    sim = taisph.Simulation(scene, precision=precision)
    sim.step(1)
    ti.sync()
    compile_time = time.perf_counter() - start
    ref = reference_setup(flagship(dim, dx), real=sim.runtime.real) if with_reference and not skin else None
    if ref is not None:
        ref.step(1)
    engine, reference = math.inf, math.inf
    t0 = sim.time
    for _ in range(repeat):  # alternating blocks: both see the same machine
        engine = min(engine, timed_block(sim.step, steps))
        if ref is not None:
            reference = min(reference, timed_block(ref.step, steps))
    dt_mean = (sim.time - t0) / (repeat * steps)
    n = sim.n_fluid
    row = dict(dim=dim, dx=dx, fluid=n, walls=sim.n - n, steps=steps, compile=compile_time,
               engine_ns=engine / (n * steps) * 1e9, reference_ns=reference / (n * steps) * 1e9,
               per_sim_second=engine / (steps * dt_mean), bytes=sim.bytes_per_particle())
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
    script = find_spec("tools.peers.pysph_dam_break").origin  # run as a file: PySPH's Python has no taisph
    cmd = [pysph_python, script, "--dx", str(dx), "--tf", str(tf), "--openmp"]
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
    p = argparse.ArgumentParser(prog="python -m tools.benchmarks.bench",
                                description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--quick", action="store_true", help="small sizes only")
    p.add_argument("--precision", choices=["f32", "f64"], default="f64")
    p.add_argument("--threads", type=int, default=None)
    p.add_argument("--repeat", type=int, default=5, help="alternating blocks per size (the best is reported)")
    p.add_argument("--work", type=float, default=4e6,
                   help="fluid particle-steps per block (steps = work / particles, at least 3)")
    p.add_argument("--compare", action="store_true", help="run PySPH's dam_break_2d after taisph (see above)")
    p.add_argument("--pysph-python", default="python", help="a Python with PySPH installed (for --compare)")
    p.add_argument("--dx", type=float, default=0.01, help="spacing for --compare (0.01: 20k fluid particles)")
    p.add_argument("--tf", type=float, default=0.05, help="simulated time for --compare")
    p.add_argument("--skin", type=float, default=None,
                   help="neighbour list skin as a fraction of the support radius (0: no lists; default: the case's)")
    p.add_argument("--cases", default="2d,3d", help="which sizes: 2d, 3d or both (default)")
    p.add_argument("--compare-splishsplash", action="store_true",
                   help="taisph's DFSPH and SPlisHSPlasH's on the dam break (dx 0.01, to 0.2 s; "
                        "tools/peers/compare_splishsplash.py)")
    p.add_argument("--splishsplash-python", default=None,
                   help="a Python with pysplishsplash (for --compare-splishsplash; "
                        f"default ${SPLISHSPLASH_PYTHON_ENV})")
    args = p.parse_args(argv)

    rt = taisph.engine.runtime.init(precision=args.precision, threads=args.threads)
    print(f"# taisph {taisph.__version__}, taichi {ti.__version__}, {platform.python_version()}, "
          f"{platform.machine()}, {os.cpu_count()} cores, {rt.threads} thread(s), {rt.precision}, "
          f"arch {rt.arch}, {time.strftime('%Y-%m-%d %H:%M')}")
    print(f"# processor: {cpu()}")
    print(f"# command: python -m tools.benchmarks.bench {' '.join(sys.argv[1:] if argv is None else argv)}")
    if args.compare_splishsplash:  # in its own module: tools/peers/compare_splishsplash.py
        compare_splishsplash(splishsplash_python(args.splishsplash_python), dx=args.dx, tfs=(0.2, 1.0),
                             precision=args.precision)
        return
    if args.compare:
        compare(args.dx, args.tf, args.pysph_python, args.precision, args.skin)
        return
    print("| dim | fluid | walls | steps | engine ns/particle-step | engine M/s | reference ns | reference M/s "
          "| engine / reference | wall s per simulated s | compile s | bytes per particle |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for dim, dx in sizes(args.quick, args.cases.split(",")):
        fluid_estimate = 2.0 / dx**dim
        steps = max(3, int(args.work / fluid_estimate))
        r = bench(dim, dx, steps, args.repeat, args.precision, args.skin)
        print(f"| {dim} | {r['fluid']} | {r['walls']} | {r['steps']} | {r['engine_ns']:.0f} | "
              f"{1e3 / r['engine_ns']:.2f} | {r['reference_ns']:.0f} | {1e3 / r['reference_ns']:.2f} | "
              f"{r['reference_ns'] / r['engine_ns']:.2f} | {r['per_sim_second']:.1f} | {r['compile']:.2f} | "
              f"{r['bytes']} |", flush=True)


if __name__ == "__main__":
    main()
