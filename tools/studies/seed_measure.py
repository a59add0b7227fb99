"""Print the measured quantities of the seed's three scenes that tests/test_seed_cases.py
asserts and docs/seed.md quotes, at the tests' resolutions (both take them from
taisph/validation/seed_scenes.py), and the largest difference between running a case and
running its exported seed files (tests/test_seed_cli.py).

    python -m tools.studies.seed_measure            # about a minute on 2 cores
    python -m tools.studies.seed_measure --rt       # Rayleigh-Taylor growth vs linear theory (about 3 min)
"""

import contextlib
import io
import math
import shlex
import sys
import tempfile
import time

import numpy as np

import taisph
from taisph.cases.drop_on_incline import downslope, height_above_plane
from taisph.geometry import inside_triangle
from taisph.validation.seed_scenes import DX_DROP, DX_TWO, DX_WEDGE, G, WEDGE, at, potential_energy, record


def wedge():
    start = time.perf_counter()
    sim, snaps = record(taisph.cases.dam_break_wedge(dx=DX_WEDGE), 0.9, 6)
    f = sim.fluid
    s = at(snaps, 0.45)
    x, v = s["x"][f], s["v"][f]
    t_up, n_up = np.array([1.0, 1.0]) / math.sqrt(2), np.array([-1.0, 1.0]) / math.sqrt(2)
    d = (x - np.array(WEDGE[0])) @ n_up
    layer = (x[:, 0] > WEDGE[0][0]) & (x[:, 0] < WEDGE[1][0]) & (d > 0) & (d < 2 * DX_WEDGE)
    vt, vn = v[layer] @ t_up, v[layer] @ n_up
    print(f"dam_break_wedge dx={DX_WEDGE} ({time.perf_counter() - start:.1f} s wall)")
    print(f"  t=0.45: {layer.sum()} particles on the upstream face, mean up-slope speed {vt.mean():.2f} m/s, "
          f"mean|v_n|/mean|v_t| = {np.abs(vn).mean() / np.abs(vt).mean():.3f}")
    for t in (0.6, 0.9):
        xt = at(snaps, t)["x"][f]
        print(f"  t={t}: past the apex {100 * (xt[:, 0] > 2.5).mean():.1f} %, beyond the wedge (x>3) "
              f"{100 * (xt[:, 0] > 3.0).mean():.1f} %")
    inside = max(int(inside_triangle(s_["x"][f], *WEDGE).sum()) for s_ in snaps)
    print(f"  particles inside the wedge (max over frames): {inside}; "
          f"max |rho/rho0-1|: {max(np.abs(s_['rho'][f] / 1000 - 1).max() for s_ in snaps):.4f}")


def drop():
    start = time.perf_counter()
    sim, snaps = record(taisph.cases.drop_on_incline(dx=DX_DROP), 0.5, 10)
    f = sim.fluid
    y0 = snaps[0]["x"][f, 1].mean()
    free = [s for s in snaps if s["t"] <= 0.2]
    err = max(abs(s["x"][f, 1].mean() - (y0 - 0.5 * G * s["t"] ** 2)) for s in free)
    rho = max(np.abs(s["rho"][f] / 1000 - 1).max() for s in free)
    print(f"drop_on_incline dx={DX_DROP} ({time.perf_counter() - start:.1f} s wall)")
    print(f"  free fall to t=0.2: max |y_com - (y0 - g t^2/2)| = {err:.2e} m, max |rho/rho0-1| = {rho:.2e}; "
          f"contact expected at t = {math.sqrt(2 * 0.3 / G):.3f} s")
    r0 = DX_DROP / 2
    print(f"  closest approach to the plane after contact: {min(height_above_plane(s['x'][f]).min() for s in snaps) / r0:.2f} r0; "
          f"at t=0.3: {height_above_plane(at(snaps, 0.3)['x'][f]).min():.4f} m")
    print(f"  extent along the slope at t=0.45: {np.ptp(downslope(at(snaps, 0.45)['x'][f])):.3f} m "
          f"= {np.ptp(downslope(at(snaps, 0.45)['x'][f])) / 0.4:.2f} diameters")
    u3, u5 = (downslope(at(snaps, t)["v"][f]).mean() for t in (0.3, 0.5))
    frictionless = G * math.sin(math.pi / 4) * 0.2
    print(f"  down-slope COM velocity gained 0.3 -> 0.5 s: {u5 - u3:.3f} m/s (frictionless {frictionless:.3f}; "
          f"ratio {(u5 - u3) / frictionless:.2f}, i.e. mean acceleration {(u5 - u3) / 0.2:.2f} m/s^2 "
          f"vs g sin45 = {G * math.sin(math.pi / 4):.2f})")


