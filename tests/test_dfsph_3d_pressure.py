"""DFSPH's pressure values in 3D (issue 51: "no test checks DFSPH's pressure values in 3D
(incompressibility hides a pressure-scale error)"; "a 3D DFSPH pressure check against
hydrostatics (a tank) and against the 3D Tait/WCSPH pressure on the same flow").

An incompressible solve hides a wrong pressure scale: the flow needs only that the solve's
own pressure force holds the density at rho0, so a wrong factor in the pressure written out
(``(kappa + kappa_v) rho^2``, taisph/engine/dfsph/kernels.py), in the kernel's 3D
normalisation or in a power of dt would leave the motion and the density as they are and
change every pressure a frame, a probe or ``sim.pressure()`` reports. These tests read that
pressure and compare it with

1. hydrostatics in a 3D tank whose pressure starts at zero (uniform density rho0, so the
   solve's warm start, ``solver.initial_kappa``, is zero): the solver has to build
   rho0 g depth itself;
2. the exact pressure of the 3D dam break's column just released: the potential flow's at
   t = 0+ (Laplace's equation in x-y, uniform across z between the side walls);
3. the Tait (WCSPH) pressure of the same 3D dam break, each solver's floor pressure averaged
   over a window of about two acoustic periods of WCSPH, whose pressure rings about the
   incompressible one with an amplitude of the order of rho g H.

Measured values are quoted in each test (CPU, f64). The bars of 1 and 2 are about three
times the measured error; the bar of 3 is set by WCSPH's ringing. What they catch, measured
with the pressure force's scale (``dfsph.parameters.gradient_scale``) multiplied by 1.1 and
by 0.95 in a throwaway run (pressures 9 % low and 5 % high): the tank fails on both (rms 11.4 %
and 4.7 %, slope 0.951 and 1.043), the released column on both (sum 0.917 and 1.074); the
comparison with WCSPH on neither (0.92 and 1.09): it would catch a factor, not a few per cent.
"""

import numpy as np
import pytest

import taisph

G, RHO0 = 9.81, 1000.0


def tank_3d(solver, dx, width=0.5, height=0.5):
    """`width` x `height` x `width` (m) of water filling the bottom of a 3D tank of the same
    width and depth (dam_break_3d with the column as wide as the tank; dummy walls without
    friction, as hydrostatic_tank has), its density uniform rho0: pressure 0 at t = 0."""
    scene = taisph.cases.dam_break_3d(dx=dx, width=width, height=height, depth=width, tank_width=width,
                                      tank_height=1.5 * height, wall_friction=False)
    scene.solver = solver
    scene.density[scene.kind == 0] = RHO0  # not the case's hydrostatic start
    return scene


def layer_pressures(sim, width, height):
    """The mean pressure of each horizontal layer of fluid particles farther than 2 h from
    every wall, the floor and the free surface (height: its initial level): (depths, pressures)."""
    x, p = sim.positions()[sim.fluid], sim.pressure()[sim.fluid]
    dx, margin = sim.scene.dx, 2 * sim.scene.smoothing_length
    depth = height - x[:, 1]
    inner = np.all((x[:, [0, 2]] > margin) & (x[:, [0, 2]] < width - margin), axis=1)
    keep = inner & (depth > margin) & (x[:, 1] > margin)
    layer = np.round((x[keep, 1] - dx / 2) / dx).astype(int)
    rows = np.unique(layer)
    return (np.array([depth[keep][layer == r].mean() for r in rows]),
            np.array([p[keep][layer == r].mean() for r in rows]))


def settled_tank(dx, times):
    """DFSPH in the 3D tank from zero pressure: per sample time, (rms over the layers of
    p / (rho0 g depth) - 1, slope of the fitted p(depth) over rho0 g, max |v|)."""
    width = height = 0.5
    sim = taisph.Simulation(tank_3d("dfsph", dx, width, height))
    assert np.all(sim.pressure()[sim.fluid] == 0.0)  # the start is away from the answer
    out = []
    for t in times:
        sim.run(t, frames=0)
        depth, p = layer_pressures(sim, width, height)
        assert len(depth) >= 4, depth
        ratio = p / (RHO0 * G * depth)
        slope = np.polyfit(depth, p, 1)[0] / (RHO0 * G)
        vmax = float(np.abs(sim.velocities()[sim.fluid]).max())
        print(f"t = {t:g} s: p / rho0 g depth by layer {np.round(ratio, 4)}, slope {slope:.4f}, max |v| {vmax:.2g} m/s")
        out.append((float(np.sqrt(np.mean((ratio - 1) ** 2))), float(slope), vmax))
    return out


