"""DFSPH's runs to the end (issue 25): the cases with the default settings, what their flow does.

    python -m tools.studies.dfsph_runs                       # all below (about 1 h on 2 cores)
    python -m tools.studies.dfsph_runs --only dam_break --dx 0.04 0.02
    python -m tools.studies.dfsph_runs --json docs/dfsph_runs.json

For each run (``--solver dfsph``, no other option):

- ``dam_break`` at each dx to t = 3 s, 60 frames: the largest fluid speed of every step
  (the device's maximum, read after each step) and of every frame, against the fastest
  physical speed (~12 m/s: the surge 2 sqrt(g H) = 8.9 m/s plus the run-up at the wall,
  WCSPH's fastest frame); the mean compression (mean over the fluid of max(rho/rho0 - 1, 0))
  of every frame; steps, solve iterations, retries, removed particles, fluid mass;
- the same to t = 1 s without frames and with 20, for the step counts (a rogue particle
  throttles the step, dt = C h / max |v|, and made them differ 7.6x);
- ``dam_break_3d`` to 2 s, ``drop_on_incline`` to its end, ``hydrostatic_tank`` for 10 s
  (rms of p - rho0 g (H - y) over rho0 g H below one kernel support of the surface).

Prints a markdown table per part (docs/dfsph.md, "Runs to the end").
"""

import argparse
import inspect
import json
import time

import numpy as np

import taisph
from taisph.engine import status as st
from taisph.validation import runs

PHYSICAL_SPEED = 12.0  # m/s: the dam break's fastest physical speed (see above)


class StepMaxima:
    """A run writer: the largest fluid speed of every step (``every`` = 1)."""

    every = 1

    def __init__(self):
        self.speed, self.when = 0.0, 0.0

    def on_start(self, sim):
        pass

    def on_steps(self, sim):
        v = sim.state.read(st.MAX_SIGNAL)  # DFSPH's signal speed is max |v| over the fluid
        if v > self.speed:
            self.speed, self.when = v, sim.device_time()

    def on_frame(self, sim, k):
        pass


def mean_compression(sim):
    rho = sim.density()[sim.fluid]
    rho0 = np.array([m.rho0 for m in sim.scene.materials])[sim.materials()[sim.fluid]]
    return float(np.mean(np.maximum(rho / rho0 - 1.0, 0.0)))


def dfsph_case(case, **params):
    """The case built for DFSPH: told so if it takes `solver` (drop_on_incline then builds
    dummy walls instead of its Lennard-Jones walls), then its solver set."""
    factory = getattr(taisph.cases, case)
    if "solver" in inspect.signature(factory).parameters:
        params["solver"] = "dfsph"
    scene = factory(**params)
    scene.solver = "dfsph"
    return scene


def dam_break(dx, t_end=3.0, frames=60, **controls):
    sim = taisph.Simulation(dfsph_case("dam_break", dx=dx), **controls)
    steps, frame_speed, compression = StepMaxima(), [], []

    def sample(s):
        v = np.linalg.norm(s.velocities()[s.fluid], axis=1)
        frame_speed.append(float(v.max()))
        compression.append(mean_compression(s))

    start = time.perf_counter()
    summary = sim.run(t_end, frames=frames, callback=sample, writers=[steps])
    wall = time.perf_counter() - start
    ps = summary.pressure_solve
    row = dict(case="dam_break", dx=dx, courant=sim.controls.courant, fluid=sim.n_fluid, t=sim.time, steps=summary.steps, wall=wall,
               step_speed_max=steps.speed, step_speed_when=steps.when, frame_speed_max=max(frame_speed),
               compression_max=max(compression), density_iterations=ps["density_iterations_mean"],
               density_iterations_max=ps["density_iterations_max"], retries=ps["retries"],
               above_tolerance=ps["steps_above_tolerance"], removed=summary.removed,
               mass_error=(summary.fluid_mass + summary.removed_mass) / float(sim.scene.mass[sim.scene.kind == 0].sum())
               - 1.0)
    sim.close()
    return row


def step_counts(dx, t_end=1.0, **controls):
    counts = {}
    for frames in (0, 20):
        sim = taisph.Simulation(dfsph_case("dam_break", dx=dx), **controls)
        summary = sim.run(t_end, frames=frames)
        counts[frames] = summary.steps
        sim.close()
    return dict(dx=dx, steps_no_frames=counts[0], steps_20_frames=counts[20],
                ratio=counts[20] / counts[0])


def other(case, t_end, controls=None, **params):
    controls = controls or {}
    if case == "hydrostatic_tank":
        out = runs.run("hydrostatic_tank", solver="dfsph", t_end=t_end, controls=controls, **params)
        return dict(case=case, t=out.sim_time, steps=out.steps, wall=out.wall, fluid=out.fluid,
                    pressure_rms_mean=out.metrics["rms_mean_second_half"], pressure_rms_end=out.metrics["rms_end"],
                    vmax_over_sqrt_gH=out.metrics["vmax_last_quarter"], outside=out.metrics["particles_outside"])
    sim = taisph.Simulation(dfsph_case(case, **params), **controls)
    steps = StepMaxima()
    compression = []
    start = time.perf_counter()
    summary = sim.run(t_end, frames=20, callback=lambda s: compression.append(mean_compression(s)), writers=[steps])
    ps = summary.pressure_solve
    row = dict(case=case, t=sim.time, steps=summary.steps, wall=time.perf_counter() - start, fluid=sim.n_fluid,
               step_speed_max=steps.speed, compression_max=max(compression),
               density_iterations=ps["density_iterations_mean"], retries=ps["retries"], removed=summary.removed)
    sim.close()
    return row


def table(rows):
    if not rows:
        return ""
    keys = list(rows[0])
    fmt = lambda v: f"{v:.4g}" if isinstance(v, float) else str(v)  # noqa: E731
    return "\n".join(["| " + " | ".join(keys) + " |", "|" + "---|" * len(keys)]
                     + ["| " + " | ".join(fmt(r[k]) for k in keys) + " |" for r in rows])


def main(argv=None):
    p = argparse.ArgumentParser(prog="python -m tools.studies.dfsph_runs", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--only", nargs="+", default=["dam_break", "step_counts", "dam_break_3d", "drop_on_incline",
                                                 "hydrostatic_tank"])
    p.add_argument("--dx", nargs="+", type=float, default=[0.04, 0.02, 0.01, 0.005])
    p.add_argument("--courant", type=float, default=None,
                   help="DFSPH's CFL number C in dt = C h / max |v| (default: the solver's)")
    p.add_argument("--json", default=None, help="write the rows to this file")
    args = p.parse_args(argv)
    controls = {} if args.courant is None else {"courant": args.courant}
    result = {}
    if "dam_break" in args.only:
        result["dam_break"] = [dam_break(dx, **controls) for dx in args.dx]
        print(table(result["dam_break"]), flush=True)
    if "step_counts" in args.only:
        result["step_counts"] = [step_counts(dx, **controls) for dx in args.dx if dx >= 0.01]
        print(table(result["step_counts"]), flush=True)
    others = [("dam_break_3d", 2.0, {}), ("drop_on_incline", None, {}), ("hydrostatic_tank", 10.0, {})]
    rows = []
    for case, t_end, params in others:
        if case in args.only:
            t_end = t_end if t_end is not None else getattr(taisph.cases, case)().t_end
            rows.append(other(case, t_end, controls, **params))
            print(table(rows[-1:]), flush=True)
    result["others"] = rows
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=1)
    return result


if __name__ == "__main__":
    main()
