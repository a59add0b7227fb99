"""The cylinder benchmark of Schaefer & Turek (1996) at several resolutions: drag, lift and
pressure difference against the references (cases/cylinder.py, docs/validation.md).

    python -m tools.studies.cylinder_study --resolutions 10 20 --t-end 8 --out out/cylinder_study
    python -m tools.studies.cylinder_study --resolutions 20 --re 100 --t-end 12 --average 4 --out out/cylinder_re100
    python -m tools.studies.cylinder_study --resolutions 10 --set c0=9 --set delta=0.05 --label c0x2

One run at a time (in this process). For each resolution D/dx it prints and writes
(OUT/cylinder_study.csv, one row per run, appended) the particles, steps, wall time,
the means over the last `--average` seconds of C_D = 2 F_x / (rho U^2 D),
C_L = 2 F_y / (rho U^2 D) and dp = p_front - p_back (U the mean inflow speed), the
change of C_D between the last two such windows (is it steady?), the recirculation
length behind the cylinder at the end (reference 0.0845 m at Re 20) and the errors
against the Re 20 references; with Re != 20 also the Strouhal number of C_L (St = f D / U,
f the peak of its low-passed spectrum) and max C_D, max C_L over a shedding period
(averaged at equal phase over the window's whole periods). The
probes of each run: OUT/probes_D<N>[_LABEL].csv; C_D(t) of all runs: OUT/cylinder_cd.png (with matplotlib).
"""

from __future__ import annotations

import argparse
import csv
import math
import sys
import time
from pathlib import Path

import numpy as np

import taisph
from taisph.probes import Probes, read_csv
from taisph.scene import catalogue
from taisph.validation.cylinder import REFERENCE_RE100, coefficients, moving_average, window_means

DIAMETER, RHO, NU = 0.1, 1.0, 1e-3
CENTRE = (0.2, 0.2)
REFERENCE = {"C_D": 5.5795, "C_L": 0.0106, "dp": 0.1175, "L_a": 0.0845}  # Re 20 (2D-1)
COLUMNS = ["label", "re", "D_dx", "particles", "steps", "t_end", "stopped", "wall_s", "C_D", "C_L", "dp", "dC_D_window", "L_a",
           "err_C_D", "err_C_L", "err_dp", "err_L_a", "C_D_max", "C_L_max", "St", "extra_inlet_buffer",
           "fluid_in_walls", "mass_change", "settings"]


def recirculation_length(sim, dx: float) -> float:
    """Length of the closed wake behind the cylinder along y = 0.2: from its back point
    x = 0.25 to where the Shepard-interpolated u_x (fluid particles, Wendland weights,
    support 2.6 dx) turns positive (reference 0.0845 m at Re 20); NaN if not negative
    within 2 dx of the back point."""
    x, v, fluid = sim.positions(), sim.velocities(), sim.fluid
    x, v = x[fluid], v[fluid]
    near = (np.abs(x[:, 1] - CENTRE[1]) < 3 * dx) & (x[:, 0] > 0.2) & (x[:, 0] < 0.7)
    x, v = x[near], v[near]
    support = 2.6 * dx
    line = np.arange(0.25 + 0.5 * dx, 0.7, 0.25 * dx)
    u = np.empty(len(line))
    for k, xs in enumerate(line):
        q = np.linalg.norm(x - [xs, CENTRE[1]], axis=1) / support
        w = np.where(q < 1, (1 - q) ** 4 * (1 + 4 * q), 0.0)
        u[k] = (w @ v[:, 0]) / w.sum() if w.sum() > 0 else math.nan
    # the wake begins where u_x is first negative, within 2 dx of the back point (the
    # first sample, half a dx behind a staircase, may read the wall's no-slip layer)
    start = np.flatnonzero((u < 0) & (line < 0.25 + 2 * dx))
    if len(start) == 0:
        return math.nan
    positive = np.flatnonzero((u > 0) & (np.arange(len(u)) > start[0]))
    if len(positive) == 0:
        return math.nan
    k = positive[0]
    return float(line[k - 1] - u[k - 1] * (line[k] - line[k - 1]) / (u[k] - u[k - 1]) - 0.25)


