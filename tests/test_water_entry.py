"""Water entry (issue 28, check 6, a demonstration; cases/water_entry.py): a cylinder of
half the water's density (D = 0.11 m) enters still water at sqrt(2 g 0.5 m) = 3.13 m/s
(Greenhow & Lin 1983), plunges and comes to float half submerged: no fluid particle lost
or inside the cylinder, and at the end it floats at Archimedes' height, nearly at rest."""

import numpy as np
import pytest

import taisph
from taisph.cases.water_entry import expected, water_entry


def entry_run(dx, t_end, every=0.01, **params):
    """Sample every `every` s: the fluid's count, finiteness, the nearest fluid particle's
    distance from the cylinder's centre; the cylinder's height and velocity."""
    scene = water_entry(dx=dx, t_end=t_end, **params)
    sim = taisph.Simulation(scene)
    fluid = sim.fluid.copy()
    nearest, heights, times, speeds = [], [], [], []
    for k in range(int(round(t_end / every)) + 1):
        if k:
            sim.run(k * every, frames=0)
        x, v = sim.positions(), sim.velocities()
        assert np.isfinite(x).all() and np.isfinite(v).all() and np.isfinite(sim.density()).all(), sim.time
        assert (sim.fluid == fluid).all(), f"a fluid particle was removed at t = {sim.time:g} s"
        body = sim.bodies()["cylinder"]
        nearest.append(np.linalg.norm(x[fluid] - body.position, axis=1).min())
        heights.append(body.position[1])
        speeds.append(np.linalg.norm(body.velocity))
        times.append(sim.time)
    sim.close()
    return np.array(times), np.array(heights), np.array(speeds), np.array(nearest)


def test_expected_numbers():
    """The lattice disc (dx = 0.005 m: 384 particles, its area 1.0 % above pi D^2 / 4)
    floats with its centre at the water's level, raised by half its area over the tank's
    width."""
    ex = expected()
    assert ex["particles"] == 384 and ex["area"] == pytest.approx(np.pi * 0.055**2, rel=0.015)
    assert ex["centre"] == pytest.approx(ex["level"], abs=1e-12)
    assert ex["level"] == pytest.approx(0.5 + ex["area"] / 2, abs=1e-12)


def test_a_cylinder_enters_the_water_quick():
    """Coarse and small (dx = 0.01 m, a 0.5 m x 0.25 m tank, 0.6 s): the cylinder enters at
    3.13 m/s, sinks, stops and rises; no fluid particle lost, none inside the cylinder
    (nearer its centre than D/2 - dx/2), the state finite."""
    dx = 0.01
    t, y, _, nearest = entry_run(dx, 0.6, tank_width=0.5, depth=0.25)
    assert nearest.min() > 0.055 - dx / 2, (nearest.min(), t[np.argmin(nearest)])
    deepest = int(np.argmin(y))
    assert y[deepest] < 0.25 - 0.055, "the cylinder did not sink below the surface"
    assert 0 < deepest < len(y) - 1 and y[-1] > y[deepest] + dx, "it did not stop and rise"


@pytest.mark.slow
def test_a_cylinder_dropped_into_water_comes_to_float():
    """Issue 28, check 6, dx = 0.005 m (D/dx = 22), 1 m x 0.5 m tank, to 4 s: no fluid
    particle lost, none inside the cylinder, finite; at the end its centre is within
    0.5 dx of Archimedes' height and it is nearly at rest."""
    dx = 0.005
    t, y, speed, nearest = entry_run(dx, 4.0)
    ex = expected(dx=dx)
    assert nearest.min() > 0.055 - dx / 2, (nearest.min(), t[np.argmin(nearest)])
    assert abs(y[-1] - ex["centre"]) < 0.5 * dx, (y[-1], ex["centre"])
    assert speed[-1] < 0.05, speed[-1]
