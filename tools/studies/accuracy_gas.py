"""Accuracy study of the gas cases: error against the exact solution as a function of
simulated time, resolution and artificial conductivity, and against wall time.

    python -m tools.studies.accuracy_gas            # docs/accuracy_gas.{csv,md}, docs/accuracy_gas_*.png
    python -m tools.studies.accuracy_gas --quick    # two resolutions, one repeat, to /tmp (a smoke run)
    python -m tools.studies.accuracy_gas --choices  # docs/gas_choices.md: one Sod run per set-up choice

Sod shock tube (cases/sod.py, Toro test 1, to t = 0.2): error = L1 of the density, the
mean over the tube's particles of |rho - rho_exact(x)| against taisph.validation.references.riemann (u, p, e
in more columns). Sedov blast (cases/sedov.py, 2D, to t = 0.1): error = |R / R_exact - 1|,
R the radius where the ring-averaged density falls half way from its peak to rho0,
against taisph.validation.references.sedov_taylor.

Each configuration runs ``repeat`` times, with and without conductivity alternating;
wall times are medians (the machine is shared and its timings vary up to 2x) and
exclude kernel compilation and the error evaluation.
:func:`rows` returns the data as a list of dicts - case, config, resolution, particles,
t, error, the other metrics, wall_time, steps, particle_steps_per_s - one per sampled
time, with wall time and steps counted from t = 0, for the main accuracy study to collect.
"""

from __future__ import annotations

import argparse
import csv
import statistics
import sys
import time
from pathlib import Path

import numpy as np

import taisph
from taisph.cases.sedov import shock_radius
from taisph.cases.sod import compare, tube
from taisph.validation.references.riemann import RiemannProblem
from taisph.validation.references.sedov_taylor import SedovTaylor

DOCS = Path(__file__).resolve().parents[2] / "docs"
SOD_LEFT = (100, 200, 400, 800)  # particles on the left half of the tube, dx = 0.5 / n
SOD_TIMES = (0.05, 0.1, 0.15, 0.2)
SEDOV_DX = (0.04, 0.02)
SEDOV_TIMES = (0.025, 0.05, 0.075, 0.1)
CONFIGS = {"conductivity": True, "no conductivity": False}
SOD_PROBLEM = RiemannProblem((1.0, 0.0, 1.0), (0.125, 0.0, 0.1), gamma=1.4)


def _timed_run(scene, times, measure):
    """Run `scene` through `times`, calling measure(sim) at each. Returns a list of
    (measurement, wall seconds since t = 0 without the measuring, steps)."""
    sim = taisph.Simulation(scene)  # compiles: not timed
    out, wall = [], 0.0
    for t in times:
        start = time.perf_counter()
        sim.run(t, frames=1)
        wall += time.perf_counter() - start
        out.append((measure(sim), wall, sim.steps))
    sim.close()
    return out


def _collect(case, resolutions, make_scene, times, measure, error_key, repeat):
    """Rows of every (config, resolution): the configurations alternate within each
    repeat, so a change of the machine's load hits both alike."""
    runs, particles = {}, {}
    for resolution in resolutions:
        for _ in range(repeat):
            for config, conductivity in CONFIGS.items():
                scene = make_scene(resolution, conductivity)
                particles[config, resolution] = scene.n
                runs.setdefault((config, resolution), []).append(_timed_run(scene, times, measure))
    rows = []
    for (config, resolution), results in runs.items():
        for k, t in enumerate(times):
            metrics, _, steps = results[0][k]  # the runs are deterministic: same metrics and steps
            wall = statistics.median(run[k][1] for run in results)
            n = particles[config, resolution]
            rows.append(dict(case=case, config=config, resolution=resolution, particles=n, t=t,
                             error=metrics[error_key], **metrics, wall_time=wall, steps=steps,
                             particle_steps_per_s=n * steps / wall))
    return sorted(rows, key=lambda r: (list(CONFIGS).index(r["config"]), r["resolution"], r["t"]))