def run_one(n: int, args, settings: dict, out: Path) -> dict:
    """One run at D/dx = n: its row of the table, and its coefficients' time series. A run
    stopped by a guard keeps the samples it took (``stopped``: its time)."""
    from taisph.run.simulation import SimulationError

    dx = DIAMETER / n
    scene = catalogue.find("cylinder")(dx=dx, re=args.re, t_end=args.t_end, **settings)
    suffix = f"_{args.label}" if args.label else ""
    path = out / f"probes_D{n}{suffix}.csv"
    probes = Probes(scene.probes, walls=scene.wall_groups, path=path)
    start = time.perf_counter()
    sim = taisph.Simulation(scene, threads=args.threads)
    inlet0 = int(np.count_nonzero(sim.buffer & (sim.positions()[:, 0] < 0)))
    mass0 = float(sim.masses()[sim.fluid].sum())
    stopped = math.nan
    try:
        sim.run(args.t_end, frames=0, writers=[probes], progress=not args.no_progress)
    except SimulationError as err:
        stopped = sim.time
        print(f"D/dx = {n}: {err}", flush=True)
    wall = time.perf_counter() - start
    steps = sim.steps
    probes.close()
    c = coefficients(read_csv(path), args.re)
    m = window_means(c, args.average)
    m["St"] = m["St"] * DIAMETER / (args.re * NU / DIAMETER)
    la = recirculation_length(sim, dx)
    x = sim.positions()
    health = {  # the open boundaries and walls: does the inlet buffer keep its particles, does fluid leak?
        "extra_inlet_buffer": int(np.count_nonzero(sim.buffer & (x[:, 0] < 0))) - inlet0,
        "fluid_in_walls": int(np.count_nonzero(sim.fluid & ((x[:, 1] < 0) | (x[:, 1] > 0.41)))),
        "mass_change": float(sim.masses()[sim.fluid].sum()) / mass0 - 1.0,
    }
    if args.snapshot:
        snapshot(sim, out / f"cylinder_D{n}{suffix}.png", f"D/dx = {n}{' ' + args.label if args.label else ''}, "
                 f"t = {sim.time:.3g} s")
    particles = sim.n
    sim.close()
    row = {"label": args.label, "re": args.re, "D_dx": n, "particles": particles, "steps": steps,
           "t_end": args.t_end, "stopped": stopped, "wall_s": round(wall, 1), **m, "L_a": la, **health,
           "settings": " ".join(f"{k}={v}" for k, v in settings.items())}
    for key in ("C_D", "C_L", "dp", "L_a"):
        row[f"err_{key}"] = (row[key] - REFERENCE[key]) / REFERENCE[key] if args.re == 20 else math.nan
    return row, c


def print_table(rows):
    print(f"{'D/dx':>5} {'particles':>9} {'steps':>7} {'wall s':>7} {'C_D':>7} {'C_L':>8} {'dp Pa':>7} "
          f"{'dC_D/win':>8} {'L_a m':>7} {'err C_D':>8} {'err C_L':>8} {'err dp':>7} {'err L_a':>7} {'stopped':>7} "
          f"{'+buffer':>7} {'leaked':>6} {'mass':>6}"
          + ("  C_D max  C_L max     St" if rows and rows[0]["re"] != 20 else ""))
    for r in rows:
        line = (f"{r['D_dx']:>5} {r['particles']:>9} {r['steps']:>7} {r['wall_s']:>7.0f} {r['C_D']:>7.4f} "
                f"{r['C_L']:>8.4f} {r['dp']:>7.4f} {r['dC_D_window']:>8.4f} {r['L_a']:>7.4f} {r['err_C_D']:>+8.1%} "
                f"{r['err_C_L']:>+8.0%} {r['err_dp']:>+7.1%} {r['err_L_a']:>+7.1%} {r['stopped']:>7.3g} "
                f"{r['extra_inlet_buffer']:>7} {r['fluid_in_walls']:>6} {r['mass_change']:>+6.1%}")
        if r["re"] != 20:
            line += f"  {r['C_D_max']:7.4f}  {r['C_L_max']:7.4f} {r['St']:6.4f}"
        print(line, flush=True)


