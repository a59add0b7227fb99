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
    python -m tools.studies.wall_pressure --dx 0.01 --only file c0x2

Prints a markdown table (figures in rho g H, time in t sqrt(g/H)).
"""

from __future__ import annotations

import argparse
import math

from taisph.validation import buchner

U = math.sqrt(2 * buchner.G * buchner.H)  # the cases' reference speed: c0 = 10 U

# name -> (scene-file overrides, simulation controls, what changes)
VARIANTS = {
    "file": ({}, {}, "the file: WCSPH, Wendland h = 2 dx, c0 = 10 U, alpha 0.02, delta 0.1, Courant 0.125"),
    "c0x2": ({"materials[0].c0": 20 * U}, {}, "c0 = 20 U (acoustic: a stiffer fluid, 2x the steps)"),
    "delta0": ({"physics.delta": 0.0}, {}, "no density diffusion"),
    "delta0.2": ({"physics.delta": 0.2}, {}, "density diffusion delta = 0.2"),
    "alpha0.1": ({"physics.alpha": 0.1}, {}, "artificial viscosity alpha = 0.1"),
    "courant/2": ({}, {"courant": 0.0625}, "Courant 0.0625 (the time step halved)"),
    "dfsph": ({"solver": "dfsph"}, {"courant": 0.5}, "DFSPH (incompressible), CFL 0.5"),
    "riemann": ({"physics.formulation": "riemann", "physics.alpha": 0.0, "physics.delta": 0.0}, {},
                "Riemann formulation (Zhang, Hu & Adams 2017), no alpha, no delta"),
}
PROBES = ("P1", "P1_point", "P2")


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
    cells += [str(row["steps"]), f"{row['wall_s']:.0f}", row["stopped"] or ""]
    return "| " + " | ".join(cells) + " |"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--dx", type=float, default=0.02)
    parser.add_argument("--only", nargs="+", choices=sorted(VARIANTS), default=list(VARIANTS))
    args = parser.parse_args(argv)
    head = ["variant"] + [f"{p} {m}" for p in PROBES for m in ("MAE", "noise", "peak / exp.")] + ["steps", "wall s", "stopped"]
    print(f"dx = {args.dx:g} m (H/dx = {buchner.H / args.dx:.0f})")
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    measure(args.dx, args.only)
    for name in args.only:
        print(f"- {name}: {VARIANTS[name][2]}")


if __name__ == "__main__":
    main()
