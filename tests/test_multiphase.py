"""Two phases and surface tension (docs/multiphase.md): the terms against exact values.

The viscosity per phase against Morris' for one fluid; the equation of state's
background pressure; the time step's capillary and per-phase viscous limits against
their formulas; the surface force on a circular drop against Young-Laplace's 2 sigma on
each half; runtime values that recompile nothing.
"""

import math

import numpy as np
import pytest

import taisph
from taisph.eos import tait
from taisph.geometry import lattice
from taisph.scene import Material, Scene
from taisph.terms import Continuity, ContinuityColagrossi, LaminarViscosity, PhaseViscosity


def _periodic_box(terms, materials, n=16, seed=3):
    """A periodic box of n x n particles at rho0 with a random velocity field."""
    dx = 1.0 / n
    scene = Scene(name="box", dim=2, dx=dx, smoothing_length=1.3 * dx, domain=((0.0, 0.0), (1.0, 1.0)),
                  periodic=(True, True), materials=materials, terms=terms, integrator="euler")
    points = lattice((0.0, 0.0), (1.0, 1.0), dx)
    velocity = np.random.default_rng(seed).normal(0.0, 0.1, points.shape)
    half = points[:, 0] < 0.5
    for k in range(len(materials)):
        sel = half if (k == 0 and len(materials) > 1) else (~half if k == 1 else np.ones(len(points), bool))
        scene.add_fluid(points[sel], velocity=velocity[sel], material=k, density=materials[k].rho0,
                        mass=materials[k].rho0 * dx**2)
    return scene


def _velocity_change(scene, dt=1e-6):
    sim = taisph.Simulation(scene, dt=dt)
    v0 = sim.velocities()
    sim.step(1)
    return (sim.velocities() - v0) / dt


def test_phase_viscosity_is_morris_for_one_fluid():
    """One fluid at rho0: Hu & Adams' (2 mu_i mu_j / (mu_i + mu_j)) (V_i^2 + V_j^2) / m_i equals
    Morris' m_j (mu_i + mu_j) / (rho_i rho_j), so PhaseViscosity(mu = rho0 nu) and
    LaminarViscosity(nu) give the same acceleration to round-off (a random velocity field)."""
    nu, rho0 = 0.01, 1000.0
    water = dict(rho0=rho0, c0=10.0, gamma=7.0)
    hu_adams = _velocity_change(_periodic_box([Continuity(), PhaseViscosity()],
                                              [Material("w", viscosity=rho0 * nu, **water)]))
    morris = _velocity_change(_periodic_box([Continuity(), LaminarViscosity(nu=nu)], [Material("w", **water)]))
    assert np.abs(morris).max() > 1.0  # the viscous acceleration is there to compare
    np.testing.assert_allclose(hu_adams, morris, rtol=0, atol=1e-9 * np.abs(morris).max())


def test_phase_viscosity_conserves_momentum_between_phases():
    """Two fluids of density 1000 and 1 and viscosity 10 and 0.01 side by side: the viscous
    forces are equal and opposite pair by pair, so the total momentum does not change
    (to round-off), while each phase's does."""
    heavy = Material("heavy", rho0=1000.0, c0=10.0, viscosity=10.0)
    light = Material("light", rho0=1.0, c0=10.0, viscosity=0.01)
    scene = _periodic_box([ContinuityColagrossi(), PhaseViscosity()], [heavy, light])
    sim = taisph.Simulation(scene, dt=1e-4)
    m, mat = sim.masses(), sim.materials()
    p0 = (m[:, None] * sim.velocities()).sum(axis=0)
    light0 = (m[mat == 1, None] * sim.velocities()[mat == 1]).sum(axis=0)
    sim.step(1)
    p1 = (m[:, None] * sim.velocities()).sum(axis=0)
    light1 = (m[mat == 1, None] * sim.velocities()[mat == 1]).sum(axis=0)
    scale = (m[:, None] * np.abs(sim.velocities())).sum()
    assert np.abs(light1 - light0).max() > 1e-4 * np.abs(light0).max()  # exchanged at the interfaces (3e-4)
    assert np.abs(p1 - p0).max() < 1e-12 * scale


