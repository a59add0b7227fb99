"""Benchmark: what open boundaries cost. The channel of ``taisph.cases.channel`` with its
inlet and outlet zones, against the same channel made periodic and driven by the
equivalent body force, in the same process, in alternating blocks of steps (this VM's
speed drifts up to 2x within minutes: the ratio is the figure to trust).

    python -m tools.benchmarks.bench_open                 # H/40 (6 400 fluid particles)
    python -m tools.benchmarks.bench_open --dx 1.25e-5    # H/80 (25 600)

Both start from a steady flow (run to --warm s first) so that the open channel's zones
create and retire particles during the blocks. Columns: ns per fluid particle-step of
each (best block), the ratio open / periodic (issue 27's bar: at most 1.15), and the
particles the open run created and retired during the blocks.
"""

import argparse
import platform
import time

import taisph
from taisph.engine import status as st


def best_block(sim, steps, blocks):
    """ns per fluid particle-step of each of `blocks` blocks of `steps` steps."""
    times = []
    for _ in range(blocks):
        sim.step(1)  # settle the clock outside the timing
        start = time.perf_counter()
        sim.step(steps)
        sim.state.read(st.TIME)  # waits for the device
        times.append((time.perf_counter() - start) / (steps * sim.n_fluid) * 1e9)
    return times


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dx", type=float, default=2.5e-5, help="particle spacing (m); H = 1 mm")
    parser.add_argument("--steps", type=int, default=400, help="steps per block")
    parser.add_argument("--rounds", type=int, default=5, help="blocks of each, alternating")
    parser.add_argument("--warm", type=float, default=0.3, help="simulated seconds run before timing")
    args = parser.parse_args(argv)
    sims = {"open": taisph.Simulation(taisph.cases.channel(dx=args.dx)),
            "periodic": taisph.Simulation(taisph.cases.channel(dx=args.dx, periodic=True))}
    for sim in sims.values():
        sim.run(args.warm, frames=0)
    next_id0 = sims["open"].state.read_flag(st.NEXT_ID)
    ns = {name: [] for name in sims}
    for _ in range(args.rounds):
        for name, sim in sims.items():
            ns[name] += best_block(sim, args.steps, 1)
    created = sims["open"].state.read_flag(st.NEXT_ID) - next_id0
    best = {name: min(v) for name, v in ns.items()}
    print(f"machine: {platform.machine()}, {platform.system()}, taichi threads {taisph.engine.runtime.current().threads}")
    print(f"channel dx = {args.dx:g} m: open {sims['open'].n_fluid} fluid + {int(sims['open'].buffer.sum())} buffer "
          f"particles, periodic {sims['periodic'].n_fluid} fluid; {args.rounds} x {args.steps} steps each, alternating")
    for name in sims:
        print(f"  {name:9s} best {best[name]:7.1f} ns per fluid particle-step ({1e3 / best[name]:.2f} M/s); "
              f"blocks {', '.join(f'{v:.1f}' for v in ns[name])}")
    print(f"  open / periodic: {best['open'] / best['periodic']:.3f} (bar 1.15); the open run created {created} "
          f"particles during its blocks")


if __name__ == "__main__":
    main()