def sod_rows(left=SOD_LEFT, times=SOD_TIMES, repeat=3) -> list:
    """Sod tube: resolution = particles on the left half (the tube holds 9/8 of that,
    the simulation twice as many with the mirror image)."""
    keys = ("L1_rho", "L1_u", "L1_p", "L1_e", "L1x_rho", "L1x_u", "L1x_p", "L1x_e", "p_star", "u_star")

    def measure(sim):
        r = compare(tube(sim), SOD_PROBLEM, sim.time)
        return {k: r[k] for k in keys}

    return _collect("sod", left, lambda n, c: taisph.cases.sod(dx=0.5 / n, conductivity=c), times, measure,
                    "L1_rho", repeat)


def sedov_rows(dxs=SEDOV_DX, times=SEDOV_TIMES, repeat=3) -> list:
    """Sedov blast: resolution = particles across the box (1 / dx)."""
    st = SedovTaylor(1.4, nu=2)

    def measure(sim):
        radius = shock_radius(sim)
        exact = float(st.radius(sim.time))
        return {"radius": radius, "radius_exact": exact, "radius_error": abs(radius / exact - 1.0),
                "radius_error_h": (radius - exact) / (1.3 * sim.scene.dx)}

    return _collect("sedov", [int(round(1.0 / dx)) for dx in dxs],
                    lambda n, c: taisph.cases.sedov(dx=1.0 / n, conductivity=c), times, measure,
                    "radius_error", repeat)


def rows(quick: bool = False, repeat: int = 3) -> list:
    """All rows of the gas study (quick: two resolutions per case)."""
    return (sod_rows(SOD_LEFT[:2] if quick else SOD_LEFT, repeat=repeat)
            + sedov_rows(SEDOV_DX[:1] if quick else SEDOV_DX, repeat=repeat))


# --- the Sod set-up's choices ------------------------------------------------------------
CHOICES = [  # (label, sod() parameters, t_end)
    ("default: equal mass, summation, h = 1.0 m/rho, conductivity", dict(dx=0.5 / 400), 0.2),
    ("  same, 800 left", dict(dx=0.5 / 800), 0.2),
    ("h = 1.2 m/rho", dict(dx=0.5 / 400, h_factor=1.2), 0.2),
    ("h = 1.2 m/rho, 800 left", dict(dx=0.5 / 800, h_factor=1.2), 0.2),
    ("h = 2.0 m/rho", dict(dx=0.5 / 400, h_factor=2.0), 0.2),
    ("Gaussian kernel, h = 1.2 m/rho", dict(dx=0.5 / 400, kernel="gaussian", h_factor=1.2), 0.2),
    ("continuity density", dict(dx=0.5 / 400, density="continuity"), 0.2),
    ("no conductivity", dict(dx=0.5 / 400, conductivity=False), 0.2),
    ("equal spacing (mass ratio 8), constant h = 1.2 dx", dict(dx=0.5 / 400, spacing="equal_spacing",
                                                              variable_h=False, h_factor=1.2), 0.2),
    ("dt halved (courant 0.1)", dict(dx=0.5 / 400, courant=0.1), 0.2),
    ("PySPH's set-up: 640 + 80 particles, t = 0.15", dict(dx=0.5 / 640), 0.15),
]


