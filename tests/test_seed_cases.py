"""The seed's three scenes (report sec. 6) do what the physics says they should.

Each case runs once at a coarse resolution (module fixtures), recording frames; the
tests assert measured quantities, with the measured values at the time of writing in
the docstrings (docs/seed.md lists them with the commands).
"""

import math

import numpy as np
import pytest

import taisph
from taisph.cases.drop_on_incline import downslope, height_above_plane
from taisph.geometry import inside_triangle
from taisph.validation.seed_scenes import DX_DROP, DX_TWO, DX_WEDGE, G, WEDGE, at, potential_energy, record


# --- dam break over a wedge (resolutions and geometry: taisph/validation/seed_scenes.py) ----
@pytest.fixture(scope="module")
def wedge():
    return record(taisph.cases.dam_break_wedge(dx=DX_WEDGE), 0.9, 6)  # frames every 0.15 s


def test_wedge_flow_runs_up_the_slope(wedge):
    """At t = 0.45 s the water on the wedge's upstream face (the layer within 2 dx of
    it) moves up the slope: mean up-slope speed > 1.5 m/s and mean |normal speed| < 0.5 x
    mean |up-slope speed|: the flow follows the face. Measured 2026-12-07 (`pytest -n 0 -s
    tests/test_seed_cases.py -k wedge_flow` with a print, 21 s for this and the next test):
    4.54 m/s (3.9 quoted before) and 0.19 (0.31 before); the speed's lower bound a third of
    it, the ratio's bar as it was (already within 3x)."""
    sim, snaps = wedge
    s = at(snaps, 0.45)
    fluid = sim.fluid
    x, v = s["x"][fluid], s["v"][fluid]
    t_up, n_up = np.array([1.0, 1.0]) / math.sqrt(2), np.array([-1.0, 1.0]) / math.sqrt(2)
    d = (x - np.array(WEDGE[0])) @ n_up
    layer = (x[:, 0] > WEDGE[0][0]) & (x[:, 0] < WEDGE[1][0]) & (d > 0) & (d < 2 * DX_WEDGE)
    assert layer.sum() >= 10
    vt, vn = v[layer] @ t_up, v[layer] @ n_up
    assert vt.mean() > 1.5, vt.mean()
    assert np.abs(vn).mean() < 0.5 * np.abs(vt).mean()


def test_wedge_flow_goes_over_the_apex(wedge):
    """Water passes the apex (x > 2.5 m): 1.5 % of the fluid by t = 0.6 s (measured 4.4 %
    2026-12-07, the command above; a third of it) and 10 % by 0.9 s (measured 21 %), and by
    0.9 s 5 % has crossed the whole wedge (x > 3 m, measured 13.8 %; these two bars were
    already within 3x: a jet leaves the apex and lands near the right wall; the
    lee side fills after 1.2 s). No particle ever inside the wedge or outside the
    tank; mass exact."""
    sim, snaps = wedge
    fluid = sim.fluid
    assert (at(snaps, 0.6)["x"][fluid, 0] > 2.5).mean() > 0.015
    x = at(snaps, 0.9)["x"][fluid]
    assert (x[:, 0] > 2.5).mean() > 0.10
    assert (x[:, 0] > 3.0).mean() > 0.05
    for s in snaps:
        x = s["x"][fluid]
        assert np.isfinite(x).all()
        assert not inside_triangle(x, *WEDGE).any(), f"a particle entered the wedge at t = {s['t']}"
        assert x[:, 0].min() > 0 and x[:, 0].max() < 4.0 and x[:, 1].min() > 0
        assert s["m"][fluid].sum() == snaps[0]["m"][fluid].sum()


# --- drop on an incline ------------------------------------------------------------------


@pytest.fixture(scope="module")
def drop():
    return record(taisph.cases.drop_on_incline(dx=DX_DROP), 0.5, 10)  # frames every 0.05 s


