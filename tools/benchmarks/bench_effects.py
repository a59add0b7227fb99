"""Benchmark: the cost of each effect, alone and all together.

    python -m tools.benchmarks.bench_effects                 # ~20k fluid particles, f64
    python -m tools.benchmarks.bench_effects --n 100000 --precision f32

Every row runs the same fluid block (a square lattice, small random velocities) with
a fixed time step. "fluid only" is the least a weakly compressible fluid needs:
continuity, pressure gradient and the Tait EOS, in a box periodic on both axes. Each
other row adds one effect; wall rows close the box at the bottom and the top with
that wall model's particles (their particles are part of the effect's cost). The
last row has every water effect together (dummy-particle walls).

Printed per row: the effects compiled in, particles, compile s (first step),
ns per fluid particle-step (best of --repeat blocks; noise on a shared VM makes the
median misleading for small differences), the ratio to "fluid only", and
M fluid particle-steps/s.
"""

import argparse
import math
import os
import platform
import sys
import time

import numpy as np
import taichi as ti

import taisph
from taisph.scene import Material, Scene
from taisph.geometry import box_walls, lattice, wall_layers
from taisph.terms import (AdamiWall, ArtificialViscosity, Continuity, DensityDiffusion, Gravity, LaminarViscosity,
                          LennardJonesWall, ParticleShifting, PressureGradient, XSPH)


def scene_with(extra: str, n: int) -> Scene:
    side = max(8, int(round(math.sqrt(n))))
    dx = 1.0 / side
    L = 1.0
    walls = extra in ("Lennard-Jones walls", "dummy walls", "all")
    dummy = extra in ("dummy walls", "all")
    terms = [Continuity(walls=dummy), PressureGradient(walls=dummy)]
    if extra in ("artificial viscosity", "all"):
        terms.append(ArtificialViscosity(alpha=0.1))
    if extra == "laminar viscosity":
        terms.append(LaminarViscosity(nu=1e-3))
    if extra in ("gravity", "all"):
        terms.append(Gravity(gravity=(0.0, -9.81)))
    if extra == "Lennard-Jones walls":
        terms.append(LennardJonesWall(lj_strength=10.0, lj_cutoff=dx / 2))
    if dummy:
        terms.append(AdamiWall())
    if extra in ("density diffusion", "all"):
        terms.append(DensityDiffusion(delta=0.1, hydrostatic=extra == "all"))
    if extra in ("XSPH", "all"):
        terms.append(XSPH(xsph_eps=0.5))
    if extra == "particle shifting":
        terms.append(ParticleShifting(shift_speed=1.0))
    h = 1.3 * dx
    pad = 3 * dx
    domain = ((0.0, -pad), (L, L + pad)) if walls else ((0.0, 0.0), (L, L))
    scene = Scene(name="effects", dim=2, dx=dx, smoothing_length=h, domain=domain,
                  periodic=(True, not walls), materials=[Material("water", rho0=1000.0, c0=20.0)],
                  terms=terms, dt=1e-5, t_end=1.0, frames=1)
    rng = np.random.default_rng(1)
    fluid = lattice((0.0, 0.0), (L, L), dx)
    scene.add_fluid(fluid, velocity=rng.normal(0.0, 0.1, size=fluid.shape))
    if extra == "Lennard-Jones walls":
        line = box_walls((0.0, 0.0), (L, L), dx / 2, open_top=False)
        scene.add_walls(line[(np.isclose(line[:, 1], 0.0) | np.isclose(line[:, 1], L)) & (line[:, 0] < L - 1e-9)])
    elif dummy:
        scene.add_walls(wall_layers((0.0, 0.0), (L, L), dx, 3, open_top=False, periodic=(True, False)))
    return scene


EFFECTS = ("fluid only", "artificial viscosity", "laminar viscosity", "gravity", "Lennard-Jones walls",
           "dummy walls", "density diffusion", "XSPH", "particle shifting", "all")


def measure(extra, n, steps, repeat, precision):
    scene = scene_with(extra, n)
    start = time.perf_counter()
    sim = taisph.Simulation(scene, precision=precision)
    sim.step(1)
    ti.sync()
    compile_time = time.perf_counter() - start
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        sim.step(steps)
        ti.sync()
        best = min(best, time.perf_counter() - t0)
    row = dict(effects=", ".join(sim.effects()), particles=sim.n, fluid=sim.n_fluid, compile=compile_time,
               ns=best / (steps * sim.n_fluid) * 1e9)
    sim.close()
    return row


def main(argv=None):
    p = argparse.ArgumentParser(prog="python -m tools.benchmarks.bench_effects",
                                description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--n", type=int, default=20_000, help="fluid particles (default 20000)")
    p.add_argument("--precision", choices=["f32", "f64"], default="f64")
    p.add_argument("--repeat", type=int, default=5)
    p.add_argument("--work", type=float, default=4e6, help="fluid particle-steps per timed block")
    args = p.parse_args(argv)
    rt = taisph.engine.runtime.init(precision=args.precision)
    print(f"# taisph {taisph.__version__}, taichi {ti.__version__}, {platform.python_version()}, "
          f"{os.cpu_count()} cores, {rt.threads} thread(s), {rt.precision}")
    print(f"# command: python -m tools.benchmarks.bench_effects {' '.join(sys.argv[1:] if argv is None else argv)}")
    print("| added effect | terms compiled in | particles | compile s | ns per fluid particle-step | × fluid only | M fluid particle-steps/s |")
    print("|---|---|---:|---:|---:|---:|---:|")
    steps = max(5, int(args.work / args.n))
    base = None
    for extra in EFFECTS:
        r = measure(extra, args.n, steps, args.repeat, args.precision)
        base = base or r["ns"]
        print(f"| {extra} | {r['effects']} | {r['particles']} | {r['compile']:.2f} | {r['ns']:.0f} | "
              f"{r['ns'] / base:.2f} | {1e3 / r['ns']:.2f} |", flush=True)


if __name__ == "__main__":
    main()
