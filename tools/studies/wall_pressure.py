"""What sets the wall pressure of the 2D dam break (issue 26, "the cause, shown"): the
Buchner (2002) comparison (:mod:`taisph.validation.buchner`, the scene file
``cases/dam_break_probes_2d.toml``) run with one setting changed at a time, each
against the file's own settings, in one process.

For each variant and probe: the mean absolute error against the experiment over T 2-6,
the probe noise (rms of the probe minus its 0.02-T moving average after the impact:
acoustic ringing and particle noise), the first peak of that moving average against the
experiment's, and the wall time. P1 is the sensor averaged over a 0.09 m face shifted
down (after Adami et al. 2012 and Greco), P1_point the pressure at the sensor's middle.

    python -m tools.studies.wall_pressure --dx 0.02
    python -m tools.studies.wall_pressure --dx 0.01 --only symmetric c0x2
    python -m tools.studies.wall_pressure --sensors --dx 0.005 --only symmetric dfsph riemann file

``--sensors`` runs ``wall_pressure_sensors_2d.toml`` (beside this script: the geometry of
Lobovsky et al. 2014, sensors at 1, 5, 10 and 27 % of H on the downstream wall) instead,
and prints each sensor's first peak (0.02-T moving average; raw), its time and the noise,
against the experiment's median peaks quoted in issue 26 (its series are not here).

Prints a markdown table (figures in rho g H, time in t sqrt(g/H)).
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np

from taisph.formats.scenefile import load
from taisph.probes import Probes
from taisph.run.simulation import Simulation
from taisph.validation import buchner

U = math.sqrt(2 * buchner.G * buchner.H)  # the cases' reference speed: c0 = 10 U

DEFAULTS = {"kernel": "spline", "h_factor": 1.3, "physics.alpha": 0.1, "physics.delta": 0.1}
# The causes are measured on the symmetric form (seed eqs. 7-8), the file's before issue 26 made the
# Riemann formulation the scene files' default: each of those variants names it, so that its table
# in docs/validation.md stays reproducible.
SYMMETRIC = {"physics.formulation": "symmetric"}
# name -> (scene-file overrides, simulation controls, what changes)
VARIANTS = {
    "symmetric": (SYMMETRIC, {}, "the file with the symmetric form: WCSPH, Wendland h = 2 dx, c0 = 10 U, alpha 0.02, "
                                 "delta 0.1, Courant 0.125"),
    "c0x2": ({**SYMMETRIC, "materials[0].c0": 20 * U}, {}, "c0 = 20 U (acoustic: a stiffer fluid, 2x the steps)"),
    "delta0": ({**SYMMETRIC, "physics.delta": 0.0}, {}, "no density diffusion"),
    "delta0.2": ({**SYMMETRIC, "physics.delta": 0.2}, {}, "density diffusion delta = 0.2"),
    "alpha0.1": ({**SYMMETRIC, "physics.alpha": 0.1}, {}, "artificial viscosity alpha = 0.1"),
    "courant/2": (SYMMETRIC, {"courant": 0.0625}, "Courant 0.0625 (the time step halved)"),
    "dfsph": ({"solver": "dfsph"}, {"courant": 0.5}, "DFSPH (incompressible), CFL 0.5"),
    "riemann": ({"physics.formulation": "riemann", "physics.alpha": 0.0, "physics.delta": 0.0}, {},
                "Riemann formulation (Zhang, Hu & Adams 2017), no alpha, no delta"),
    "file": ({}, {}, "the file as shipped: the Riemann formulation with its alpha 0.02 and delta 0.1"),
    # the scene files' and cases' defaults instead of the file's tuned settings
    "defaults": ({**DEFAULTS, **SYMMETRIC}, {"courant": 0.25},
                 "the defaults with the symmetric form: spline, h = 1.3 dx, alpha 0.1, delta 0.1, Courant 0.25"),
    "defaults+riemann": ({**DEFAULTS, "physics.formulation": "riemann", "physics.alpha": 0.0, "physics.delta": 0.0},
                         {"courant": 0.25}, "the defaults with the Riemann formulation (the scene files' defaults)"),
    "defaults+dfsph": ({**DEFAULTS, "solver": "dfsph"}, {"courant": 0.5}, "the defaults under DFSPH (CFL 0.5)"),
    # delta-plus-SPH (Sun et al. 2017): delta-SPH with particle shifting kept off the free surface, U = sqrt(2 g H);
    # the symmetric form only (shifting is refused with the Riemann formulation: particle_shifting.py)
    "delta+": ({**SYMMETRIC, "physics.shifting": U}, {}, "delta+-SPH: the symmetric form, delta 0.1, shifting with U"),
    "defaults+shifting": ({**DEFAULTS, **SYMMETRIC, "physics.shifting": U}, {"courant": 0.25},
                          "the defaults with the symmetric form and particle shifting (U): delta+-SPH"),
}
PROBES = ("P1", "P1_point", "P2")
SENSORS_FILE = Path(__file__).with_name("wall_pressure_sensors_2d.toml")
SENSORS_H = 0.3
# the experiment's median first peaks (0.02-T moving average, rho g H) and their T, as issue 26 quotes them
SENSORS = {"S1": (2.60, 2.464), "S2": (1.87, 2.595), "S3": (1.45, 2.762), "S4": (0.51, 3.20)}


def sensors(dx: float, names) -> None:
    """First peaks at the four sensors of the Lobovsky geometry, for each variant."""
    scale = math.sqrt(buchner.G / SENSORS_H)
    print("| variant | " + " | ".join(f"{s} peak (raw) @ T, noise" for s in SENSORS) + " | steps | wall s |")
    print("|" + "---|" * (len(SENSORS) + 3))
    for name in names:
        overrides, controls, _ = VARIANTS[name]
        scene, settings = load(SENSORS_FILE, {"dx": dx, **overrides})
        if settings.courant is not None:
            controls = {"courant": settings.courant, **controls}
        sim = Simulation(scene, **controls)
        probes = Probes(settings.probes, walls=settings.wall_groups, path=None)
        start = time.perf_counter()
        sim.run(7.1 / scale, frames=1, writers=[probes])
        wall = time.perf_counter() - start
        cells = [name]
        for s, (peak_exp, t_exp) in SENSORS.items():
            t, p = probes.series(s)
            T, P = t * scale, np.nan_to_num(p / (buchner.RHO0 * buchner.G * SENSORS_H))
            avg = buchner.moving_average(T, P)
            wet = np.flatnonzero(avg > 0.2)
            first = (T >= T[wet[0]]) & (T <= T[wet[0]] + 0.6) if len(wet) else np.zeros_like(T, bool)
            k = int(np.argmax(np.where(first, avg, -1.0)))
            after = (T >= 2.0) & (T <= T[-1] - buchner.NOISE_WIDTH / 2)
            noise = float(np.sqrt(np.mean((P[after] - avg[after]) ** 2)))
            cells.append(f"{avg[k]:.2f} ({P[first].max():.2f}) @ {T[k]:.3f} / {peak_exp:.2f} @ {t_exp:.3f}, {noise:.3f}")
        probes.close()
        sim.close()
        print("| " + " | ".join(cells) + f" | {sim.steps} | {wall:.0f} |", flush=True)


def measure(dx: float, names) -> list[dict]:
    rows = []
    for name in names:
        overrides, controls, what = VARIANTS[name]
        out = buchner.run(dx=dx, overrides=overrides, **controls)
        row = dict(variant=name, what=what, wall_s=out["wall_s"], steps=out["steps"], stopped=out["stopped"])
        for probe in PROBES:
            m = out.get(probe)
            if m:
                row[probe] = m
        rows.append(row)
        print(_line(row), flush=True)
    return rows


def _line(row) -> str:
    cells = [row["variant"]]
    for probe in PROBES:
        m = row.get(probe)
        cells += [f"{m['mae']:.3f}", f"{m['noise']:.3f}", f"{m['peak']:.2f} / {m['peak_ref']:.2f}"] if m else ["-"] * 3
    m = row.get("P1")
    cells += [f"{m['impact_error']:+.1%}" if m else "-", str(row["steps"]), f"{row['wall_s']:.0f}", row["stopped"] or ""]
    return "| " + " | ".join(cells) + " |"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--dx", type=float, default=0.02)
    parser.add_argument("--only", nargs="+", choices=sorted(VARIANTS), default=list(VARIANTS))
    parser.add_argument("--sensors", action="store_true", help="the Lobovsky geometry's four wall sensors instead")
    args = parser.parse_args(argv)
    if args.sensors:
        print(f"dx = {args.dx:g} m (H/dx = {SENSORS_H / args.dx:.0f}); peak / experiment's median peak, rho g H")
        return sensors(args.dx, args.only)
    head = (["variant"] + [f"{p} {m}" for p in PROBES for m in ("MAE", "noise", "peak / exp.")]
            + ["P1 impact", "steps", "wall s", "stopped"])
    print(f"dx = {args.dx:g} m (H/dx = {buchner.H / args.dx:.0f})")
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    measure(args.dx, args.only)
    for name in args.only:
        print(f"- {name}: {VARIANTS[name][2]}")


if __name__ == "__main__":
    main()