def test_drop_falls_freely_until_it_touches(drop):
    """Before contact (t = sqrt(2 fall / g) = 0.247 s) the drop is in free fall: its
    centre of mass follows y0 - g t^2 / 2 to 1e-9 m and its density stays rho0 to 1e-12
    (no relative motion, no pressure); at t = 0.2 s it is still > 0.05 m from the plane."""
    sim, snaps = drop
    fluid = sim.fluid
    y0 = snaps[0]["x"][fluid, 1].mean()
    for s in snaps:
        if s["t"] <= 0.2:
            assert abs(s["x"][fluid, 1].mean() - (y0 - 0.5 * G * s["t"] ** 2)) < 1e-9
            assert np.abs(s["rho"][fluid] / 1000.0 - 1).max() < 1e-12
    assert height_above_plane(at(snaps, 0.2)["x"][fluid]).min() > 0.05


def test_drop_reaches_plane_spreads_and_slides_down(drop):
    """After contact the water touches the plane (closest particle within dx of it by
    0.3 s), never crosses it (every particle > r0/4 above it and above the floor),
    spreads along it (extent along the slope > 2.5 x the diameter at 0.45 s; measured
    3.6 x), and its centre of mass moves down-slope, speeding up: the down-slope
    velocity gained from 0.3 s to 0.5 s is between half of and the frictionless value
    g sin 45 deg x 0.2 s = 1.39 m/s (measured 1.06 m/s: the bumpy wall-particle plane
    acts like friction)."""
    sim, snaps = drop
    fluid = sim.fluid
    r0 = DX_DROP / 2
    assert height_above_plane(at(snaps, 0.3)["x"][fluid]).min() < DX_DROP
    for s in snaps:
        x = s["x"][fluid]
        assert height_above_plane(x).min() > 0.25 * r0
        assert x[:, 1].min() > 0
        assert s["m"][fluid].sum() == snaps[0]["m"][fluid].sum()
    extent = np.ptp(downslope(at(snaps, 0.45)["x"][fluid]))
    assert extent > 2.5 * 0.4
    u = {t: downslope(at(snaps, t)["v"][fluid]).mean() for t in (0.3, 0.5)}
    com = [downslope(s["x"][fluid]).mean() for s in snaps if s["t"] >= 0.25]
    assert np.all(np.diff(com) > 0)
    frictionless = G * math.sin(math.pi / 4) * 0.2
    assert 0.5 * frictionless < u[0.5] - u[0.3] <= frictionless * 1.01


def test_drop_3d_builds_and_falls():
    """The 3D sphere: same geometry extruded, free fall for 50 steps exact to 1e-9 m."""
    scene = taisph.cases.drop_on_incline(dim=3, dx=0.08)
    assert scene.dim == 3 and scene.n_fluid > 50
    sim = taisph.Simulation(scene)
    y0 = sim.positions()[sim.fluid, 1].mean()
    sim.step(50)
    assert abs(sim.positions()[sim.fluid, 1].mean() - (y0 - 0.5 * G * sim.time**2)) < 1e-9
    z = sim.positions()[sim.fluid, 2]
    assert abs(z.mean() - 0.4) < 1e-9  # centred between the side walls, nothing pushes it across


# --- two fluids ----------------------------------------------------------------------------


@pytest.fixture(scope="module")
def two_fluids():
    runs = {}
    for ratio in (2.0, 0.5):  # heavy on top (Rayleigh-Taylor), and the stable control
        runs[ratio] = record(taisph.cases.two_fluids(dx=DX_TWO, density_ratio=ratio), 1.5, 3)
    return runs


