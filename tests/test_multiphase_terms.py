"""The multiphase terms (Hu & Adams 2006 pressure, Colagrossi & Landrini 2003
continuity): momentum conservation, and exact reduction to the seed's eqs. 7-8 for
a single fluid of equal masses and densities."""

import numpy as np
import pytest

import taisph
from taisph.terms import (ArtificialViscosity, Continuity, ContinuityColagrossi, PressureGradient,
                          PressureHuAdams)


def two_material_cloud(rng, dim, terms, kernel="spline", equal=False, n=None):
    n = n or (800 if dim == 2 else 1500)
    h = 0.08
    points = rng.uniform(0, 1, size=(n, dim))
    heavy = taisph.Material("heavy", rho0=1000.0, c0=20.0)
    light = taisph.Material("light", rho0=500.0, c0=20.0)
    scene = taisph.Scene("cloud", dim=dim, dx=h / 1.3, smoothing_length=h, domain=(np.zeros(dim), np.ones(dim)),
                         materials=[heavy, light], kernel=kernel, integrator="euler", terms=terms)
    velocity = rng.normal(0, 1, size=(n, dim))
    if equal:
        scene.add_fluid(points, density=1000.0, mass=1.0, velocity=velocity)
    else:
        # the left half light, the right half heavy: a density jump of 2 across x = 0.5
        light_side = points[:, 0] < 0.5
        for material, sel, rho0 in ((0, ~light_side, 1000.0), (1, light_side, 500.0)):
            k = int(sel.sum())
            scene.add_fluid(points[sel], material=material, velocity=velocity[sel],
                            density=rho0 * (1 + 0.01 * rng.standard_normal(k)),
                            mass=rho0 * (h / 1.3) ** dim * rng.uniform(0.5, 1.5, size=k))
    return scene


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("kernel", ["spline", "wendland"])
def test_hu_adams_pressure_conserves_momentum(dim, kernel, rng):
    """Two fluids (density ratio 2, random masses and densities, random velocities):
    one step changes total linear momentum by < 1e-12 of sum |m dv|, and (2D) the
    torque about the origin by < 1e-12 of sum |x| |m dv|; mass is unchanged."""
    scene = two_material_cloud(rng, dim, [ContinuityColagrossi(), PressureHuAdams(), ArtificialViscosity(alpha=0.5)],
                               kernel=kernel)
    sim = taisph.Simulation(scene)
    x0, v0, m = sim.positions(), sim.velocities(), sim.masses()
    sim.step(dt=1e-4)
    dp = m[:, None] * (sim.velocities() - v0)
    scale = np.abs(dp).sum()
    assert scale > 0
    assert np.abs(dp.sum(axis=0)).max() < 1e-12 * scale
    if dim == 2:
        torque = (x0[:, 0] * dp[:, 1] - x0[:, 1] * dp[:, 0]).sum()
        assert abs(torque) < 1e-12 * (np.abs(x0).max() * np.abs(dp)).sum()
    assert sim.total_mass() == m.sum()


@pytest.mark.parametrize("dim", [2, 3])
def test_multiphase_terms_reduce_to_seed_equations(dim, rng):
    """Equal masses and densities: the Hu & Adams acceleration equals the seed's eq. 8
    and the Colagrossi & Landrini density rate equals eq. 7 (to 1e-12 relative)."""
    results = []
    for terms in ([Continuity(), PressureGradient()], [ContinuityColagrossi(), PressureHuAdams()]):
        scene = two_material_cloud(np.random.default_rng(7), dim, terms, equal=True)
        # equal densities but a non-zero pressure: raise it through rho0 of the material
        scene.materials[0].rho0 = 990.0
        sim = taisph.Simulation(scene)
        v0, rho0 = sim.velocities(), sim.density()
        sim.step(dt=1e-4)
        results.append(((sim.velocities() - v0) / 1e-4, (sim.density() - rho0) / 1e-4))
    (a_seed, drho_seed), (a_multi, drho_multi) = results
    assert np.abs(a_seed).max() > 0 and np.abs(drho_seed).max() > 0
    np.testing.assert_allclose(a_multi, a_seed, rtol=0, atol=1e-12 * np.abs(a_seed).max())
    np.testing.assert_allclose(drho_multi, drho_seed, rtol=0, atol=1e-12 * np.abs(drho_seed).max())


def test_cannot_combine_both_forms():
    scene = taisph.Scene("x", dim=2, dx=0.1, smoothing_length=0.13, domain=([0, 0], [1, 1]),
                         terms=[Continuity(), ContinuityColagrossi()])
    scene.add_fluid([[0.5, 0.5]])
    with pytest.raises(ValueError, match="either Continuity"):
        scene.validate()