def choices_table(command) -> str:
    """One Sod run per set-up choice (CHOICES): the errors behind the case's defaults;
    then the 1D lattice sums that explain the choice of h (:func:`lattice_table`)."""
    lines = [f"Made by `{command}`.", "",
             "| set-up | tube particles | L1 rho | L1 u | L1 p | L1 e | L1x rho | L1x u | L1x p | p* | u* "
             "| shock - exact (h) | contact blip | min e |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for label, params, t_end in CHOICES:
        sim = taisph.Simulation(taisph.cases.sod(**params))
        sim.run(t_end, frames=1)
        state = tube(sim)
        r = compare(state, SOD_PROBLEM, t_end)
        near = np.abs(state["x"] - (0.5 + SOD_PROBLEM.u_star * t_end)) < 0.03
        blip = np.abs(state["p"][near] - SOD_PROBLEM.p_star).max()
        lines.append(f"| {label} | {len(state['x'])} | {r['L1_rho']:.5f} | {r['L1_u']:.5f} | {r['L1_p']:.5f} | "
                     f"{r['L1_e']:.5f} | {r['L1x_rho']:.5f} | {r['L1x_u']:.5f} | {r['L1x_p']:.5f} | "
                     f"{r['p_star']:.4f} | {r['u_star']:.4f} | "
                     f"{(r['shock'] - r['shock_exact']) / r['h_shock']:+.2f} | {blip:.4f} | {r['e_min']:.4f} |")
        sim.close()
    lines += ["", "L1: mean over the tube's particles; L1x: integral over x. Contact blip: max |p - p*| "
              "within 0.03 of the contact. Shock: where rho falls through (rho*_R + rho_R)/2, in units of "
              "the smoothing length behind it.", "", lattice_table()]
    return "\n".join(lines)


def lattice_table(etas=(1.0, 1.1, 1.2, 1.3, 1.5, 2.0)) -> str:
    """1D uniform lattice, spacing dx = 1, h = eta: the density sum dx sum_k W(k dx) - 1
    and the pressure force across a plane, 2 dx^2 sum_(k>=1) k |dW/dx(k dx)| - 1 (the
    momentum flux of a uniform pressure P through a plane between particles is
    P (1 + that); both are 0 for the continuous integral). Kernels evaluated by the
    solver's own Taichi functions (smoothing.evaluate)."""
    from taisph.engine import smoothing

    lines = ["1D lattice sums (relative errors of the density sum / of the pressure force across a plane):", "",
             "| kernel | " + " | ".join(f"h = {eta:g} dx" for eta in etas) + " |",
             "|---|" + "---:|" * len(etas)]
    for name in smoothing.KERNELS:
        cells = []
        for eta in etas:
            k = np.arange(-40, 41, dtype=float)
            w, grad = smoothing.evaluate(name, 1, k[:, None], eta)
            flux = 2.0 * np.sum(k[k > 0] * np.abs(grad[k > 0, 0]))
            cells.append(f"{w.sum() - 1:+.5f} / {flux - 1:+.5f}")
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


# --- output -----------------------------------------------------------------------------
def write_csv(data, path):
    fields = list(dict.fromkeys(k for row in data for k in row))
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        w.writerows(data)


def markdown(data, command) -> str:
    final = [r for r in data if r["t"] == max(q["t"] for q in data if q["case"] == r["case"])]
    lines = [f"Made by `{command}`; wall times are medians, compilation excluded.", ""]
    sod = [r for r in final if r["case"] == "sod"]
    if sod:
        lines += ["**Sod shock tube, t = 0.2** (L1 = mean over the tube's particles of |q - q_exact|)", "",
                  "| config | left particles | simulated | L1 rho | L1 u | L1 p | L1 e | p* | u* | steps | wall s "
                  "| M particle-steps/s |", "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
        for r in sod:
            lines.append(f"| {r['config']} | {r['resolution']} | {r['particles']} | {r['L1_rho']:.5f} | "
                         f"{r['L1_u']:.5f} | {r['L1_p']:.5f} | {r['L1_e']:.5f} | {r['p_star']:.5f} | "
                         f"{r['u_star']:.5f} | {r['steps']} | {r['wall_time']:.2f} | "
                         f"{r['particle_steps_per_s'] / 1e6:.2f} |")
        lines += ["", "Exact: p* = 0.30313, u* = 0.92745.", ""]
    sedov = [r for r in final if r["case"] == "sedov"]
    if sedov:
        lines += ["**Sedov blast, 2D, t = 0.1** (R_exact = 1.004 (E t^2/rho)^(1/4) = "
                  f"{sedov[0]['radius_exact']:.4f})", "",
                  "| config | particles across | particles | R | R/R_exact - 1 | (R - R_exact)/h0 | steps | wall s "
                  "| M particle-steps/s |", "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
        for r in sedov:
            lines.append(f"| {r['config']} | {r['resolution']} | {r['particles']} | {r['radius']:.4f} | "
                         f"{r['radius'] / r['radius_exact'] - 1:+.4f} | {r['radius_error_h']:+.2f} | {r['steps']} | "
                         f"{r['wall_time']:.2f} | {r['particle_steps_per_s'] / 1e6:.2f} |")
        lines += ["", "h0 = 1.3 dx, the initial smoothing length.", ""]
    return "\n".join(lines)


def plots(data, prefix: Path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullFormatter

    styles = {"conductivity": "-", "no conductivity": "--"}
    panels = [(case, key, label) for case, key, label in (
        ("sod", "L1_rho", "Sod: L1 error of density"), ("sod", "L1_p", "Sod: L1 error of pressure"),
        ("sedov", "radius_error", "Sedov: |R / R_exact - 1|")) if any(r["case"] == case for r in data)]

    def select(case, config, **match):
        return [r for r in data if r["case"] == case and r["config"] == config
                and all(r[k] == v for k, v in match.items())]

    # work-precision: error at the end time against wall time
    fig, axes = plt.subplots(1, len(panels), figsize=(5 * len(panels), 4.2), squeeze=False)
    for ax, (case, key, label) in zip(axes[0], panels):
        end = max(r["t"] for r in data if r["case"] == case)
        for config, style in styles.items():
            pts = sorted((r["wall_time"], r[key], r["resolution"]) for r in select(case, config, t=end))
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o" + style, label=config)
            for w, e, n in pts:
                ax.annotate(str(n), (w, e), textcoords="offset points", xytext=(4, 4), fontsize=8)
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.set_xlabel("wall time (s, median)")
        ax.set_ylabel(label)
        ax.set_title(f"{case}, t = {end:g} (labels: resolution)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.tight_layout()
    fig.savefig(f"{prefix}_work_precision.png", dpi=100)
    plt.close(fig)
    # error against simulated time, per resolution
    fig, axes = plt.subplots(1, len(panels), figsize=(5 * len(panels), 4.2), squeeze=False)
    for ax, (case, key, label) in zip(axes[0], panels):
        resolutions = sorted({r["resolution"] for r in data if r["case"] == case})
        colours = plt.cm.viridis(np.linspace(0, 0.85, len(resolutions)))
        for colour, n in zip(colours, resolutions):
            for config, style in styles.items():
                pts = sorted((r["t"], r[key]) for r in select(case, config, resolution=n))
                ax.semilogy([p[0] for p in pts], [p[1] for p in pts], "o" + style, color=colour,
                            label=f"{n}, {config}")
        ax.set_xlabel("simulated time")
        ax.set_ylabel(label)
        ax.set_title(f"{case}: by resolution (dashed: no conductivity)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(f"{prefix}_error_vs_time.png", dpi=100)
    plt.close(fig)


def main(argv=None):
    p = argparse.ArgumentParser(prog="python -m tools.studies.accuracy_gas",
                                description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--quick", action="store_true", help="two resolutions per case, one repeat, output to /tmp")
    p.add_argument("--repeat", type=int, default=3, help="runs per configuration (median wall time)")
    p.add_argument("--out", type=Path, help="output prefix (default docs/accuracy_gas)")
    p.add_argument("--choices", action="store_true",
                   help="instead: one Sod run per set-up choice, table to docs/gas_choices.md")
    args = p.parse_args(argv)
    if args.choices:
        table = choices_table("python -m tools.studies.accuracy_gas --choices")
        path = args.out or DOCS / "gas_choices.md"
        Path(path).write_text(table + "\n")
        print(table)
        return
    repeat = 1 if args.quick else args.repeat
    prefix = args.out or (Path("/tmp/accuracy_gas") if args.quick else DOCS / "accuracy_gas")
    command = "python -m tools.studies.accuracy_gas " + " ".join(argv if argv is not None else sys.argv[1:])
    data = rows(quick=args.quick, repeat=repeat)
    prefix.parent.mkdir(parents=True, exist_ok=True)
    write_csv(data, f"{prefix}.csv")
    table = markdown(data, command.strip())
    Path(f"{prefix}.md").write_text(table + "\n")
    plots(data, prefix)
    print(table)
    print(f"wrote {prefix}.csv, {prefix}.md, {prefix}_work_precision.png, {prefix}_error_vs_time.png")


if __name__ == "__main__":
    main()
