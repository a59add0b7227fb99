"""Neighbour lists with a skin (taisph.engine.neighbours): reused between rebuilds, yet exact.

The lists hold every particle closer than support + skin at the last rebuild; they are
rebuilt when some particle has moved half the skin. These tests check that the pairs
the engine visits equal the brute-force pairs while lists are being reused, that a
list overflow falls back to the cells without losing a neighbour (bit for bit), and
that a dam break with lists agrees with one that walks the cells every step.
"""

import numpy as np
import pytest

import taisph
from taisph import Simulation
from taisph.engine import neighbours
from taisph.terms import Continuity

from test_neighbours import assert_same_pairs


def drifting_cloud(rng, n=1500, skin=0.3):
    """Particles in random straight-line motion (continuity only: no force acts)."""
    h = 0.02
    points = rng.uniform(0.1, 0.9, size=(n, 2))
    scene = taisph.Scene("cloud", dim=2, dx=h / 1.3, smoothing_length=h, domain=(np.zeros(2), np.ones(2)),
                         terms=[Continuity()], neighbour_skin=skin)
    scene.add_fluid(points, velocity=rng.normal(0.0, 0.05, size=(n, 2)))
    return scene


def test_pairs_stay_exact_while_lists_are_reused(rng):
    """After steps without a rebuild and after rebuilds, the visited pairs are exactly
    the brute-force pairs at the current positions."""
    sim = Simulation(drifting_cloud(rng), max_density_error=0)
    built = sim.list_rebuilds
    for _ in range(6):
        sim.step(5, dt=2e-3)  # up to ~0.1 of the skin per step for the fastest particles
        assert_same_pairs(sim, sim.positions())
    rebuilt = sim.list_rebuilds - built
    assert 0 < rebuilt < sim.steps - 1, f"{rebuilt} rebuilds in {sim.steps} steps"


def test_list_overflow_falls_back_to_the_cells(rng, monkeypatch):
    """With room for only 4 entries every list overflows and every particle walks the
    cells of its last rebuild instead: the pairs are still exact, and a dam break
    ends bit for bit where the one with full lists ends (same sums in the same order)."""
    monkeypatch.setattr(neighbours, "list_capacity", lambda scene: 4)
    sim = Simulation(drifting_cloud(rng), max_density_error=0)
    sim.step(12, dt=2e-3)
    assert sim.list_rebuilds < sim.steps
    assert (sim.state.ncount.to_numpy() == -1).mean() > 0.9  # all but isolated particles overflow
    assert_same_pairs(sim, sim.positions())

    scene = taisph.cases.dam_break(dx=0.08)
    scene.neighbour_skin = 0.3
    small = Simulation(scene, deterministic=True)
    small.step(60)
    monkeypatch.undo()
    full = Simulation(scene, deterministic=True)
    full.step(60)
    assert (full.state.ncount.to_numpy()[: full.n_fluid] >= 0).any()
    np.testing.assert_array_equal(small.positions(), full.positions())
    np.testing.assert_array_equal(small.density(), full.density())


def test_dam_break_with_lists_agrees_with_cells_every_step():
    """Lists (skin 0.3 of the support; Lennard-Jones walls kept only within their
    cut-off plus the skin) against the cell walk every step: the same flow to
    round-off after 150 steps (the sums are taken in another order), with the lists
    rebuilt on a fraction of the steps."""
    runs = {}
    for skin in (0.0, 0.3):
        scene = taisph.cases.dam_break(dx=0.04)
        scene.neighbour_skin = skin
        sim = Simulation(scene, deterministic=True, dt=2e-4)
        sim.step(150)
        runs[skin] = sim
    cells, lists = runs[0.0], runs[0.3]
    assert lists.list_rebuilds < 0.5 * lists.steps
    assert np.abs(lists.positions() - cells.positions()).max() < 1e-9  # m, in a 4 m tank
    assert np.abs(lists.density() / cells.density() - 1).max() < 1e-9


def test_skin_out_of_range_is_refused():
    scene = taisph.cases.dam_break(dx=0.1)
    scene.neighbour_skin = -0.1
    with pytest.raises(ValueError, match="neighbour_skin"):
        Simulation(scene)
