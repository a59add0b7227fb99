"""The 3D dam break stands and falls along y, as the 2D one does (x along the flow, y up,
z across): a hydrostatic start along y, and gravity pulling the water down y. (With the
seed's physics, whose Lennard-Jones walls exert no force on the water at t = 0.)

(The 3D sphere of ``drop_on_incline --set dim=3`` is checked the same way in
tests/test_seed_cases.py: it falls freely along -y, exact to 1e-9 m.)
"""

import numpy as np
import pytest

import taisph

G, RHO0, H, DX = 9.81, 1000.0, 2.0, 0.1


@pytest.fixture(scope="module")
def dam_break_3d():
    return taisph.Simulation(taisph.cases.dam_break_3d(dx=DX, seed_physics=True))


def test_column_starts_hydrostatic_along_y(dam_break_3d):
    """At t = 0 the lowest row of fluid particles (y = dx/2) carries the weight of the
    2 m column above it: p = rho0 g (H - dx/2) = 19.13 kPa within 1 % (the inverse
    Tait density makes it exact to round-off); the pressure falls along y, not z."""
    sim = dam_break_3d
    x, p = sim.positions()[sim.fluid], sim.pressure()[sim.fluid]
    floor = np.isclose(x[:, 1], x[:, 1].min())
    assert x[:, 1].min() == pytest.approx(DX / 2)
    assert p[floor] == pytest.approx(RHO0 * G * (H - DX / 2), rel=0.01)
    top = np.isclose(x[:, 1], x[:, 1].max())
    assert p[top] == pytest.approx(RHO0 * G * DX / 2, rel=0.01)


def test_water_falls_along_minus_y_as_in_2d():
    """At t = 0 no wall pushes (the water starts r0 = dx/2 from the Lennard-Jones
    walls, where their force is zero) and the pressure forces cancel in the sum, so
    the centre of mass accelerates at g along -y: after the first step the mean
    velocity is -g t along y within 2 % (measured 1.3 %), with mean v_x below 2 % of
    g t (measured 1.3 %) and mean v_z below 1e-9 g t (symmetry between the side
    walls). Later the walls push back (the left wall carries the column's pressure,
    so the mean v_x grows, as in 2D): over the first 6 steps the mean (v_x, v_y) equals
    the 2D dam break's within 3 % of g t (measured 1.8 %), and v_z stays 0."""
    flows = {}
    for case in ("dam_break", "dam_break_3d"):
        sim = taisph.Simulation(taisph.cases.CASES[case](dx=DX, seed_physics=True))
        flows[case] = []
        for _ in range(6):
            sim.step(1)
            flows[case].append((sim.time, sim.velocities()[sim.fluid].mean(axis=0)))
    t, v = flows["dam_break_3d"][0]
    assert v[1] == pytest.approx(-G * t, rel=0.02)
    assert abs(v[0]) < 0.02 * G * t
    assert abs(v[2]) < 1e-9 * G * t
    for (t2, v2), (t3, v3) in zip(flows["dam_break"], flows["dam_break_3d"]):
        assert t3 == pytest.approx(t2, rel=1e-4)  # adaptive steps, nearly the same
        assert np.abs(v3[:2] / t3 - v2 / t2).max() < 0.03 * G
        assert abs(v3[2]) < 1e-9 * G * t3