def test_heavy_fluid_sinks_and_releases_potential_energy(two_fluids):
    """Heavy on top (ratio 2): by 1.5 s the heavy fluid's centre of mass has fallen
    > 0.04 m (measured 0.066), the potential energy has dropped by > 5 % of what full
    inversion would release (measured 7.9 %), a heavy finger reaches 0.3 m below the
    mid-height interface and light fluid rises 0.25 m above it (measured 0.40, 0.34).
    The stable control (light on top, ratio 0.5) with the same walls and perturbation
    lowers its upper fluid by less than a third as much (measured 0.010 m, 0.15 x): the
    fall is the instability, not the settling of the Lennard-Jones walls."""
    sim, snaps = two_fluids[2.0]
    fluid = sim.fluid
    heavy, light = fluid & (sim.materials() == 0), fluid & (sim.materials() == 1)
    first, last = snaps[0], snaps[-1]
    fall = first["x"][heavy, 1].mean() - last["x"][heavy, 1].mean()
    assert fall > 0.04
    W, H, rho_h, rho_l = 1.0, 2.0, 1000.0, 500.0
    full_inversion = G * W * (rho_h - rho_l) * (H / 2) ** 2  # continuum: layers swapped
    released = potential_energy(first, fluid) - potential_energy(last, fluid)
    assert released > 0.05 * full_inversion
    assert last["x"][heavy, 1].min() < H / 2 - 0.3
    assert last["x"][light, 1].max() > H / 2 + 0.25
    sim_c, snaps_c = two_fluids[0.5]
    upper_c = sim_c.fluid & (sim_c.materials() == 0)
    fall_control = snaps_c[0]["x"][upper_c, 1].mean() - snaps_c[-1]["x"][upper_c, 1].mean()
    assert fall_control < fall / 3


def test_no_material_created_or_lost(two_fluids):
    """Per material: the particle count, every particle's material and its total mass
    are exactly unchanged; every particle stays in the box; densities stay within 5 %
    of their own material's rho0 (measured 2.3 %: the interface stays sharp, no light
    particle takes the heavy density or the reverse)."""
    sim, snaps = two_fluids[2.0]
    fluid = sim.fluid
    for s in snaps:
        np.testing.assert_array_equal(s["mat"], snaps[0]["mat"])
        for k in (0, 1):
            sel = fluid & (s["mat"] == k)
            assert s["m"][sel].sum() == snaps[0]["m"][sel].sum()
        x = s["x"][fluid]
        assert x[:, 0].min() > 0 and x[:, 0].max() < 1.0 and x[:, 1].min() > 0 and x[:, 1].max() < 2.5
        rho0 = np.where(s["mat"][fluid] == 0, 1000.0, 500.0)
        assert np.abs(s["rho"][fluid] / rho0 - 1).max() < 0.05


@pytest.mark.parametrize("case,params", [("dam_break_wedge", {"dx": 0.1}), ("drop_on_incline", {"dx": 0.05}),
                                         ("two_fluids", {"dx": 0.1})])
def test_frames_open_in_vtk(tmp_path, case, params):
    """Each scene's frames open with VTK's XML reader (as ParaView reads them), with every
    fluid particle, the walls in their own file, and (two_fluids) both materials."""
    vtkio = pytest.importorskip("vtkmodules.vtkIOXML")
    from vtkmodules.util.numpy_support import vtk_to_numpy

    from taisph.run import vtk

    scene = taisph.cases.CASES[case](**params)
    sim = taisph.Simulation(scene)
    sim.run(3 * sim.dt, frames=1, out=tmp_path)
    entries = vtk.read_pvd(tmp_path / f"{case}.pvd")
    assert len([e for e in entries if e[1] == 0]) == 2 and any(e[1] == 1 for e in entries)
    for _, part, name in entries:
        reader = vtkio.vtkXMLUnstructuredGridReader()
        reader.SetFileName(str(tmp_path / name))
        reader.Update()
        grid = reader.GetOutput()
        assert grid.GetNumberOfPoints() == (scene.n_fluid if part == 0 else scene.n_wall)
        if part == 0:
            materials = set(vtk_to_numpy(grid.GetPointData().GetArray("material")).tolist())
            assert materials == ({0, 1} if case == "two_fluids" else {0})