def test_dfsph_builds_the_hydrostatic_pressure_of_a_3d_tank_from_zero():
    """0.5 m of water in a 0.5 m x 0.5 m tank, dx = 0.05 (1 000 particles), pressure 0 at
    t = 0; after a damped oscillation of the solve's pressure (rms 3.5 % at 0.1 s, 1.4 % at
    0.2 s, 3.3 % at 0.3 s, ...) the water is at rest by 2 s. At 2, 2.5 and 3 s, over the 4 layers 2 h from
    the walls, floor and surface: the rms of p / (rho0 g depth) - 1 is <= 4.5 % (measured
    1.4-1.5 %: the layers 0.995, 0.986, 1.002, 0.975 from the deepest up: the pressure is short by
    about 0.008 rho g H, 0.08 dx of head, a free-surface offset), the slope of p against
    depth is rho0 g within 2.5 % (measured +0.7 %; pressures 5 % high or 9 % low fail both:
    module docstring), and max |v| <= 1.5e-3 m/s (measured 5e-4 at 2 s, 1e-4 at 3 s)."""
    for rms, slope, vmax in settled_tank(0.05, (2.0, 2.5, 3.0)):
        assert rms <= 0.045
        assert abs(slope - 1) <= 0.025
        assert vmax <= 1.5e-3


@pytest.mark.slow
def test_dfsph_builds_the_hydrostatic_pressure_of_a_3d_tank_from_zero_at_dx_0_025():
    """The same at dx = 0.025 (8 000 particles, 14 layers; measured at 2.5 and 3 s: rms 0.61 %
    and 0.56 %, the layers between 0.989 and 1.005, alternating, slope 0.994 and 0.995, max |v|
    4e-4 m/s)."""
    for rms, slope, vmax in settled_tank(0.025, (2.5, 3.0)):
        assert rms <= 0.02
        assert abs(slope - 1) <= 0.02
        assert vmax <= 1.5e-3


def released_column_pressure(x, y, width, height, terms=400):
    """The pressure (Pa) at t = 0+ of a `width` x `height` column of water released at
    x = width, its back wall at x = 0 and floor at y = 0 (rho0, g): the potential flow's,
    with the accelerations of the fluid at rest a = g - grad p / rho0 divergence-free, so
    laplace(p) = 0, p = 0 on the free faces (y = height, x = width), dp/dy = -rho0 g on the
    floor and dp/dx = 0 on the back wall (Korobkin & Yilmaz 2009, "The initial stage of
    dam-break flow", J. Eng. Math. 63). Mirrored at x = 0, the series
    p = rho0 g sum_n c_n cos(k_n x) sinh(k_n (height - y)) / (k_n cosh(k_n height)),
    k_n = (n + 1/2) pi / width, c_n = 2 (-1)^n / ((n + 1/2) pi), the cosine series of 1."""
    n = np.arange(terms)
    k = (n + 0.5) * np.pi / width
    c = 2 * (-1.0) ** n / ((n + 0.5) * np.pi)
    x, y = np.asarray(x, float)[:, None], np.asarray(y, float)[:, None]
    decay = (np.exp(-k * y) - np.exp(-k * (2 * height - y))) / (k * (1 + np.exp(-2 * k * height)))
    return RHO0 * G * (c * np.cos(k * x) * decay).sum(axis=1)


def released_column(dx):
    """DFSPH's pressure after the first step of the 3D dam break (1 x 2 x 1 m column), the
    solve converged to 1e-7 (with the default 2e-4 the first step stops 33 % high in the sum,
    still near the hydrostatic warm start, and the second 6 % low: the comparison with WCSPH
    below has the solve as run), against released_column_pressure over the fluid farther
    than 2 h from the side walls: (sum p / sum exact, rms (p - exact) / (rho0 g H))."""
    scene = taisph.cases.dam_break_3d(dx=dx)
    scene.solver = "dfsph"
    sim = taisph.Simulation(scene, dfsph_tolerance=1e-7, dfsph_min_iterations=20, dfsph_max_iterations=5000)
    sim.step(1)
    x, p = sim.positions()[sim.fluid], sim.pressure()[sim.fluid]
    margin, depth, width, height = 2 * scene.smoothing_length, 1.0, 1.0, 2.0
    inner = (x[:, 2] > margin) & (x[:, 2] < depth - margin)
    exact = released_column_pressure(np.minimum(x[inner, 0], width), x[inner, 1], width, height)
    ratio = float(p[inner].sum() / exact.sum())
    rms = float(np.sqrt(np.mean((p[inner] - exact) ** 2)) / (RHO0 * G * height))
    print(f"dx = {dx:g}, t = {sim.time:.4g} s: sum p / sum exact {ratio:.4f}, rms error {rms:.4f} rho0 g H")
    return ratio, rms


