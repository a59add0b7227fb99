"""The dam break's surge front at a fine resolution: the reference of the work-precision
study's case "dam_break_front" (taisph/validation/runs.py, FINE_FRONT; docs/accuracy.md).

    python -m tools.studies.dam_break_reference                      # dx = 0.005 (the shipped file)
    python -m tools.studies.dam_break_reference --dx 0.01 --out /tmp/front_0.01.csv

Runs the dam_break case with its defaults (cases/dam_break.py: dummy walls with wall
friction, delta 0.1, alpha 0.1, cubic spline h = 1.3 dx, Courant 0.4) to
T = t sqrt(2 g / L) = 3.1 and writes the front Z = x_front / L (the largest fluid x plus
dx/2, over the column width L) at `--samples` even times and at the experiments' times,
with a header naming the command, the configuration, the commit, the date and the cost.
The experiments' front is slower than the inviscid model converges to (docs/accuracy.md),
so against them the error grows with resolution; against this it falls.
"""

import argparse
import datetime
import platform
import sys
from pathlib import Path

from taisph import validation
from taisph.validation.accuracy_cost import git_commit
from taisph.validation.runs import DATA, FINE_FRONT


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--dx", type=float, default=0.005, help="particle spacing (m, default 0.005)")
    p.add_argument("--samples", type=int, default=125, help="even times over T 0..3.1 (default 125)")
    p.add_argument("--out", type=Path, default=DATA / FINE_FRONT, help="CSV to write (default: the shipped reference)")
    a = p.parse_args(argv)
    out = validation.run("dam_break", dx=a.dx, T_end=3.1, samples=a.samples)
    if out.diverged:
        sys.exit(f"the run diverged at t = {out.sim_time:g} s: no reference written")
    command = "python -m tools.studies.dam_break_reference" + "".join(f" {x}" for x in (argv or sys.argv[1:]))
    header = [
        f"The dam break's surge front computed by taisph at dx = {a.dx:g} m: the reference of the work-precision",
        "study's case dam_break_front (a fine-resolution solution of the same model, not an experiment).",
        "Case: taisph.cases.dam_break with its defaults (1 m x 2 m column in a 4 m tank, dummy walls with wall",
        "friction, delta-SPH 0.1, Monaghan alpha 0.1, cubic spline h = 1.3 dx, Tait c0 = 10 sqrt(2 g H),",
        "predictor-corrector, adaptive step with Courant 0.4).",
        f"Made by: {command}",
        f"Commit {git_commit()}, {datetime.date.today().isoformat()}, {platform.machine()} {platform.system()}: "
        f"{out.fluid} fluid particles, {out.steps} steps, {out.wall:.0f} s stepping.",
        f"Front against Koshizuka & Oka (1996): mean |dZ| {out.metrics['ko_mean_abs']:.4f}.",
        "Columns: T = t sqrt(2 g / L) [-], Z = x_front / L [-] (x_front the largest fluid x plus dx/2).",
    ]
    rows = [f"{T:.6f},{Z:.6f}" for T, Z in zip(out.series["T"], out.series["Z"])]
    a.out.parent.mkdir(parents=True, exist_ok=True)
    tmp = a.out.with_suffix(".tmp")
    tmp.write_text("\n".join("# " + line for line in header) + "\nT_sqrt2g_over_L,Z_x_over_L\n" + "\n".join(rows) + "\n")
    tmp.replace(a.out)  # nothing half-written
    print(f"{a.out}: {len(rows)} points; {out.fluid} fluid particles, {out.steps} steps, {out.wall:.0f} s stepping; "
          f"mean |Z - Z_KO| {out.metrics['ko_mean_abs']:.4f}")


if __name__ == "__main__":
    main()