def test_background_pressure_shifts_the_equation_of_state():
    """p(rho) = B((rho/rho0)^gamma - 1) + p_b: the density at pressure p_b is rho0, and the
    inverse is exact on the host (numpy) and on the device (the wall pressure's inverse)."""
    p = np.array([0.0, 50.0, 1234.5])
    rho = tait.density(p, 1000.0, 20.0, 7.0, background_pressure=50.0)
    assert rho[1] == 1000.0
    np.testing.assert_allclose(tait.pressure(rho, 1000.0, 20.0, 7.0, background_pressure=50.0), p, rtol=1e-12,
                               atol=1e-9)
    scene = taisph.cases.oscillating_drop(deformation=0.0, t_end=1e-4)
    sim = taisph.Simulation(scene)
    mat, p_b = sim.materials(), scene.materials[0].background_pressure
    expected = np.where(mat == 0, p_b + scene.case_parameters["sigma"] / scene.case_parameters["radius"], p_b)
    np.testing.assert_allclose(sim.pressure(), expected, rtol=1e-9, atol=1e-9)


def test_time_step_takes_the_capillary_limit():
    """A millimetre drop with water's sigma in a fluid half as dense, c0 = 1 m/s: the capillary
    limit 0.25 sqrt(rho h^3 / (2 pi sigma)), rho the mean of the two densities (Brackbill et
    al. 1992), is below the acoustic and viscous ones, and it is the step taken."""
    scene = taisph.cases.oscillating_drop(deformation=0.0, ambient_density=500.0, c0=1.0)
    h, sigma = scene.smoothing_length, scene.case_parameters["sigma"]
    rho = 0.5 * (1000.0 + 500.0)
    capillary = 0.25 * math.sqrt(rho * h**3 / (2.0 * math.pi * sigma))
    acoustic = 0.25 * h / max(m.c0 for m in scene.materials)
    viscous = 0.125 * h**2 / max(m.viscosity / m.rho0 for m in scene.materials)
    assert capillary < 0.8 * min(acoustic, viscous)
    sim = taisph.Simulation(scene)
    assert sim.dt == pytest.approx(capillary, rel=1e-12)
    sim.step(3)
    from taisph.engine import status as st
    assert sim.state.read(st.DT) == pytest.approx(capillary, rel=1e-9)


def test_time_step_takes_the_most_viscous_phase():
    """With a viscosity per material, dt <= 0.125 h^2 / max_k(mu_k / rho0_k): the light
    phase's 0.5 / 1 m^2/s, not the heavy one's 10 / 1000."""
    heavy = Material("heavy", rho0=1000.0, c0=1.0, viscosity=10.0)
    light = Material("light", rho0=1.0, c0=1.0, viscosity=0.5)
    scene = _periodic_box([ContinuityColagrossi(), PhaseViscosity()], [heavy, light])
    scene.integrator = "pc"
    expected = 0.125 * scene.smoothing_length**2 / 0.5
    sim = taisph.Simulation(scene)
    assert sim.dt == pytest.approx(expected, rel=1e-12)
    sim.step(2)
    from taisph.engine import status as st
    assert sim.state.read(st.DT_STABLE) == pytest.approx(expected, rel=1e-9)


def test_surface_force_on_half_a_drop_is_two_sigma():
    """Young-Laplace on a circular drop of radius R = 20 dx: the surface tension on its upper
    half sums to -2 sigma (per unit depth: the tension pulling at the two ends of the half
    circle), and the colour gradient's delta function integrates to the perimeter 2 pi R.
    Measured after one step from the lattice (2026-12-08): -2 sigma x 1.007 and 2 pi R x 1.018."""
    scene = taisph.cases.oscillating_drop(deformation=0.0, ambient_density=1000.0, ambient_viscosity=1e-3)
    sim = taisph.Simulation(scene, dt=1e-9)
    sim.step(1)
    p = scene.case_parameters
    sigma, radius = p["sigma"], p["radius"]
    x, m, rho = sim.positions(), sim.masses(), sim.density()
    grad_c, kappa = sim.quantity("colour_gradient"), sim.quantity("curvature")
    accel = 2.0 * sigma * kappa[:, None] * grad_c / (p["drop_density"] + p["ambient_density"])
    upper = x[:, 1] > 0.5 * p["box"] * radius
    force = float((m[upper] * accel[upper, 1]).sum())
    perimeter = float((np.linalg.norm(grad_c, axis=1) * m / rho).sum())
    assert force == pytest.approx(-2.0 * sigma, rel=0.05)
    assert perimeter == pytest.approx(2.0 * math.pi * radius, rel=0.05)


