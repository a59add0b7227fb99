"""The cell-grid neighbour search finds exactly the brute-force pair set.

Clouds include particles exactly on cell edges, particles far outside the scene's
domain (clamped into border cells), coincident particles, and clouds after the
particles have moved outside the grid built at the start.
"""

import numpy as np
import pytest

import taisph
from taisph.terms import Continuity, PressureGradient


def cloud_scene(points, dim, h=0.1, kernel="spline", domain=None):
    lo = np.zeros(dim) if domain is None else np.asarray(domain[0], float)
    hi = np.ones(dim) if domain is None else np.asarray(domain[1], float)
    scene = taisph.Scene("cloud", dim=dim, dx=h / 1.3, smoothing_length=h, domain=(lo, hi),
                         terms=[Continuity(), PressureGradient()], kernel=kernel)
    scene.add_fluid(points)
    return scene


def brute_force(points, radius):
    """(pairs, ambiguous): pairs with r < radius, and pairs within 1e-9 of the cut-off,
    which floating-point rounding may put on either side."""
    d = np.linalg.norm(points[:, None, :] - points[None, :, :], axis=2)
    np.fill_diagonal(d, np.inf)
    inside = d < radius
    near = np.abs(d - radius) <= 1e-9 * radius
    return inside, near


def assert_same_pairs(sim, points):
    radius = sim.scene.support_radius
    inside, near = brute_force(points, radius)
    pairs = sim.neighbour_pairs()
    found = np.zeros_like(inside)
    assert len(np.unique(pairs, axis=0)) == len(pairs), "a pair was found twice"
    found[pairs[:, 0], pairs[:, 1]] = True
    mismatch = (found != inside) & ~near
    assert not mismatch.any(), f"{mismatch.sum()} pairs differ, e.g. {np.argwhere(mismatch)[:3]}"
    assert found.sum() >= inside.sum() - near.sum()


@pytest.mark.parametrize("dim", [1, 2, 3])
@pytest.mark.parametrize("kernel", ["spline", "gaussian"])
def test_random_cloud(dim, kernel, rng):
    n = {1: 300, 2: 1500, 3: 2000}[dim]
    points = rng.uniform(0, 1, size=(n, dim))
    sim = taisph.Simulation(cloud_scene(points, dim, kernel=kernel))
    assert_same_pairs(sim, points)


@pytest.mark.parametrize("dim", [2, 3])
def test_cell_edges_outside_and_coincident(dim, rng):
    h = 0.1
    cell = 2 * h  # spline support = cell edge of the grid
    inner = rng.uniform(0, 1, size=(600, dim))
    # points exactly on cell edges of the grid (its origin is one cell below the domain)
    edges = (rng.integers(-1, 6, size=(300, dim)) * cell).astype(float)
    edges[::3, 0] = 1.0  # on the domain boundary
    far = rng.uniform(-3, 4, size=(100, dim))  # far outside the domain
    far[:10] = far[0]  # coincident particles
    points = np.concatenate([inner, edges, far])
    sim = taisph.Simulation(cloud_scene(points, dim, h=h))
    assert_same_pairs(sim, points)


def test_particles_moving_out_of_the_grid(rng):
    """The grid is built once; particles that later fly outside it are clamped into the
    border cells and still find their neighbours (and nothing indexes out of bounds)."""
    dim = 2
    points = rng.uniform(0, 1, size=(800, dim))
    sim = taisph.Simulation(cloud_scene(points, dim))
    velocity = rng.normal(0, 5, size=(800, dim))
    moved = points + velocity  # up to ~15 units outside a unit-square domain
    _move(sim, moved)
    assert_same_pairs(sim, moved)
    # and a non-finite position stays in bounds (clamped into cell 0)
    moved[5] = np.nan
    moved[6] = [np.inf, -np.inf]
    _move(sim, moved)
    pairs = sim.neighbour_pairs()
    assert not np.isin([5, 6], pairs).any()


def _move(sim, positions):
    """Put the particles at `positions` (by id) in the device state."""
    vec, sca, ints = sim.state.memory_order()
    vec[sim.solver.layout.q.position] = positions[ints[sim.solver.layout.q.id]]
    sim.state.set_state(vec, sca, ints)


def test_asking_for_pairs_mid_run_does_not_change_the_run():
    """`neighbour_pairs()` sorts the state by cell, which starts a step of length 0;
    called in the middle of a run it must leave the state, the clock and the time-step
    maxima alone: the run continues bit for bit as if it had not been asked
    (deterministic mode, dam break)."""
    scene = taisph.cases.dam_break(dx=0.08)
    a = taisph.Simulation(scene, deterministic=True)
    b = taisph.Simulation(scene, deterministic=True)
    a.step(30)
    b.step(30)
    x_before = b.positions()
    pairs = b.neighbour_pairs()
    assert len(pairs) > 0
    np.testing.assert_array_equal(b.positions(), x_before)
    assert b.time == a.time and b.steps == a.steps
    a.step(30)
    b.step(30)
    assert b.time == a.time
    np.testing.assert_array_equal(b.positions(), a.positions())
    np.testing.assert_array_equal(b.velocities(), a.velocities())
