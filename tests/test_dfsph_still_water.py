"""Still water under DFSPH (issue 25: the tank for 10 s within 1 % of rho g H).

Two causes kept the pressure of water at rest off its hydrostatic value, each measured
in docs/dfsph.md, "Still water": the SPH pressure gradient overstates a linear pressure
field by the lattice's gradient moment B (1.0105 for the cases' cubic spline, h = 1.3 dx,
in 2D), so water settled 1 % of rho g H short at the floor; and the particles paired
after 2-3 s (pressure rms 1.4 % over the second half of 10 s). The pressure force is
scaled by 1 / B and fluid pairs closer than dx repel (``PAIRING_REPULSION``).
"""

import numpy as np
import pytest

import taisph
from taisph.engine import smoothing
from taisph.engine.dfsph import parameters
from taisph.validation import runs


@pytest.mark.parametrize("kernel, h, dim", [("spline", 1.3, 2), ("spline", 1.3, 3), ("wendland", 2.0, 2),
                                            ("spline", 1.2, 2)])
def test_the_lattice_moment_is_what_the_sph_gradient_makes_of_a_linear_field(kernel, h, dim):
    """sum_j V (f_j - f_i) grad_i W_ij for f = a . x on a cubic lattice (the solver's own
    kernel gradient, smoothing.evaluate) equals B a, B = smoothing.lattice_moment, to
    1e-6; B differs from 1 by the amounts the docs quote (spline h = 1.3 dx in 2D: 1.05 %)."""
    dx = 1.0
    reach = int(np.ceil(2 * h)) + 1
    axis = np.arange(-reach, reach + 1) * dx
    lattice = np.stack(np.meshgrid(*([axis] * dim), indexing="ij"), -1).reshape(-1, dim)
    lattice = lattice[np.linalg.norm(lattice, axis=1) > 0]
    a = np.array([0.3, -1.0, 0.7][:dim])
    _, grad = smoothing.evaluate(kernel, dim, -lattice, h)  # r_i - r_j with i at the origin
    gradient = ((lattice @ a)[:, None] * grad).sum(axis=0) * dx**dim
    moment = smoothing.lattice_moment(kernel, dim, h, dx)
    np.testing.assert_allclose(gradient, moment * a, rtol=1e-6, atol=1e-9)
    expected = {("spline", 1.3, 2): 1.0105, ("spline", 1.3, 3): 0.9935, ("wendland", 2.0, 2): 0.9992,
                ("spline", 1.2, 2): 0.9908}[(kernel, h, dim)]
    assert moment == pytest.approx(expected, abs=1e-4)


def still_water(dx, t_end, samples):
    """The tank under DFSPH: the pressure error's rms per sample, the floor row's mean
    error at the end (fractions of rho g H) and the closest fluid pair over all samples (in dx)."""
    scene = taisph.cases.hydrostatic_tank(dx=dx, t_end=t_end)
    scene.solver = "dfsph"
    sim = taisph.Simulation(scene)
    x0 = sim.positions()[sim.fluid]
    H = x0[:, 1].max() + dx / 2
    rho_g = scene.materials[0].rho0 * 9.81
    rms, closest = [], np.inf
    for k in range(1, samples + 1):
        sim.run(t_end * k / samples, frames=0)
        x, p = sim.positions()[sim.fluid], sim.pressure()[sim.fluid]
        error = (p - rho_g * (H - x[:, 1])) / (rho_g * H)
        deep = x[:, 1] < H - scene.support_radius
        rms.append(float(np.sqrt(np.mean(error[deep] ** 2))))
        d = np.sqrt(((x[:, None, :] - x[None, :, :]) ** 2).sum(-1)) + np.eye(len(x)) * dx
        closest = min(closest, float(d.min() / dx))
    floor = x[:, 1] < dx
    return np.array(rms), float(np.mean(error[floor])), closest


def test_still_water_stays_hydrostatic_for_10_s_with_the_cases_spline():
    """dx = 0.025 (800 particles), 10 s, the case's cubic spline with h = 1.3 dx, against
    the hydrostatic pressure rho g (H - y): rms pressure error <= 0.17 % of rho g H in every
    sample (issue 25 asked for 1 %; 1.38 % over the second half before the 1 / B scale and the
    pairing repulsion), the floor's pressure within 0.07 % (was 1.1 % short), and no two
    particles closer than 0.95 dx (was 0.34 dx: pairs). Measured 2026-12-07 (`pytest -n 0 -s
    tests/test_dfsph_still_water.py -k cases_spline` with a print, 13 s): rms 0.056-0.057 %,
    floor -0.024 %, closest pair 0.985 dx; the bars are 3x the errors (for the pair, 3x its
    shortfall from dx)."""
    rms, floor, closest = still_water(0.025, 10.0, 10)
    assert rms.max() <= 0.0017, rms
    assert abs(floor) <= 7e-4, floor
    assert closest >= 0.95, closest


@pytest.mark.slow
def test_still_water_stays_hydrostatic_for_10_s_at_dx_0_0125():
    """The same at dx = 0.0125 (3 200 particles; 1.67 % rms before). Measured 2026-12-07
    (`pytest -n 0 -s -m slow tests/test_dfsph_still_water.py -k 0_0125` with a print, 33 s):
    rms 0.024 %, floor -0.014 %, closest pair 0.985 dx; asserted, 3x those: rms <= 0.075 %,
    floor within 0.045 %, no pair closer than 0.95 dx."""
    rms, floor, closest = still_water(0.0125, 10.0, 10)
    assert rms.max() <= 7.5e-4, rms
    assert abs(floor) <= 4.5e-4, floor
    assert closest >= 0.95, closest


def test_the_pressure_force_scale_is_one_over_the_lattice_moment():
    """The scale is 1 / B of the scene's kernel and lattice; the quick still water's
    headline error (runs.hydrostatic_tank, dx = 0.05, 1 s) is far inside the 3 % the
    coarse test holds (measured 0.10 %, 2026-12-07; 0.74 % without the scale at 0.5 s)."""
    scene = taisph.cases.hydrostatic_tank(dx=0.05)
    assert parameters.gradient_scale(scene) == pytest.approx(1 / 1.01054, rel=1e-5)
    out = runs.run("hydrostatic_tank", dx=0.05, solver="dfsph", t_end=1.0, samples=4)
    assert out.error <= 0.003, out.metrics
