"""Which integrator x kernel pairs stay stable at which time step, on the seed's scenes.

    python -m tools.studies.stability --json docs/seed_stability.json   # all three scenes (about 40 min on 2 cores)
    python -m tools.studies.stability --scenes drop_on_incline --json docs/seed_stability.json

For every scene, integrator (euler, eulermid, pc) and kernel (spline, gaussian,
wendland), runs go down a ladder of fixed time steps from the seed's advice (0.001 s).
A run is **stable** if it reaches t_end with

* a finite state (positions, velocities, densities),
* every fluid particle inside the scene's domain (the tank plus one dx), and
* every density within 10 % of its material's rho0 (|rho/rho0 - 1| <= 0.1),

checked every 0.05 s of simulated time (``taisph.formats.seed.health``); an unstable run
stops at the first failed check and records when. Going down the ladder stops at the
first stable step: smaller steps are not run (explicit schemes are assumed to stay
stable below a stable step; --confirm runs one more step to check that).
Results already in the --json file are reused (delete it to start again).
"""

import argparse
import json
import re
import sys
import time
from pathlib import Path

import numpy as np

import taisph
from taisph.engine.timestep import fixed_dt
from taisph.formats.seed import health

SCENES = {
    # scene: (builder kwargs, t_end) at the tests' resolutions
    "dam_break_wedge": (dict(dx=0.04), 0.75),
    "drop_on_incline": (dict(dx=0.02), 0.5),
    "two_fluids": (dict(dx=0.04), 1.0),
}
INTEGRATORS = ("euler", "eulermid", "pc")
KERNELS = ("spline", "gaussian", "wendland")
LADDER = (1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5, 1e-5)
CHECK_EVERY = 0.05
MAX_DENSITY_DEVIATION = 0.1


def trial(name, kwargs, t_end, integrator, kernel, dt):
    scene = taisph.cases.CASES[name](integrator=integrator, kernel=kernel, **kwargs)
    scene.dt = dt
    sim = taisph.Simulation(scene)
    fluid = sim.fluid
    rho0 = np.array([m.rho0 for m in scene.materials])[sim.materials()[fluid]]
    worst = 0.0
    start = time.perf_counter()
    problems = []
    checks = int(round(t_end / CHECK_EVERY))
    for k in range(1, checks + 1):
        try:
            sim.run(t_end * k / checks, frames=1)
        except taisph.run.simulation.SimulationError as err:  # the engine's guards tripped
            problems = err.report["codes"]
            break
        problems = health(sim, box=scene.domain, max_density_deviation=MAX_DENSITY_DEVIATION)
        if not problems:
            worst = max(worst, float(np.abs(sim.density()[fluid] / rho0 - 1).max()))
        else:
            break
    result = dict(scene=name, integrator=integrator, kernel=kernel, dt=dt, stable=not problems,
                  t_reached=sim.time, max_density_deviation=worst, problems=problems, steps=sim.steps,
                  wall_s=round(time.perf_counter() - start, 2), default_dt=fixed_dt(scene))
    sim.close()
    return result


def main(argv=None):
    p = argparse.ArgumentParser(prog="python -m tools.studies.stability",
                                description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--scenes", nargs="+", default=list(SCENES), choices=list(SCENES))
    p.add_argument("--integrators", nargs="+", default=list(INTEGRATORS), choices=list(INTEGRATORS))
    p.add_argument("--kernels", nargs="+", default=list(KERNELS), choices=list(KERNELS))
    p.add_argument("--json", type=Path, help="also write the results as JSON (reusing those already there)")
    p.add_argument("--confirm", action="store_true", help="after the first stable step, run the next smaller one")
    args = p.parse_args(argv)
    results = []
    if args.json and args.json.exists():
        results = json.loads(args.json.read_text())
    for name in args.scenes:
        kwargs, t_end = SCENES[name]
        for integrator in args.integrators:
            for kernel in args.kernels:
                stable_seen = 0
                for dt in LADDER:
                    key = (name, integrator, kernel, dt)
                    done = [x for x in results if (x["scene"], x["integrator"], x["kernel"], x["dt"]) == key]
                    r = done[0] if done else trial(name, kwargs, t_end, integrator, kernel, dt)
                    results = [x for x in results if (x["scene"], x["integrator"], x["kernel"], x["dt"]) != key] + [r]
                    state = (f"stable, max |rho/rho0-1| = {100 * r['max_density_deviation']:.2f} %" if r["stable"]
                             else f"UNSTABLE at t = {r['t_reached']:.2f} s: {'; '.join(r['problems'])}")
                    print(f"{name:16s} {integrator:8s} {kernel:8s} dt={dt:<7g} {state} "
                          f"({r['steps']} steps, {r['wall_s']} s)", flush=True)
                    if args.json:
                        args.json.write_text(json.dumps(results, indent=1))
                    stable_seen += r["stable"]
                    if stable_seen == (2 if args.confirm else 1):
                        break
    print()
    print(table(results))


def _failure(problems) -> str:
    """'blow-up' (non-finite, or a density off by more than 100 %) or the density reached."""
    text = "; ".join(problems)
    match = re.search(r"density up to ([0-9.e+]+) %", text)
    if "non-finite" in text or (match and float(match.group(1)) > 100):
        return "blow-up"
    if match:
        return f"{float(match.group(1)):.0f} %"
    return "left the domain"


def table(results) -> str:
    """Markdown tables, one per scene: rows integrator x kernel, columns dt."""
    lines = []
    for name in SCENES:
        rows = [r for r in results if r["scene"] == name]
        if not rows:
            continue
        kwargs, t_end = SCENES[name]
        dts = sorted({r["dt"] for r in rows}, reverse=True)
        lines.append(f"**{name}** ({', '.join(f'{k}={v}' for k, v in kwargs.items())}, t_end = {t_end} s, "
                     f"default dt = {rows[0]['default_dt']:.3g} s)\n")
        lines.append("| integrator | kernel | " + " | ".join(f"dt = {dt:g}" for dt in dts) + " |")
        lines.append("|---|---|" + "---:|" * len(dts))
        for integrator in INTEGRATORS:
            for kernel in KERNELS:
                cells = []
                for dt in dts:
                    r = next((x for x in rows if (x["integrator"], x["kernel"], x["dt"]) == (integrator, kernel, dt)), None)
                    if r is None:
                        cells.append("")
                    elif r["stable"]:
                        cells.append(f"✓ {100 * r['max_density_deviation']:.1f} %")
                    else:
                        cells.append(f"✗ {r['t_reached']:.2f} s, {_failure(r['problems'])}")
                if any(cells):
                    lines.append(f"| {integrator} | {kernel} | " + " | ".join(cells) + " |")
        lines.append("")
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())
