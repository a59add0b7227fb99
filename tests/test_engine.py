"""Engine mechanisms other issues build on: periodic axes, neighbour passes, XSPH."""

import numpy as np
import pytest

import taisph
from taisph.terms import XSPH, ArtificialViscosity, Continuity, PressureGradient, SummationDensity


def periodic_scene(points, dim, periodic, terms=None, h=0.1, velocity=None):
    scene = taisph.Scene("box", dim=dim, dx=h / 1.3, smoothing_length=h, domain=(np.zeros(dim), np.ones(dim)),
                         terms=terms or [Continuity(), PressureGradient()], periodic=periodic,
                         materials=[taisph.Material(c0=10.0)])
    scene.add_fluid(points, velocity=velocity)
    return scene


def nearest_image_pairs(points, radius, periodic):
    d = points[:, None, :] - points[None, :, :]
    for k, p in enumerate(periodic):
        if p:
            d[..., k] -= np.round(d[..., k])
    r = np.linalg.norm(d, axis=2)
    np.fill_diagonal(r, np.inf)
    return r < radius, np.abs(r - radius) <= 1e-9 * radius


@pytest.mark.parametrize("dim,periodic", [(2, (True, True)), (2, (True, False)), (2, (False, True)),
                                          (3, (True, True, True)), (3, (False, True, False)), (1, (True,))])
def test_periodic_neighbours_are_nearest_images(dim, periodic, rng):
    """The grid wraps around periodic axes: the pair set equals the brute-force
    nearest-image pairs (box of side 1, support 0.2 -> 5 cells per periodic axis)."""
    n = {1: 200, 2: 1200, 3: 1500}[dim]
    points = rng.uniform(0, 1, size=(n, dim))
    points[:20, 0] = rng.choice([0.0, 1 - 1e-12], size=20)  # on the periodic seam
    sim = taisph.Simulation(periodic_scene(points, dim, periodic))
    inside, near = nearest_image_pairs(points, sim.scene.support_radius, periodic)
    found = np.zeros_like(inside)
    pairs = sim.neighbour_pairs()
    found[pairs[:, 0], pairs[:, 1]] = True
    assert not ((found != inside) & ~near).any()


def test_periodic_positions_wrap_and_stay_exact(rng):
    """Particles drifting through a fully periodic box stay inside it, and the
    neighbour set is still exact after they crossed the seams several times."""
    points = rng.uniform(0, 1, size=(600, 2))
    velocity = np.tile([3.3, -2.1], (600, 1))  # no relative motion: no forces
    sim = taisph.Simulation(periodic_scene(points, 2, (True, True), velocity=velocity))
    sim.step(40, dt=0.02)  # moves 2.6 and 1.7 box lengths
    x = sim.positions()
    assert x.min() >= 0 and x.max() < 1
    expected = (points + 0.8 * np.array([3.3, -2.1])) % 1.0
    np.testing.assert_allclose(x, expected, atol=1e-9)
    inside, near = nearest_image_pairs(x, sim.scene.support_radius, (True, True))
    found = np.zeros_like(inside)
    pairs = sim.neighbour_pairs()
    found[pairs[:, 0], pairs[:, 1]] = True
    assert not ((found != inside) & ~near).any()


def test_periodic_axis_too_short_is_refused():
    with pytest.raises(ValueError, match="at least 3 kernel supports"):
        taisph.Simulation(periodic_scene(np.full((4, 2), 0.5), 2, (True, False), h=0.2))


def test_summation_density_pass_on_a_lattice():
    """A neighbour pass before the force pass: rho = sum_j m_j W_ij on a periodic
    lattice equals rho0 to the lattice-sum accuracy of the cubic spline at h = 1.3 dx
    (5e-5, measured in tests/test_kernels.py's study), and the EOS sees it (P ~ 0)."""
    dx = 0.05
    axis = (np.arange(20) + 0.5) * dx
    points = np.stack(np.meshgrid(axis, axis, indexing="ij"), -1).reshape(-1, 2)
    scene = periodic_scene(points, 2, (True, True), terms=[SummationDensity(), PressureGradient()], h=1.3 * dx)
    scene.dx = dx
    scene.mass[:] = 1000.0 * dx**2
    scene.density[:] = 500.0  # wrong on purpose: the pass replaces it
    sim = taisph.Simulation(scene)
    rho = sim.density()
    np.testing.assert_allclose(rho, 1000.0, rtol=1e-4)
    assert np.abs(sim.pressure()).max() < 1e-3 * 1000.0 * 10.0**2


def test_summation_density_and_continuity_are_exclusive():
    scene = periodic_scene(np.full((4, 2), 0.5), 2, (True, True), terms=[SummationDensity(), Continuity()])
    with pytest.raises(ValueError, match="cannot both"):
        scene.validate()


def test_xsph_moves_particles_not_momentum(rng):
    """XSPH shifts are antisymmetric pair sums (sum_i m_i shift_i = 0): the centre of
    mass still moves with the total momentum, while individual paths change."""
    points = rng.uniform(0, 1, size=(500, 2))
    velocity = rng.normal(0, 1, size=(500, 2))
    runs = []
    for extra in ([], [XSPH(xsph_eps=0.5)]):
        terms = [Continuity(), PressureGradient(), ArtificialViscosity(alpha=0.1), *extra]
        scene = periodic_scene(points, 2, (False, False), terms=terms, velocity=velocity)
        scene.integrator = "euler"
        sim = taisph.Simulation(scene)
        m = sim.masses()
        x0, v0 = sim.positions(), sim.velocities()
        sim.step(1, dt=1e-3)
        runs.append(sim.positions())
        com_shift = (m[:, None] * (sim.positions() - x0)).sum(0) / m.sum()
        expected = 1e-3 * (m[:, None] * v0).sum(0) / m.sum()
        np.testing.assert_allclose(com_shift, expected, atol=1e-14)
    assert np.abs(runs[1] - runs[0]).max() > 1e-6


@pytest.mark.parametrize("name,dim", [("spline", 2), ("gaussian", 3), ("wendland", 1), ("wendland", 2)])
def test_a_kernel_s_numpy_form_is_its_taichi_form(name, dim):
    """Each smoothing kernel's ``f_numpy`` (sums on the host: DFSPH's lattice density)
    gives the values of its ``f`` in the kernels, across both pieces and the cut-off."""
    from taisph.engine import smoothing

    h = 0.1
    r = np.linspace(0.0, 3.2 * h, 97)
    rij = np.zeros((len(r), dim))
    rij[:, 0] = r
    w, _ = smoothing.evaluate(name, dim, rij, h)
    kernel = smoothing.make(name, dim)
    np.testing.assert_allclose(kernel.sigma(dim) / h**dim * kernel.f_numpy(r / h), w, rtol=1e-12, atol=1e-14)