def test_phase_constants_change_without_recompiling():
    """A material's viscosity and background pressure and the surface tension are runtime
    values: changing them recompiles no kernel and changes the result."""
    scene = taisph.cases.oscillating_drop(deformation=0.2, dx=1e-3 / 8, t_end=1e-3)
    sim = taisph.Simulation(scene)
    sim.step(3)
    sim.positions()
    compiled = sim.solver.compiled_count()
    before = sim.velocities()
    sim.set(sigma=0.5)
    sim.set_material(0, viscosity=0.01, background_pressure=10.0)
    sim.step(3)
    assert sim.solver.compiled_count() == compiled
    assert sim.parameters()["sigma"] == 0.5
    assert not np.array_equal(sim.velocities(), before)


def _drop_at_rest(**case):
    """Run a circular drop at rest to `t_end` and average its pressure jump (taisph.validation.phases)
    over the second half, sampled every 20 steps; also the largest speed seen then."""
    from taisph.validation.phases import pressure_jump

    scene = taisph.cases.oscillating_drop(deformation=0.0, **case)
    sim = taisph.Simulation(scene)
    radius = scene.case_parameters["radius"]
    jumps, speeds = [], []
    while sim.time < scene.t_end * (1 - 1e-12):
        sim.step(20)
        if sim.time > 0.5 * scene.t_end:
            jumps.append(pressure_jump(sim, radius))
            speeds.append(float(np.linalg.norm(sim.velocities(), axis=1).max()))
    return scene, float(np.mean(jumps)), max(speeds)


def test_laplace_pressure_of_a_drop_at_rest():
    """A circular drop of radius R = 20 dx in fluid of the same density, sigma = 0.0728 N/m,
    R = 1 mm, mu = 0.1 Pa s in both (Laplace number sigma rho R / mu^2 = 7.3: a few viscous
    times R^2 / nu = 10 ms settle it), no gravity, a periodic box of 4 R: the pressure inside
    less the pressure outside, averaged over 3-6 ms, is Laplace's sigma / R within 5 %
    (measured 2026-12-08: 70.15 Pa against 72.8, -3.6 %); the spurious currents stay below
    1 % of the capillary velocity sigma / mu (measured 0.0015 m/s, 0.2 %). The drop starts
    with the Laplace jump in its density, so the test checks that the surface force holds it:
    with the force applied twice (a bug found this way: the loop over materials ran over the
    material table's padding rows) the jump read 100-180 Pa."""
    scene, jump, speed = _drop_at_rest(ambient_density=1000.0, ambient_viscosity=0.1, drop_viscosity=0.1, c0=6.0,
                                       t_end=0.006)
    p = scene.case_parameters
    assert jump == pytest.approx(p["sigma"] / p["radius"], rel=0.05)
    assert speed < 0.01 * p["sigma"] / p["drop_viscosity"]


def test_free_surface_tension_on_half_a_drop():
    """SurfaceTension(free_surface=True): a drop of R = 20 dx with no fluid around it. The
    void counts as colour 0, so only the liquid's half of the colour jump is seen (its
    delta integrates to 0.51 of the perimeter) and the one-sided curvature reads about
    1.9/R; their product, the force on the upper half, is -2 sigma within 10 % (measured
    2026-12-08: 0.942 of it)."""
    from taisph.terms import ContinuityColagrossi, PressureHuAdams, SurfaceTension

    radius, dx, sigma = 1e-3, 5e-5, 0.0728
    scene = Scene(name="free_drop", dim=2, dx=dx, smoothing_length=1.3 * dx, domain=((0, 0), (4 * radius, 4 * radius)),
                  materials=[Material("water", rho0=1000.0, c0=3.0)], integrator="euler",
                  terms=[ContinuityColagrossi(), PressureHuAdams(), SurfaceTension(sigma=sigma, free_surface=True)])
    centre = np.array([2 * radius, 2 * radius])
    points = lattice((0, 0), (4 * radius, 4 * radius), dx)
    scene.add_fluid(points[np.linalg.norm(points - centre, axis=1) < radius], density=1000.0, mass=1000.0 * dx**2)
    sim = taisph.Simulation(scene, dt=1e-9)
    sim.step(1)
    x, m = sim.positions(), sim.masses()
    accel = sigma * sim.quantity("curvature")[:, None] * sim.quantity("colour_gradient") / 1000.0
    upper = x[:, 1] > centre[1]
    assert float((m[upper] * accel[upper, 1]).sum()) == pytest.approx(-2.0 * sigma, rel=0.10)
