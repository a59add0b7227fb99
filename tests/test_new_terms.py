"""The terms added for accuracy, each against a property it must have: laminar viscosity
(momentum conservation, decay rate of a shear wave), particle shifting (no effect on a
regular lattice), the checks that refuse an inconsistent scene."""

import math

import numpy as np
import pytest

import taisph
from taisph.scene import Material, Scene
from taisph.geometry import lattice
from taisph.terms import (AdamiWall, Continuity, DensityDiffusion, LaminarViscosity, ParticleShifting,
                          PressureGradient)


def test_laminar_viscosity_conserves_momentum(rng):
    """Morris's viscous force is pairwise equal and opposite: one step changes total
    momentum by less than 1e-12 of sum |m dv| on a random cloud."""
    n, h = 800, 0.08
    scene = Scene("cloud", dim=2, dx=h / 1.3, smoothing_length=h, domain=(np.zeros(2), np.ones(2)),
                  materials=[Material(rho0=1000.0, c0=20.0)], integrator="euler",
                  terms=[Continuity(), PressureGradient(), LaminarViscosity(nu=0.05)])
    scene.add_fluid(rng.uniform(0, 1, size=(n, 2)), density=1000.0 * (1 + 0.01 * rng.standard_normal(n)),
                    velocity=rng.normal(0, 1, size=(n, 2)), mass=rng.uniform(0.5, 1.5, size=n))
    sim = taisph.Simulation(scene)
    v0, m = sim.velocities(), sim.masses()
    sim.step(dt=1e-4)
    dp = m[:, None] * (sim.velocities() - v0)
    sim.close()
    assert np.abs(dp).sum() > 0
    assert np.abs(dp.sum(axis=0)).max() < 1e-12 * np.abs(dp).sum()


def test_shear_wave_decays_at_the_viscous_rate():
    """u = sin(2 pi y) in a periodic box decays as exp(-4 pi^2 nu t): amplitude within 1 %
    after 0.5 s (nu = 0.1, 25 x 25 particles; measured 0.5 % at 50 x 50)."""
    dx, nu = 0.04, 0.1
    h = 1.3 * dx
    scene = Scene("shear", dim=2, dx=dx, smoothing_length=h, domain=((0, 0), (1, 1)), periodic=(True, True),
                  materials=[Material("f", 1.0, 10.0, 7.0)],
                  terms=[Continuity(), PressureGradient(), LaminarViscosity(nu=nu)])
    pts = lattice((0, 0), (1, 1), dx)
    scene.add_fluid(pts, velocity=np.stack([np.sin(2 * np.pi * pts[:, 1]), 0 * pts[:, 1]], axis=1))
    sim = taisph.Simulation(scene)
    sim.run(0.5, frames=1)
    u = sim.velocities()[:, 0]
    y = sim.positions()[:, 1]
    sim.close()
    amplitude = np.sum(u * np.sin(2 * np.pi * y)) / np.sum(np.sin(2 * np.pi * y) ** 2)
    assert amplitude == pytest.approx(math.exp(-4 * math.pi**2 * nu * 0.5), rel=0.01)


def test_shifting_leaves_a_regular_lattice_alone():
    """On a periodic lattice the concentration gradient is zero: with particle shifting
    and no flow nothing moves (to round-off)."""
    scene = taisph.cases.taylor_green(dx=1 / 20, U=1.0)
    scene.velocity[:] = 0.0
    scene.density[:] = 1.0
    sim = taisph.Simulation(scene)
    x0 = sim.positions()
    sim.step(20)
    moved = np.abs(sim.positions() - x0).max()
    sim.close()
    assert moved < 1e-12


def test_shifting_sees_walls():
    """Water at rest on a lattice in a box of dummy walls on the same lattice: the walls
    fill the kernel sums like water, so the concentration gradient is zero next to them
    and nothing moves (to round-off). Before walls counted in the sum, the rows next to
    the walls were shifted into them (the cylinder case's fluid went through its walls)."""
    dx = 0.05
    scene = Scene("box", dim=2, dx=dx, smoothing_length=1.3 * dx, domain=((-0.2, -0.2), (1.2, 1.2)),
                  materials=[Material("water", 1000.0, 10.0, 7.0)],
                  terms=[Continuity(walls=True), PressureGradient(walls=True), AdamiWall(),
                         ParticleShifting(shift_speed=1.0)])
    points = lattice((-3 * dx, -3 * dx), (1 + 3 * dx, 1 + 3 * dx), dx)
    inside = np.all((points > 0) & (points < 1), axis=1)
    scene.add_fluid(points[inside])
    scene.add_walls(points[~inside])
    sim = taisph.Simulation(scene)
    x0 = sim.positions()
    sim.step(20)
    moved = np.abs(sim.positions() - x0).max()
    sim.close()
    assert moved < 1e-12 * dx


def test_inconsistent_scenes_are_refused():
    """Dummy walls without wall-aware pressure/continuity, no-slip viscosity without dummy
    walls, density diffusion without continuity, shifting without a speed: ValueError."""
    def scene(terms, walls=True):
        s = Scene("s", dim=2, dx=0.1, smoothing_length=0.13, domain=((0, 0), (1, 1)), terms=terms)
        s.add_fluid(lattice((0, 0), (1, 1), 0.1))
        if walls:
            s.add_walls(lattice((0, -0.3), (1, 0), 0.1))
        return s

    with pytest.raises(ValueError, match="walls=True"):
        scene([Continuity(), PressureGradient(), AdamiWall()]).validate()
    with pytest.raises(ValueError, match="dummy-wall"):
        scene([Continuity(), PressureGradient(), LaminarViscosity(nu=1e-3, walls=True)]).validate()
    with pytest.raises(ValueError, match="continuity"):
        scene([PressureGradient(), DensityDiffusion()]).validate()
    with pytest.raises(ValueError, match="shift_speed"):
        scene([Continuity(), PressureGradient(), ParticleShifting()], walls=False).validate()
