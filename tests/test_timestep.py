"""The time step: one formula (taisph.engine.timestep.stable_dt) on the device and on the
host, and every limit it has applies (CFL, force, viscous)."""

import math

import numpy as np
import pytest

import taisph
from taisph.engine import kernels
from taisph.engine.timestep import initial_dt, stable_dt
from taisph.geometry import lattice
from taisph.scene import Material, Scene
from taisph.terms import AdaptiveSmoothingLength, Continuity, Gravity, LaminarViscosity, PressureGradient, Term


def periodic_box(nu=None, dx=0.04, c0=10.0, amplitude=0.0):
    """Water-like fluid on a periodic lattice with the shear wave u = A sin(2 pi y)."""
    terms = [Continuity(), PressureGradient()] + ([LaminarViscosity(nu=nu)] if nu else [])
    scene = Scene("box", dim=2, dx=dx, smoothing_length=1.3 * dx, domain=((0, 0), (1, 1)), periodic=(True, True),
                  materials=[Material("f", 1.0, c0, 7.0)], terms=terms)
    pts = lattice((0, 0), (1, 1), dx)
    scene.add_fluid(pts, velocity=np.stack([amplitude * np.sin(2 * np.pi * pts[:, 1]), 0 * pts[:, 1]], axis=1))
    return scene


def test_the_host_estimate_is_the_devices_first_step():
    """At rest on a periodic lattice (no force), the first adaptive step is the CFL limit
    0.25 h / c0, and the host's estimate before a run (initial_dt, sim.dt) is the same
    number to round-off: both evaluate stable_dt. (Scene.stable_dt used C = 0.2 while
    the device used 0.25: 20 % apart.)"""
    scene = periodic_box()
    h = scene.smoothing_length
    assert initial_dt(scene) == pytest.approx(0.25 * h / 10.0, rel=1e-14)
    sim = taisph.Simulation(scene)
    assert sim.dt == pytest.approx(initial_dt(scene), rel=1e-12)
    sim.step(1)
    assert sim.time == pytest.approx(initial_dt(scene), rel=1e-12)
    sim.close()


def test_with_adaptive_h_the_smallest_h_limits_the_step_on_host_and_device():
    """A smoothing length per particle (adaptive_h): at rest with uniform c0 (no force:
    the density is rho0 everywhere, the pressure zero), the first adaptive step is
    0.25 h_min / c0, the smallest h's limit, and the host's estimate (initial_dt,
    sim.dt) is the same number. The device used the scene's smoothing_length, the cap
    on h (here 2.5 dx), and took a step 2.5 / 1.2 times the host's."""
    dx, c0 = 0.04, 10.0
    scene = Scene("box", dim=2, dx=dx, smoothing_length=2.5 * dx, domain=((0, 0), (1, 1)), periodic=(True, True),
                  materials=[Material("f", 1.0, c0, 7.0)],
                  terms=[Continuity(), PressureGradient(), AdaptiveSmoothingLength(h_factor=1.2)])
    pts = lattice((0, 0), (1, 1), dx)
    heavy = pts[:, 1] > 0.5  # four times the mass: h = 1.2 (m / rho)^(1/2) = 2.4 dx, the others 1.2 dx
    scene.add_fluid(pts, mass=np.where(heavy, 4.0, 1.0) * dx * dx, density=1.0)
    h_min = 1.2 * dx
    assert initial_dt(scene) == pytest.approx(0.25 * h_min / c0, rel=1e-12)
    sim = taisph.Simulation(scene)
    assert sim.dt == pytest.approx(initial_dt(scene), rel=1e-12)
    sim.step(1)
    assert sim.time == pytest.approx(initial_dt(scene), rel=1e-12)
    sim.close()


