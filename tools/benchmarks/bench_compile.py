"""Time to first step, cold and warm, and a 10-run parameter sweep that compiles once.

    python -m tools.benchmarks.bench_compile

Cold: a new process with an empty Taichi offline cache (TI_OFFLINE_CACHE_FILE_PATH
pointed at a fresh folder): import, build the 2D dam break (dx = 0.02) or the 3D one
(dx = 0.1), compile and run the first step. Warm: the same again with that cache filled. Then, in one
process, ten dam breaks with different viscosity, sound speed and resolution, each
run 20 steps: the kernels compile for the first and are reused by the other nine
(the count of compiled Taichi kernel instances is printed after each run).
"""

import json
import os
import subprocess
import sys
import tempfile
import time

FIRST_STEP = """
import json, time
t0 = time.perf_counter()
import taichi as ti, taisph
t1 = time.perf_counter()
sim = taisph.Simulation(CASE)
sim.step(1); ti.sync()
t2 = time.perf_counter()
print(json.dumps(dict(imports=t1 - t0, first_step=t2 - t1)))
"""


CASES = {"2D": "taisph.cases.dam_break(dx=0.02)", "3D": "taisph.cases.dam_break_3d(dx=0.1)"}


def first_step(cache: str, case: str) -> dict:
    env = dict(os.environ, TI_OFFLINE_CACHE_FILE_PATH=cache)
    code = FIRST_STEP.replace("CASE", case)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def sweep() -> None:
    import taichi as ti

    import taisph

    print("| run | dx | alpha | c0 | particles | compiled kernel instances | wall s (build + 20 steps) |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    for k in range(10):
        dx = (0.02, 0.025, 0.03)[k % 3]
        alpha, c0 = 0.05 + 0.02 * k, 60.0 + 5 * k
        start = time.perf_counter()
        sim = taisph.Simulation(taisph.cases.dam_break(dx=dx, alpha=alpha, c0=c0))
        sim.step(20)
        ti.sync()
        wall = time.perf_counter() - start
        print(f"| {k + 1} | {dx} | {alpha:.2f} | {c0:.0f} | {sim.n} | {sim.solver.compiled_count()} | {wall:.2f} |",
              flush=True)
        sim.close()


def main():
    print("| case | offline cache | import s | build + compile + first step s |")
    print("|---|---|---:|---:|")
    for name, case in CASES.items():
        with tempfile.TemporaryDirectory(prefix="taisph-ticache-") as cache:
            cold = first_step(cache, case)
            warm = first_step(cache, case)
        print(f"| {name} | cold (empty) | {cold['imports']:.2f} | {cold['first_step']:.2f} |")
        print(f"| {name} | warm | {warm['imports']:.2f} | {warm['first_step']:.2f} |", flush=True)
    print()
    sweep()


if __name__ == "__main__":
    main()