def test_released_column_has_the_potential_flow_pressure():
    """The 3D dam break at dx = 0.1 (2 000 particles), its column released: the pressure of
    the first step (t = 11.5 ms; with dt_max = 2 ms the same to 0.2 %) over the column is
    the exact t = 0+ pressure's within 5 % in the sum (measured +1.6 %; 0.4 % at dx = 0.05)
    and within 2.2 % of rho0 g H in rms (measured 0.73 %; 0.39 % at dx = 0.05). The hydrostatic
    pressure it starts from is 6.6 times the exact pressure in the sum (2.7 times at the
    back wall's foot): the solve has brought it down to the released column's."""
    ratio, rms = released_column(0.1)
    assert abs(ratio - 1) <= 0.05
    assert rms <= 0.022


@pytest.mark.slow
def test_released_column_has_the_potential_flow_pressure_at_dx_0_05():
    """The same at dx = 0.05 (16 000 particles; measured: sum +0.41 %, rms 0.39 % of rho0 g H)."""
    ratio, rms = released_column(0.05)
    assert abs(ratio - 1) <= 0.015
    assert rms <= 0.012


def floor_pressure(solver, dx, t_end=0.25, every=0.01):
    """The 3D dam break (1 x 2 x 1 m column, 4 m tank) under `solver`: the mean pressure of
    the floor's row of fluid particles under the column (x < 1 m, farther than 2 h from the
    side walls), sampled every `every` s to `t_end`: (the samples' mean, the samples)."""
    scene = taisph.cases.dam_break_3d(dx=dx)
    scene.solver = solver
    sim = taisph.Simulation(scene)
    margin, samples = 2 * scene.smoothing_length, []
    for k in range(1, int(round(t_end / every)) + 1):
        sim.run(k * every, frames=0)
        x, p = sim.positions()[sim.fluid], sim.pressure()[sim.fluid]
        under = (x[:, 1] < dx) & (x[:, 0] < 1.0) & (x[:, 2] > margin) & (x[:, 2] < 1.0 - margin)
        samples.append(float(p[under].mean()))
    print(f"{solver}, dx = {dx:g}: floor pressure under the column, mean over (0, {t_end:g}] s "
          f"{np.mean(samples):.0f} Pa, samples {np.round(np.array(samples) / 1000, 1)} kPa")
    return float(np.mean(samples)), np.array(samples)


def test_dfsph_floor_pressure_agrees_with_wcsph_in_the_3d_dam_break():
    """dx = 0.1, the first 0.25 s (WCSPH's c0 = 10 sqrt(2 g H) rings with a period 4 H / c0
    = 0.13 s and an amplitude of about rho g H / 2 on the floor: samples from -5 to +20 kPa).
    The floor pressure under the column, averaged over (0, 0.25] s (25 samples), agrees
    between the solvers within 10 % (measured: DFSPH 6.94 kPa, WCSPH 6.77 kPa, 1.026; with
    samples every 5 ms 6.82 and 6.89, 0.99, and moving the window's ends by a quarter period
    0.965-1.001, so WCSPH's ringing leaves about 3.5 % in the mean; over one period, (0, 0.125]
    and (0.125, 0.25] s, 1.10 and 0.92). Both are about a third of the 19.1 kPa they start from
    (hydrostatic): the comparison is of the flow's pressure, not of the start."""
    dfsph, _ = floor_pressure("dfsph", 0.1)
    wcsph, _ = floor_pressure("wcsph", 0.1)
    assert dfsph < 0.5 * RHO0 * G * 1.95 and wcsph < 0.5 * RHO0 * G * 1.95  # far from the start
    assert abs(dfsph / wcsph - 1) <= 0.10


@pytest.mark.slow
def test_dfsph_floor_pressure_agrees_with_wcsph_in_the_3d_dam_break_at_dx_0_05():
    """The same at dx = 0.05 (16 000 particles; measured: DFSPH 7.08 kPa, WCSPH 7.26 kPa,
    0.975; the window's ends moved by a quarter period 0.94-1.02)."""
    dfsph, _ = floor_pressure("dfsph", 0.05)
    wcsph, _ = floor_pressure("wcsph", 0.05)
    assert abs(dfsph / wcsph - 1) <= 0.10