def test_reading_gravity_changes_nothing():
    """Gravity() given no vector: param_values(dim) is the default of that dimension
    and leaves the term as it was (it stored the first dimension's vector, so a second
    read in another dimension failed); initial_dt reads it the same way."""
    g = Gravity()
    before = dict(g.values)
    assert list(g.param_values(2)["gravity"]) == [0.0, -9.81]
    assert list(g.param_values(3)["gravity"]) == [0.0, -9.81, 0.0]
    assert g.values == before
    scene = periodic_box()
    scene.terms.append(g)
    scene.validate()  # a scene's check fills in its dimension's default: describe() shows it
    assert g.describe() == "gravity(gravity=(0, -9.81))"
    values = dict(g.values)
    # the force limit alone (a huge Courant number lifts the acoustic one)
    assert initial_dt(scene, courant=1e9) == pytest.approx(0.25 * math.sqrt(scene.smoothing_length / 9.81), rel=1e-12)
    assert g.values == values
    g.values["gravity"] = (1.0, 0.0)  # set (as scene.set does): no longer the default
    assert list(g.param_values(2)["gravity"]) == [1.0, 0.0]


def test_stable_dt_takes_the_smallest_limit():
    """Each limit alone, then together; a zero maximum imposes no limit."""
    h = 0.1
    assert stable_dt(h, 10.0, 0.0, 0.0, 0.25, 0.25, 0.125) == pytest.approx(0.25 * h / 10.0)
    assert stable_dt(h, 0.0, 100.0, 0.0, 0.25, 0.25, 0.125) == pytest.approx(0.25 * math.sqrt(h / 100.0))
    assert stable_dt(h, 0.0, 0.0, 2.0, 0.25, 0.25, 0.125) == pytest.approx(0.125 * h * h / 2.0)
    assert stable_dt(h, 10.0, 100.0, 2.0, 0.25, 0.25, 0.125) == pytest.approx(0.125 * h * h / 2.0)


def test_adaptive_dt_honours_the_viscous_limit():
    """With nu = 1 m^2/s on 50 x 50 particles the viscous limit 0.125 h^2/nu = 8.5e-5 s
    is an eighth of the acoustic one (6.5e-4 s). Adaptive steps stay within it and the
    shear wave decays as the exact exp(-4 pi^2 nu t): amplitude within 1.4 % at t = 0.05 s,
    3x the measured +0.46 % (2026-12-07, `pytest -n 0 -s tests/test_timestep.py -k
    viscous_limit` with a print, 8 s; 1.8 % on 25 x 25). Before the viscous limit applied, the steps
    were the acoustic ones and the amplitude came out 23 % too large (63 % too small
    on 25 x 25)."""
    nu = 1.0
    scene = periodic_box(nu=nu, amplitude=0.01, dx=0.02)
    h = scene.smoothing_length
    sim = taisph.Simulation(scene)
    summary = sim.run(0.05, frames=1)
    u, y = sim.velocities()[:, 0], sim.positions()[:, 1]
    sim.close()
    assert summary.dt_max <= 0.125 * h * h / nu * (1 + 1e-12)
    amplitude = np.sum(u * np.sin(2 * np.pi * y)) / np.sum(np.sin(2 * np.pi * y) ** 2)
    assert amplitude == pytest.approx(0.01 * math.exp(-4 * math.pi**2 * nu * 0.05), rel=0.014)


def test_a_term_is_called_exactly_when_it_defines_a_hook():
    """has_pair/has_particle/has_derive are derived from the hooks a class defines: a term
    with a pair() and no flag is traced into the force kernel (a forgotten flag used to
    drop it silently), and a class that sets a flag is refused."""
    import taichi as ti

    @ti.data_oriented
    class Drag(Term):
        name = "drag_test"
        params = {"k": 0.0}

        @ti.func
        def pair(self, s: ti.template(), i, j, rij, r, grad, rates: ti.template()):
            rates.acc -= s.params[self.p.k] * (s.Sv[self.q.velocity, i] - s.Sv[self.q.velocity, j])

    assert Drag().has_pair and not Drag().has_particle and not Drag().has_derive
    scene = periodic_box()
    scene.terms.append(Drag(k=1.0))
    kernels.TRACED.clear()
    taisph.Simulation(scene).step(1)
    assert ("drag_test", "pair") in kernels.TRACED
    with pytest.raises(TypeError, match="has_pair"):
        type("Flagged", (Term,), {"has_pair": True})