def snapshot(sim, path: Path, title: str):
    """The fluid particles coloured by u_x (a PNG; nothing without matplotlib)."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    x, v = sim.positions()[sim.fluid], sim.velocities()[sim.fluid]
    fig, ax = plt.subplots(figsize=(14, 3.2))
    dots = ax.scatter(x[:, 0], x[:, 1], c=v[:, 0], s=0.5, cmap="jet", rasterized=True)
    ax.set_aspect("equal")
    ax.set_title(title)
    fig.colorbar(dots, ax=ax, label="u_x (m/s)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot(series, path: Path, re: float):
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return None
    if re == 20:
        fig, ax = plt.subplots(figsize=(7, 4))
        for label, c in series:
            ax.plot(c["t"], c["C_D"], lw=0.8, label=label)
        ax.axhline(REFERENCE["C_D"], color="k", ls="--", lw=0.8, label="Schäfer & Turek 5.5795")
        ax.set_ylim(0, 2 * REFERENCE["C_D"])
        ax.set_xlabel("t (s)")
        ax.set_ylabel("C_D")
        ax.set_title(f"cylinder, Re = {re:g}")
        ax.legend(fontsize=8)
    else:  # shedding: C_D and C_L, their 0.02 s moving averages (the samples' noise is larger than the swing)
        fig, axes = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
        for label, c in series:
            smooth_t = moving_average(c["t"], c["t"], 0.02)
            for ax, key in zip(axes, ("C_D", "C_L")):
                ax.plot(smooth_t, moving_average(c["t"], c[key], 0.02), lw=0.8, label=f"{label} (0.02 s average)")
        for ax, key in zip(axes, ("C_D_max", "C_L_max")):
            low, high = REFERENCE_RE100[key]
            ax.axhspan(low, high, color="k", alpha=0.3, label=f"Schäfer & Turek max {key[:3]} {low:g}-{high:g}")
            ax.set_ylabel(key[:3])
            ax.legend(fontsize=8, loc="lower left")
        axes[0].set_title(f"cylinder, Re = {re:g}")
        axes[1].set_xlabel("t (s)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--resolutions", type=int, nargs="+", default=[10, 20],
                        help="D/dx of the runs, multiples of 10 (default 10 20)")
    parser.add_argument("--t-end", type=float, default=8.0, help="simulated time of each run (s, default 8)")
    parser.add_argument("--average", type=float, default=3.0,
                        help="the coefficients are means over the last this many seconds (default 3)")
    parser.add_argument("--re", type=float, default=20.0, help="Reynolds number (default 20)")
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                        help="a further case parameter (cases/cylinder.py), e.g. c0=9; repeatable")
    parser.add_argument("--label", default="", help="a label for the rows and file names of this set of runs")
    parser.add_argument("--threads", type=int, default=None, help="CPU threads (default: all)")
    parser.add_argument("--out", type=Path, default=Path("out/cylinder_study"), help="output folder")
    parser.add_argument("--snapshot", action="store_true", help="also plot each run's final particles (PNG)")
    parser.add_argument("--no-progress", action="store_true")
    args = parser.parse_args(argv)
    if any(n < 10 or n % 10 for n in args.resolutions):
        parser.error("--resolutions: D/dx must be a multiple of 10 (dx must divide 0.01 m)")
    settings, _ = catalogue.solver_setting(args.set, None)
    settings = catalogue.case_arguments("cylinder", settings)
    settings = {k: v for k, v in settings.items() if k not in ("dx", "re", "t_end")}
    args.out.mkdir(parents=True, exist_ok=True)
    rows, series = [], []
    for n in args.resolutions:
        row, c = run_one(n, args, settings, args.out)
        rows.append(row)
        series.append((f"D/dx = {n}" + (f" {args.label}" if args.label else ""), c))
        print_table([row])
    print()
    print_table(rows)
    table = args.out / "cylinder_study.csv"
    new = not table.exists()
    with open(table, "a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
        if new:
            w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    print(f"rows appended to {table}")
    png = plot(series, args.out / f"cylinder_cd{'_' + args.label if args.label else ''}.png", args.re)
    if png:
        print(f"C_D(t): {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
