"""Cost per fluid particle-step of the flagship 2D dam break at several sizes, timed over
the same simulated interval, so that every size is measured in the same flow state.

`tools/benchmarks/bench.py` gives every size the same number of particle-steps per block; the small
case then steps far into the collapse while the large one barely leaves rest, and a step
of moving water costs more than one of still water (the artificial viscosity acts on
approaching pairs only). Here every size is first advanced to `--t-start` (untimed; the
state is kept as a checkpoint under `--cache`, so a later run starts there at once), then
all sizes advance the same simulated interval in `--rounds` rounds, one size after the
other within each round, so that sizes are compared within the same minutes of this
shared machine (the checkpoints hold the case as it was when they were written: delete
the cache after changing the case's defaults). Each round prints ns per fluid
particle-step for every size and each size's ratio to the largest; the summary gives
the best round of each size and the median of the per-round ratios.

    python -m tools.benchmarks.bench_flatness                       # 20k, 100k, 1M; t = 0.1 -> 0.11 s
    python -m tools.benchmarks.bench_flatness --sizes 20000 100000 --t-start 0.05 --interval 0.02
    python -m tools.benchmarks.bench_flatness --reference           # the hand-fused loop's flatness too

With ``--reference`` the hand-fused loop of ``tools/benchmarks/bench_reference.py`` starts from each
size's state and, in every round, runs as many steps as the engine just took: its own
flatness, in the same minutes, is what this machine allows a loop of this physics.
"""

import argparse
import math
import statistics
import time
from pathlib import Path

import taichi as ti

import taisph
from tools.benchmarks.bench_reference import flagship, setup as reference_setup


def prepared(n_fluid: int, t_start: float, cache: Path, threads):
    """The flagship at `n_fluid` fluid particles advanced to `t_start` (from the cached
    checkpoint if there is one)."""
    dx = math.sqrt(2.0 / n_fluid)
    folder = cache / f"n{n_fluid}_t{t_start:g}"
    if (folder / "state.npz").exists():
        try:
            return taisph.Simulation.from_checkpoint(folder, threads=threads)
        except Exception as error:  # an unreadable cache is rebuilt, not trusted
            print(f"  cache {folder} not usable ({error}); rebuilding")
    sim = taisph.Simulation(flagship(2, dx), threads=threads)
    start = time.perf_counter()
    sim.run(t_end=t_start, frames=1)
    print(f"  {sim.n_fluid} fluid: advanced to t = {sim.time:g} s in {sim.steps} steps, "
          f"{time.perf_counter() - start:.0f} s (untimed)", flush=True)
    sim.save_checkpoint(folder)
    return sim


def main(argv=None):
    p = argparse.ArgumentParser(prog="python -m tools.benchmarks.bench_flatness",
                                description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--sizes", type=int, nargs="+", default=[20_000, 100_000, 1_000_000],
                   help="fluid particles (dx = sqrt(2 / n))")
    p.add_argument("--t-start", type=float, default=0.1, help="simulated time where timing starts (s)")
    p.add_argument("--interval", type=float, default=0.01, help="simulated seconds timed per size")
    p.add_argument("--rounds", type=int, default=5, help="0: only prepare the checkpoints")
    p.add_argument("--threads", type=int, default=None)
    p.add_argument("--cache", type=Path, default=Path("bench_flatness_cache"),
                   help="folder for the checkpoints at t-start")
    p.add_argument("--reference", action="store_true",
                   help="also time the hand-fused reference (tools/benchmarks/bench_reference.py) from each size's "
                        "state, as many steps as the engine took, right after it")
    args = p.parse_args(argv)
    taisph.engine.runtime.init(threads=args.threads)
    print(f"preparing {args.sizes} at t = {args.t_start:g} s (checkpoints in {args.cache})", flush=True)
    sims = [prepared(n, args.t_start, args.cache, args.threads) for n in sorted(args.sizes)]
    if args.rounds == 0:
        return
    width = args.interval / args.rounds
    for sim in sims:  # compile and warm up outside the timing: run() itself pays a first-call cost
        sim.run(t_end=sim.time + 0.1 * width, frames=1)
    refs = {}
    if args.reference:  # the hand-fused loop, started from each size's state
        for sim in sims:
            refs[sim.n_fluid] = reference_setup(sim.scene, real=sim.runtime.real, start_from=sim)
            refs[sim.n_fluid].step(2)
    ti.sync()
    t0 = max(sim.time for sim in sims)
    cost = {sim.n_fluid: [] for sim in sims}
    ref_cost = {sim.n_fluid: [] for sim in sims}
    timed_steps = {sim.n_fluid: 0 for sim in sims}
    names = [f"{sim.n_fluid:>9}" for sim in sims]
    print(f"\nns per fluid particle-step, each size over the same {width:g} s of simulated time per round"
          + ("; the reference (ref) runs as many steps as the engine did, from its own state" if refs else ""))
    print("round  t (s)      " + " ".join(names) + "   ratios to the largest"
          + ("   ref: " + " ".join(names) + "   ratios" if refs else ""))
    for k in range(args.rounds):
        t_target = t0 + (k + 1) * width
        row, ref_row = [], []
        for sim in sims:
            steps0 = sim.steps
            ti.sync()
            start = time.perf_counter()
            sim.run(t_end=t_target, frames=1)
            ti.sync()
            wall = time.perf_counter() - start
            steps = sim.steps - steps0
            ns = wall / (sim.n_fluid * steps) * 1e9
            cost[sim.n_fluid].append(ns)
            timed_steps[sim.n_fluid] += steps
            row.append(ns)
            if refs:
                ref = refs[sim.n_fluid]
                start = time.perf_counter()
                ref.step(steps)
                ti.sync()
                ns = (time.perf_counter() - start) / (ref.fluid * steps) * 1e9
                ref_cost[sim.n_fluid].append(ns)
                ref_row.append(ns)
        line = f"{k + 1:>5}  {t_target:.4f}  " + " ".join(f"{ns:>9.1f}" for ns in row)
        line += "   " + " ".join(f"{ns / row[-1]:.2f}" for ns in row[:-1])
        if refs:
            line += "        " + " ".join(f"{ns:>9.1f}" for ns in ref_row)
            line += "   " + " ".join(f"{ns / ref_row[-1]:.2f}" for ns in ref_row[:-1])
        print(line, flush=True)
    largest = sims[-1].n_fluid
    for label, table in (("engine", cost), ("reference", ref_cost)):
        if not table[largest]:
            continue
        print(f"\n{label}: size   timed steps  best ns  median ns  median ratio to the largest (same round)"
              "  best / best")
        for sim in sims:
            c = table[sim.n_fluid]
            per_round = [a / b for a, b in zip(c, table[largest])]
            print(f"{sim.n_fluid:>9} {timed_steps[sim.n_fluid]:>8} {min(c):>8.1f} {statistics.median(c):>10.1f} "
                  f"{statistics.median(per_round):>8.2f}  (rounds {min(per_round):.2f}-{max(per_round):.2f})"
                  f"  {min(c) / min(table[largest]):.2f}")


if __name__ == "__main__":
    main()