def two_fluids():
    out = {}
    for ratio in (2.0, 0.5):
        start = time.perf_counter()
        sim, snaps = record(taisph.cases.two_fluids(dx=DX_TWO, density_ratio=ratio), 1.5, 3)
        f = sim.fluid
        up, low = f & (sim.materials() == 0), f & (sim.materials() == 1)
        first, last = snaps[0], snaps[-1]
        fall = first["x"][up, 1].mean() - last["x"][up, 1].mean()
        out[ratio] = fall
        print(f"two_fluids dx={DX_TWO} density_ratio={ratio} ({time.perf_counter() - start:.1f} s wall)")
        print(f"  upper fluid COM fall by 1.5 s: {fall:.4f} m")
        if ratio == 2.0:
            full = G * 1.0 * 500.0 * 1.0
            rel = (potential_energy(first, f) - potential_energy(last, f)) / full
            print(f"  potential energy released: {100 * rel:.1f} % of full inversion ({full:.0f} J/m)")
            print(f"  heavy finger tip {1.0 - last['x'][up, 1].min():.3f} m below y = 1, light bubble "
                  f"{last['x'][low, 1].max() - 1.0:.3f} m above")
            print(f"  max |rho/rho0-1| over frames: "
                  f"{max(np.abs(s['rho'][f] / np.where(s['mat'][f] == 0, 1000.0, 500.0) - 1).max() for s in snaps):.4f}")
    print(f"  control/unstable fall ratio: {out[0.5] / out[2.0]:.3f}")


def export_run():
    from taisph.cli import main as cli
    from taisph.formats import dat as seedio

    for case, params in (("dam_break_wedge", {"dx": 0.08}), ("two_fluids", {"dx": 0.05}),
                         ("drop_on_incline", {"dim": 3, "dx": 0.1})):
        with tempfile.TemporaryDirectory() as tmp:
            buf = io.StringIO()
            with contextlib.redirect_stdout(buf):
                cli.main(["export", case, "--dat", f"{tmp}/dat"]
                         + sum((["--set", f"{k}={v}"] for k, v in params.items()), []))
            argv = shlex.split(buf.getvalue().strip().splitlines()[-1])[3:]
            scene = taisph.cases.CASES[case](**params)
            sim = taisph.Simulation(scene)
            t_end = 30 * sim.dt
            argv[(2 if scene.n_wall else 1) + 1] = repr(t_end)
            with contextlib.redirect_stdout(io.StringIO()):
                cli.main(argv + ["--frames", "1", "--out", f"{tmp}/out", "--no-progress"])
            sim.run(t_end, frames=1)
            f = seedio.read_output(f"{tmp}/out/fluid.dat")[-1]
            fl = sim.fluid
            print(f"export -> run, {case} {params}, {sim.steps} steps: max |dx| = "
                  f"{np.abs(f.position - sim.positions()[fl]).max():.3g} m, max |dv| = "
                  f"{np.abs(f.velocity - sim.velocities()[fl]).max():.3g} m/s, max |drho| = "
                  f"{np.abs(f.density - sim.density()[fl]).max():.3g} kg/m^3")


def rt_growth():
    """Interface amplitude of two_fluids, as the first Fourier mode of the upper fluid,
    a(t) = -(2/W) sum_upper V_p cos(k x_p), V_p = m_p / rho0 (exactly a for an interface
    y = H/2 + a cos(k x)), against inviscid linear theory a0 cosh(sigma t),
    sigma = sqrt(A k g), and the viscous estimate sigma_v = sqrt(sigma^2 + nu^2 k^4) - nu k^2
    with the artificial viscosity's nu = alpha h c0 / 8 (2D, Monaghan 2005)."""
    from taisph.terms import Continuity, PressureGradient

    k = 2 * math.pi
    sigma0 = math.sqrt(G * k / 3.0)
    print(f"two_fluids Rayleigh-Taylor: inviscid linear theory sigma = {sigma0:.2f} /s")
    times = (0.25, 0.5, 0.75, 1.0)
    for dx, alpha, form in ((0.04, 0.1, "multiphase"), (0.04, 0.02, "multiphase"), (0.04, 0.1, "seed"),
                            (0.02, 0.1, "multiphase")):
        scene = taisph.cases.two_fluids(dx=dx, alpha=alpha)
        if form == "seed":
            scene.terms[:2] = [Continuity(), PressureGradient()]
        start = time.perf_counter()
        sim, snaps = record(scene, 1.0, 8)
        f = sim.fluid
        up = f & (sim.materials() == 0)

        volume = snaps[0]["m"][up] / scene.materials[0].rho0

        def amplitude(s):
            return float(-2.0 * (volume * np.cos(k * s["x"][up, 0])).sum())

        a0 = amplitude(snaps[0])
        nu = alpha * scene.smoothing_length * scene.materials[0].c0 / 8
        sigma_v = math.sqrt(sigma0**2 + nu**2 * k**4) - nu * k**2
        growth = ", ".join(f"t={t}: a/a0={amplitude(at(snaps, t)) / a0:.2f} "
                           f"(sigma_eff {math.acosh(max(1.0, amplitude(at(snaps, t)) / a0)) / t:.2f})" for t in times)
        print(f"  dx={dx} alpha={alpha} {form:10s} a0={a0:.3f} nu={nu:.4f} sigma_viscous={sigma_v:.2f}/s | {growth} "
              f"({time.perf_counter() - start:.0f} s wall)")


if __name__ == "__main__":
    if "--rt" in sys.argv:
        rt_growth()
        sys.exit()
    export_run()
    wedge()
    drop()
    two_fluids()
