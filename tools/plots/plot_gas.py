"""Profiles of the gas cases against their exact solutions, for docs/gas.md.

    python -m tools.plots.plot_gas                 # docs/sod_profiles.png, docs/sedov_profiles.png
    python -m tools.plots.plot_gas --sod-left 640 --t-sod 0.15 -o /tmp/sod720   # PySPH's set-up
    python -m tools.plots.plot_gas --only sedov --sedov-constant-h -o /tmp/const  # the variants in docs/gas.md

Sod: density, velocity, pressure and internal energy of the tube's particles at t_sod
(default 0.2, 400 particles on the left half) over the exact Riemann solution, with and
without artificial conductivity; the L1 errors (mean over particles) in the legends.
Sedov: the 2D particles coloured by density, and density, radial velocity and pressure
against radius over the Sedov-Taylor similarity profile at t = 0.1 (dx = 0.01).
Prints the numbers it plots.
"""

import argparse
from pathlib import Path

import numpy as np

import taisph
from taisph.cases.sedov import shock_radius
from taisph.cases.sod import compare, tube
from taisph.validation.references.riemann import RiemannProblem
from taisph.validation.references.sedov_taylor import SedovTaylor

DOCS = Path(__file__).resolve().parents[2] / "docs"


def sod_figure(path, left=400, t=0.2):
    import matplotlib.pyplot as plt

    problem = RiemannProblem((1.0, 0.0, 1.0), (0.125, 0.0, 0.1), gamma=1.4)
    runs = {}
    for label, conductivity in (("conductivity", True), ("no conductivity", False)):
        sim = taisph.Simulation(taisph.cases.sod(dx=0.5 / left, conductivity=conductivity))
        sim.run(t, frames=1)
        runs[label] = (tube(sim), compare(tube(sim), problem, t))
        print(f"sod {left} left particles, t = {t}, {label}: "
              + ", ".join(f"{k} {v:.5f}" for k, v in runs[label][1].items()))
    x = np.linspace(0.0, 1.0, 4001)
    exact = dict(zip(("rho", "u", "p", "e"), problem.sample(x, t, 0.5)))
    fig, axes = plt.subplots(2, 2, figsize=(11, 7.5), sharex=True)
    names = {"rho": "density", "u": "velocity", "p": "pressure", "e": "internal energy"}
    for ax, q in zip(axes.flat, ("rho", "u", "p", "e")):
        ax.plot(x, exact[q], "k-", lw=1.2, label="exact (Riemann)")
        for (label, (state, err)), style in zip(runs.items(), (dict(ms=3, color="C0"), dict(ms=2, color="C3"))):
            ax.plot(state["x"], state[q], ".", label=f"{label}: L1 {err['L1_' + q]:.4f}", **style)
        ax.set_ylabel(names[q])
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    for ax in axes[1]:
        ax.set_xlabel("x")
    n = len(next(iter(runs.values()))[0]["x"])
    fig.suptitle(f"Sod shock tube, t = {t:g}: {n} particles in the tube (equal mass, {left} on the left)")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def sedov_figure(path, dx=0.01, t=0.1, **params):
    import matplotlib.pyplot as plt

    st = SedovTaylor(1.4, nu=2)
    sim = taisph.Simulation(taisph.cases.sedov(dx=dx, **params))
    sim.run(t, frames=1)
    pos = sim.positions()
    r = np.linalg.norm(pos, axis=1)
    rho, p = sim.density(), sim.pressure()
    vr = (sim.velocities() * pos).sum(axis=1) / np.maximum(r, 1e-12)
    radius, exact_radius = shock_radius(sim), float(st.radius(t))
    me = sim.masses() * sim.quantity("energy")
    inner = float(me[r < exact_radius / 4].sum())
    print(f"sedov dx {dx} {params or ''}, {sim.n} particles, t = {t}: R {radius:.4f}, exact {exact_radius:.4f} "
          f"({radius / exact_radius - 1:+.4f}); peak density {rho.max():.3f} (exact {2.4 / 0.4:.1f}); "
          f"internal energy within R/4: {inner:.3f}; min rho {rho.min():.4f}, "
          f"min e {sim.quantity('energy').min():.3g}; steps {sim.steps}")
    rr = np.linspace(1e-4, 0.5, 2000)
    e_rho, e_u, e_p = st.sample(rr, t)
    fig, axes = plt.subplots(1, 4, figsize=(17, 4.2))
    sc = axes[0].scatter(pos[:, 0], pos[:, 1], c=rho, s=1.5, cmap="viridis")
    axes[0].add_patch(plt.Circle((0, 0), exact_radius, fill=False, color="r", lw=0.8))
    axes[0].set_aspect("equal")
    axes[0].set_title(f"density, t = {t:g} (red: exact shock)")
    fig.colorbar(sc, ax=axes[0], shrink=0.8)
    for ax, q, e, name in ((axes[1], rho, e_rho, "density"), (axes[2], vr, e_u, "radial velocity"),
                           (axes[3], p, e_p, "pressure")):
        ax.plot(r, q, ".", ms=1, color="C0", label="SPH particles")
        ax.plot(rr, e, "k-", lw=1.2, label="Sedov-Taylor")
        ax.axvline(radius, color="C3", lw=0.8, ls="--", label=f"measured R = {radius:.3f}")
        ax.set_xlim(0, 0.5)
        ax.set_xlabel("r")
        ax.set_title(name)
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    fig.suptitle(f"2D Sedov blast, E = 1, rho = 1, gamma = 1.4, {sim.n} particles (dx = {dx:g}), "
                 + ("constant h" if params.get("variable_h") is False else "variable h")
                 + (", conductivity" if params.get("conductivity") else ""))
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(argv=None):
    import matplotlib

    matplotlib.use("Agg")
    p = argparse.ArgumentParser(prog="python -m tools.plots.plot_gas",
                                description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--sod-left", type=int, default=400)
    p.add_argument("--t-sod", type=float, default=0.2)
    p.add_argument("--sedov-dx", type=float, default=0.01)
    p.add_argument("--sedov-conductivity", action="store_true", help="Sedov with artificial conductivity")
    p.add_argument("--sedov-constant-h", action="store_true", help="Sedov with a constant smoothing length")
    p.add_argument("--only", choices=["sod", "sedov"])
    p.add_argument("-o", "--out", type=Path, help="output prefix (default docs/)")
    args = p.parse_args(argv)
    prefix = str(args.out) + "_" if args.out else str(DOCS) + "/"
    if args.only != "sedov":
        sod_figure(prefix + "sod_profiles.png", args.sod_left, args.t_sod)
    if args.only != "sod":
        params = {}
        if args.sedov_conductivity:
            params["conductivity"] = True
        if args.sedov_constant_h:
            params["variable_h"] = False
        sedov_figure(prefix + "sedov_profiles.png", args.sedov_dx, **params)


if __name__ == "__main__":
    main()
