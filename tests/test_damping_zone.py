"""The damping zone (taisph.terms.DampingZone): dv/dt = - r s^2 v inside it, nothing outside."""

import numpy as np
import pytest

import taisph
from taisph.messages import InputError
from taisph.terms import DampingZone


def test_velocity_decays_at_the_zones_rate_and_nowhere_else():
    """Three particles with no other force, forward Euler, dt = 0.01 s, r = 4 /s: before the
    zone nothing changes; halfway in (s = 0.5: r s^2 = 1 /s) and past its end (r) the speed
    falls by (1 - dt r s^2) per step, exactly."""
    scene = taisph.Scene(name="sponge", dim=2, dx=0.1, smoothing_length=0.13, domain=((0, 0), (2, 1)),
                         terms=[DampingZone(damping_start=(1.0, 0.0), damping_direction=(0.5, 0.0),
                                            damping_rate=4.0)], integrator="euler")
    scene.add_fluid([[0.5, 0.5], [1.25, 0.5], [1.8, 0.5]], velocity=(0.0, 0.1))
    sim = taisph.Simulation(scene, dt=0.01)
    with pytest.warns(Warning):  # (the fixed dt is above a stability limit that does not apply here)
        sim.run(0.5, frames=0)
    v = sim.velocities()[:, 1]
    expected = 0.1 * (1 - 0.01 * 4.0 * np.array([0.0, 0.25, 1.0])) ** 50
    assert np.abs(v - expected).max() < 1e-15


def test_a_zone_without_direction_is_refused():
    scene = taisph.Scene(name="sponge", dim=2, dx=0.1, smoothing_length=0.13, domain=((0, 0), (2, 1)),
                         terms=[DampingZone(damping_start=(1.0, 0.0), damping_direction=(0.0, 0.0))])
    scene.add_fluid([[0.5, 0.5]])
    with pytest.raises(InputError, match="damping_direction must not be zero"):
        scene.validate()
