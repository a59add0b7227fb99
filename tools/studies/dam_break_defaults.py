"""Which physics should the flagship dam break use by default? Accuracy and cost measured.

    python -m tools.studies.dam_break_defaults                       # the model table, dx = 0.02
    python -m tools.studies.dam_break_defaults --courant 0.25 0.4 0.5 --set walls=dummy delta=0.1
    python -m tools.studies.dam_break_defaults --dx 0.01 --models seed best

For each configuration (``--set`` values of the dam_break case and Courant/force
factors of the time step) it runs the 2D dam break to t = 0.7 s and prints:

- pressure noise: the rms over fluid particles, at t = 0.3 s, of p_i minus the mean
  pressure of its neighbours within the kernel support (2.6 dx), over rho g H (H = 2 m):
  a checkerboard pressure field scores high, a smooth one low;
- front: mean |Z - Z_KO| against Koshizuka & Oka (1996) for T = t sqrt(2g/L) <= 3.1
  (taisph.validation.dam_break);
- steps, wall seconds (stepping only) and wall seconds per simulated second;
- whether it ran to the end (a blow-up or a guard is a failed run).
"""

import argparse
import time

import numpy as np

import taisph
from taisph import validation
from taisph.scene.catalogue import parse_setting

MODELS = {  # name: dam_break parameters
    "seed": {},
    "delta": {"delta": 0.1},
    "delta+dummy": {"delta": 0.1, "walls": "dummy"},
    "delta+dummy+friction": {"delta": 0.1, "walls": "dummy", "wall_friction": True},
}


def pressure_noise(sim) -> float:
    """rms over fluid particles of p_i - mean(p_j, |x_i - x_j| < support), over rho g H."""
    p = sim.pressure()
    fluid = sim.fluid
    pairs = sim.neighbour_pairs()
    pairs = pairs[fluid[pairs[:, 0]] & fluid[pairs[:, 1]]]
    total = np.bincount(pairs[:, 0], weights=p[pairs[:, 1]], minlength=len(p))
    count = np.bincount(pairs[:, 0], minlength=len(p))
    has = fluid & (count > 0)
    return float(np.sqrt(np.mean((p[has] - total[has] / count[has]) ** 2)) / (1000.0 * 9.81 * 2.0))


def measure(params: dict, courant: float, force_factor: float, t_noise=0.3, t_end=0.7) -> dict:
    controls = dict(courant=courant, force_factor=force_factor)
    scene = taisph.cases.dam_break(**params)
    sim = taisph.Simulation(scene, **controls)
    start = time.perf_counter()
    row = dict(ok=True)
    try:
        sim.run(t_noise, frames=1)
        row["noise"] = pressure_noise(sim)
        sim.run(t_end, frames=1)
    except taisph.run.simulation.SimulationError as err:
        row.update(ok=False, failure=str(err).splitlines()[0])
    row.update(wall=time.perf_counter() - start, steps=sim.steps, t=sim.time, fluid=sim.n_fluid)
    sim.close()
    if row["ok"]:  # a second run: the validation samples the front at the reference's times
        row["front"] = validation.dam_break(T_end=3.1, controls=controls, **params).error
    return row


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m tools.studies.dam_break_defaults",
                                 description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dx", type=float, default=0.02)
    ap.add_argument("--models", nargs="*", default=list(MODELS), help=f"from {', '.join(MODELS)}")
    ap.add_argument("--set", nargs="*", default=None, metavar="NAME=VALUE",
                    help="one configuration of dam_break parameters instead of --models")
    ap.add_argument("--courant", type=float, nargs="*", default=[0.25])
    ap.add_argument("--force-factor", type=float, nargs="*", default=[0.25])
    args = ap.parse_args(argv)
    configs = ([("set", dict(parse_setting("dam_break", item) for item in args.set))] if args.set is not None
               else [(m, MODELS[m]) for m in args.models])
    print(f"# python -m tools.studies.dam_break_defaults {' '.join(argv or __import__('sys').argv[1:])}")
    print("| model | courant | force factor | fluid | ran to 0.7 s | pressure noise | front mean abs dZ | steps "
          "| wall s | wall s per simulated s |")
    print("|---|---:|---:|---:|---|---:|---:|---:|---:|---:|")
    for name, params in configs:
        params = dict(params, dx=args.dx)
        for c in args.courant:
            for f in args.force_factor:
                r = measure(params, c, f)
                ok = "yes" if r["ok"] else f"no: {r['failure'][:60]}"
                print(f"| {name} {params} | {c:g} | {f:g} | {r['fluid']} | {ok} | {r.get('noise', float('nan')):.3f} | "
                      f"{r.get('front', float('nan')):.3f} | {r['steps']} | {r['wall']:.1f} | "
                      f"{r['wall'] / r['t']:.0f} |", flush=True)


if __name__ == "__main__":
    main()
