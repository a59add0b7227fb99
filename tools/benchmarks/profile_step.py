"""Where the engine's step spends its time: Taichi's kernel profiler on the flagship 2D dam break.

    python -m tools.benchmarks.profile_step 20000 300     # fluid particles, steps (after as many to warm up)

Builds ``bench_reference.flagship(2, dx)`` with dx = sqrt(2 / N) (the bench's sizes),
steps it N steps to compile and warm up, then profiles the next N steps and prints the
wall time per step, ns per fluid particle-step and Taichi's table of offloaded tasks
(one row per parallel or serial loop of a kernel: the sort kernel's loops, the dummy
walls' pressure pass, the force pass). Kernel names are Taichi's; the largest row is the
force pass. Below ``taisph.run.simulation.SERIAL_SORT_BELOW`` particles the sort kernel runs
as one serial task.
"""

import math
import os
import sys
import time

os.environ["TAISPH_PROFILE"] = "1"  # before taisph starts Taichi: kernel_profiler=True

import taichi as ti  # noqa: E402

import taisph  # noqa: E402
from tools.benchmarks.bench_reference import flagship  # noqa: E402


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    n_fluid = int(argv[0]) if argv else 20_000
    steps = int(argv[1]) if len(argv) > 1 else 300
    sim = taisph.Simulation(flagship(2, math.sqrt(2.0 / n_fluid)))
    sim.step(steps)
    ti.sync()
    ti.profiler.clear_kernel_profiler_info()
    start = time.perf_counter()
    sim.step(steps)
    ti.sync()
    wall = time.perf_counter() - start
    print(f"fluid {sim.n_fluid}, walls {sim.n - sim.n_fluid}, steps {sim.steps - steps}..{sim.steps}, "
          f"t = {sim.time:.4g} s: {wall / steps * 1e3:.3f} ms per step, "
          f"{wall / (steps * sim.n_fluid) * 1e9:.1f} ns per fluid particle-step")
    ti.profiler.print_kernel_profiler_info("count")
    sim.close()


if __name__ == "__main__":
    main()
