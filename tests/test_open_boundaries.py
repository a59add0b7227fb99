"""Open boundaries (taisph.terms.open_boundary): a stream through them is kept exactly,
mass is accounted for to round-off, the pressure-driven and velocity-driven channels
match Poiseuille's parabola, a reversing flow keeps its mass and its spacing, and bad
zones are refused before anything is built."""

import math

import numpy as np
import pytest

import taisph
from taisph.geometry import lattice
from taisph.messages import InputError
from taisph.scene import Material, Scene
from taisph.terms import (Continuity, DensityDiffusion, DensityRelaxation, LaminarViscosity, PressureGradient,
                          SummationDensity)

DX, H, L = 5e-5, 1e-3, 4e-3
C0 = 0.125


def tait_density(p, rho0=1000.0, c0=C0):
    return rho0 * (1.0 + 7.0 * p / (rho0 * c0**2)) ** (1.0 / 7.0)


def stream(u=0.01, inlet=None, outlet=None, delta=0.1, c0=C0, pressure=0.1, summation=False):
    """Water filling [0, L] x [0, H], periodic across (no walls), moving at u along x
    at `pressure` (Pa), with an inlet zone at x = 0 and an outlet at x = L; its density
    by the continuity equation (with density diffusion delta) or by summation."""
    if summation:
        terms = [SummationDensity(lattice=True), PressureGradient()]
    else:
        terms = [Continuity(), PressureGradient()] + ([DensityDiffusion(delta=delta, hydrostatic=False)] if delta else [])
    scene = Scene(name="stream", dim=2, dx=DX, smoothing_length=1.3 * DX, domain=((0, 0), (L, H)),
                  materials=[Material("water", 1000.0, c0, 7.0)], terms=terms, kernel="wendland",
                  periodic=(False, True))
    rho = tait_density(pressure, c0=c0)
    scene.add_fluid(lattice((0, 0), (L, H), DX), density=rho, mass=rho * DX**2, velocity=(u, 0.0))
    scene.add_open_boundary("inlet", at=(0, 0), to=(0, H), **(inlet or {"pressure": 0.1}))
    scene.add_open_boundary("outlet", at=(L, 0), to=(L, H), **(outlet or {"pressure": 0.1}))
    return scene


def startup_poiseuille(y, t, u_max, nu=2.5e-7):
    """Start-up of plane Poiseuille flow from rest under a constant pressure gradient
    (series solution; Morris et al. 1997, eq. 21, in terms of u_max)."""
    steady = 4.0 * y * (H - y) / H**2
    decay = sum(32.0 / (math.pi**3 * n**3) * np.sin(n * math.pi * y / H) * math.exp(-(n * math.pi) ** 2 * nu * t / H**2)
                for n in range(1, 400, 2))
    return u_max * (steady - decay)


def test_a_uniform_stream_through_two_pressure_zones_is_kept_to_round_off():
    """Water at 0.01 m/s and 0.1 Pa between two zones prescribing 0.1 Pa: nothing may
    change but positions. Measured (2026-12-07) after 0.2 s (1 662 steps): velocity within
    6.1e-14 m/s of the stream's (bar 2e-13, was 1e-11), pressure within 1.9e-13 Pa of 0.1
    (bar 6e-13, was 1e-11), fluid count constant; the mass let in is the 40 columns the
    stream carries across the inlet in 0.2 s (u t / dx = 40), half the fluid's: 0.5 m0 within
    5e-14 (measured 1.7e-14; was > 0.3 m0); fluid mass = initial + in - out to round-off."""
    sim = taisph.Simulation(stream())
    n0, m0 = sim.n_fluid, sim.total_mass()
    sim.run(0.2, frames=0)
    v, p = sim.velocities()[sim.fluid], sim.pressure()[sim.fluid]
    mass_in, mass_out = sim.open_boundary_mass()
    print(f"u {np.abs(v[:, 0] - 0.01).max():.3g}, v {np.abs(v[:, 1]).max():.3g}, p {np.abs(p - 0.1).max():.3g}, "
          f"in {mass_in / m0 - 0.5:.3g} m0 + 0.5, steps {sim.steps}")
    assert np.abs(v[:, 0] - 0.01).max() < 2e-13 and np.abs(v[:, 1]).max() < 2e-13
    assert np.abs(p - 0.1).max() < 6e-13
    assert mass_in / m0 == pytest.approx(0.5, rel=5e-14)  # 0.002 m of 0.004 m crossed
    assert sim.n_fluid == n0
    assert sim.total_mass() == pytest.approx(m0 + mass_in - mass_out, rel=1e-12)


def test_a_uniform_stream_with_summation_density_is_kept():
    """The same stream with the density summed over the lattice (normalised by the
    kernel's lattice sum, 1.0105 here) and the buffers keeping their imposed density:
    the pressure stays 0.1 Pa and the stream uniform (measured 2026-12-07 after 0.2 s, 1 662
    steps: velocity within 6.3e-14 m/s of the stream's, bar 2e-13 (was 1e-11); pressure within
    8.6e-12 Pa, bar 3e-11 (was 1e-9)). Without the normalisation the sum reads 1.05 % too
    dense: a pressure of 0.276 Pa against the zones' 0.1."""
    sim = taisph.Simulation(stream(summation=True))
    n0, m0 = sim.n_fluid, sim.total_mass()
    sim.run(0.2, frames=0)
    v, p = sim.velocities()[sim.fluid], sim.pressure()[sim.fluid]
    print(f"u {np.abs(v[:, 0] - 0.01).max():.3g}, v {np.abs(v[:, 1]).max():.3g}, p {np.abs(p - 0.1).max():.3g}, "
          f"steps {sim.steps}")
    assert np.abs(v[:, 0] - 0.01).max() < 2e-13 and np.abs(v[:, 1]).max() < 2e-13
    assert np.abs(p - 0.1).max() < 3e-11
    assert sim.n_fluid == n0
    mass_in, mass_out = sim.open_boundary_mass()
    assert sim.total_mass() == pytest.approx(m0 + mass_in - mass_out, rel=1e-12)


def test_water_at_rest_between_equal_pressures_stays_at_rest():
    """At rest after 0.1 s to round-off: |v| < 1e-15 m/s (measured 2.4e-16; was 1e-12); nothing
    crossed a face."""
    sim = taisph.Simulation(stream(u=0.0))
    sim.run(0.1, frames=0)
    print(f"|v| {np.abs(sim.velocities()).max():.3g}")
    assert np.abs(sim.velocities()).max() < 1e-15
    assert sim.open_boundary_mass() == (0.0, 0.0)


def test_a_velocity_inlet_feeds_a_stream_at_its_speed():
    """Inlet prescribing 0.01 m/s, outlet prescribing 0.1 Pa (the inlet's pressure is
    extrapolated): the stream keeps 0.01 m/s to round-off. Measured (2026-12-07) after 0.3 s:
    mean 2.6e-14 of 0.01 m/s off (bar 1e-13; was 2e-3), spread (std) 1.8e-12 m/s (bar 5e-12;
    was 1e-4)."""
    sim = taisph.Simulation(stream(inlet={"velocity": 0.01}))
    sim.run(0.3, frames=0)
    u = sim.velocities()[sim.fluid, 0]
    print(f"mean {u.mean() / 0.01 - 1:.3g}, std {u.std():.3g}")
    assert u.mean() == pytest.approx(0.01, rel=1e-13) and u.std() < 5e-12


@pytest.mark.parametrize("inlet", ["pressure", pytest.param("velocity", marks=pytest.mark.slow)])
def test_the_open_channel_reaches_poiseuilles_parabola(inlet):
    """The case `channel` at H/20 (CI; the bar is H/40, test below): at t = 1.5 s (3.7
    time constants) the profile across the middle third against the start-up solution
    (pressure inlet) or the steady parabola the inlet prescribes (velocity inlet).
    Measured (2026-12-07): L2 error 1.73 % of u_max (pressure; bar 3 %, the issue's) and
    0.44 % (velocity; bar 1.3 %, was 3 %); fluid count -0.25 % for both (bar 0.75 %, was
    1 %); mass balance to round-off."""
    scene = taisph.cases.channel(dx=DX, inlet=inlet, t_end=1.5)
    sim = taisph.Simulation(scene)
    n0, m0 = sim.n_fluid, sim.total_mass()
    sim.run(frames=0)
    x, u = sim.positions()[sim.fluid], sim.velocities()[sim.fluid, 0]
    middle = np.abs(x[:, 0] - L / 2) < L / 6
    u_max = H**2 * 0.1 / (8 * 2.5e-4 * L)
    exact = (startup_poiseuille(x[middle, 1], sim.time, u_max) if inlet == "pressure"
             else u_max * 4 * x[middle, 1] * (H - x[middle, 1]) / H**2)
    error = np.sqrt(np.mean((u[middle] - exact) ** 2)) / u_max
    print(f"error {error:.4f}, count {sim.n_fluid / n0 - 1:.4f}")
    assert error < (0.03 if inlet == "pressure" else 0.013)
    assert abs(sim.n_fluid - n0) <= 0.0075 * n0
    mass_in, mass_out = sim.open_boundary_mass()
    assert sim.total_mass() == pytest.approx(m0 + mass_in - mass_out, rel=1e-12)


@pytest.mark.slow
def test_the_open_channel_at_h_over_40_meets_the_bar():
    """Issue 27's check 1 at H/dx = 40, t = 3 s (7.4 time constants). Measured (2026-12-07,
    215 s): profile L2 error against the start-up solution at three sections 0.54, 0.29,
    0.52 % of u_max (bar 1.6 %, 3x the largest; the issue's is 3 %); the flow in and out over
    the last second, by the zones' mass counters, equal within 0.032 % (bar 0.1 %; was 1 %);
    fluid count -0.19 % (bar 0.6 %; was 1 %)."""
    sim = taisph.Simulation(taisph.cases.channel(dx=2.5e-5, t_end=2.0))
    n0 = sim.n_fluid
    sim.run(frames=0)
    in0, out0 = sim.open_boundary_mass()
    sim.run(3.0, frames=0)
    in1, out1 = sim.open_boundary_mass()
    x, u = sim.positions()[sim.fluid], sim.velocities()[sim.fluid, 0]
    u_max = 0.0125
    errors = []
    for section in (0.5e-3, 2e-3, 3.5e-3):
        near = np.abs(x[:, 0] - section) < 2.5e-5
        errors.append(np.sqrt(np.mean((u[near] - startup_poiseuille(x[near, 1], sim.time, u_max)) ** 2)) / u_max)
    print(f"errors {errors}, in - out {(in1 - in0) / (out1 - out0) - 1:.4g}, count {sim.n_fluid / n0 - 1:.4g}")
    assert abs((in1 - in0) - (out1 - out0)) <= 0.001 * (in1 - in0)
    assert max(errors) < 0.016
    assert abs(sim.n_fluid - n0) <= 0.006 * n0


NU = 2.5e-7  # kinematic viscosity of check 1's fluid (mu = 2.5e-4 Pa s, rho 1000 kg/m^3)


def reversing(periods, relaxation_time=None, viscous=True):
    """A stream whose inlet velocity is 0.01 sin(2 pi t / T) m/s (T = 0.5 s: it moves
    water 16 dx each way, far more than the buffer's depth), outlet at 1 Pa with c0 =
    0.5 m/s: the column's acceleration needs a pressure swing rho L dU/dt = 0.5 Pa, which
    the 1 Pa keeps above zero (a swing into tension tore the column off the inlet at
    c0 = 0.125 m/s and 0.1 Pa). Both zones see the flow reverse. The fluid is check 1's
    (nu = 2.5e-7 m^2/s: Re = U H / nu = 40) unless `viscous` is False: inviscid, where the
    outlet takes water in as one stream (docs/open_boundaries.md, "Inflow through an
    extrapolated zone")."""
    T, c0 = 0.5, 0.5
    t = np.linspace(0.0, T, 33)
    scene = stream(u=0.0, inlet={"velocity": np.stack([t, 0.01 * np.sin(2 * np.pi * t / T)], axis=1), "period": T},
                   outlet={"pressure": 1.0}, c0=c0, pressure=1.0)
    scene.t_end = periods * T
    if relaxation_time is not None:
        scene.terms.append(DensityRelaxation(relaxation_time=relaxation_time))
    if viscous:
        scene.terms.append(LaminarViscosity(nu=NU))
    return scene, T


def reversing_run(periods, relaxation_time=None, viscous=True):
    """Run :func:`reversing`; the period means of the fluid mass (16 samples a period),
    the closest two fluid particles ever seen at the samples, and the zones' mass in and out."""
    scene, T = reversing(periods, relaxation_time, viscous)
    sim = taisph.Simulation(scene, deterministic=True)  # (the serial sort; below 60 000 particles in any case)
    masses, closest = [], np.inf
    for k in range(1, 16 * periods + 1):
        sim.run(k * T / 16, frames=0)
        masses.append(sim.total_mass())
        x = sim.positions()[sim.kinds() == 0]
        d = x[:, None, :] - x[None, :, :]
        d[..., 1] -= H * np.round(d[..., 1] / H)  # periodic across
        r = np.sqrt((d**2).sum(-1)) + np.eye(len(x))
        closest = min(closest, r.min())
    return np.mean(np.reshape(masses, (periods, 16)), axis=1), closest, sim.open_boundary_mass()


REVERSING_WALK = ("measured 2026-12-07 (AMD EPYC, 246 s): inviscid without DensityRelaxation the period-mean "
                  "mass walks 1.273 % from the first period's over 10 periods (0.5 % bar) and a pair comes "
                  "0.441 dx close (0.5 dx bar); over 2 periods already 0.812 % (0.624 dx)")


@pytest.mark.parametrize("periods, relaxation_time, viscous", [
    (2, None, True), (2, 0.01, True), (2, 0.01, False),
    *[pytest.param(10, tau, viscous, marks=pytest.mark.slow) for tau, viscous in [(None, True), (0.01, True),
                                                                                   (0.01, False)]],
    pytest.param(10, None, False, marks=[pytest.mark.slow, pytest.mark.xfail(strict=True, reason=REVERSING_WALK)]),
])
def test_a_reversing_flow_keeps_its_mass_and_its_spacing(periods, relaxation_time, viscous):
    """Issue 27's check 4: the period means of the fluid mass within 0.5 % of the first
    period's over 10 periods, and no two fluid particles closer than 0.5 dx at any
    sample. The fluid mass at one instant is coarse (particles cross a face a whole column
    at a time, 20 here, 1.25 % of the fluid); its mean over a period (16 samples) is not.
    Both zones must have let water in and out (> 0.3 of the fluid's mass each way: a
    precondition, not a measurement; measured 1.59-1.62 over 2 periods). Measured at H/dx
    = 20 (this test; 2 periods 2026-12-07, 10 periods 2026-12-06/07, AMD EPYC), 2 / 10
    periods: 0.207 % / 0.21 % and 0.947 dx; with DensityRelaxation (tau = 0.01 s, 77 h /
    c0; the evolved density pulled towards the summed one gives the particle count a
    restoring force, taisph/terms/density_relaxation.py) 0.125 % / 0.125 % and 0.946 dx.
    At H/dx = 40 (dx halved) only with the term: 0.262 % and 0.502 dx (2 780 s on one
    thread); without it 0.48 % by the fourth period and a pair 0.473 dx apart in the third.
    Inviscid, the outlet taking water in as a uniform stream: with the term 0.164 % / 0.207
    % and 0.551 / 0.503 dx; without it the known miss, a strict xfail (REVERSING_WALK:
    1.273 % and 0.441 dx over 10 periods; docs/open_boundaries.md). The runs are
    deterministic (serial cell sort): on one machine they repeat bit for bit, at 1 or 2
    threads alike (checked 2026-12-07); another processor's round-off may walk the mass
    elsewhere (0.60 % on a Xeon, 2.07 % on an EPYC, 2026-12-06, older code), which is why
    no bar here was ever widened to hold a walk: the walk is the xfail."""
    means, closest, (mass_in, mass_out) = reversing_run(periods, relaxation_time, viscous)
    print(f"mass {np.abs(means / means[0] - 1.0).max():.4%}, closest {closest / DX:.4f} dx, "
          f"in {mass_in / means[0]:.4f}, out {mass_out / means[0]:.4f}")
    assert np.abs(means / means[0] - 1.0).max() <= 0.005
    assert closest >= 0.5 * DX
    assert mass_in > 0.3 * means[0] and mass_out > 0.3 * means[0]


def test_water_entering_a_zone_that_extrapolates_the_velocity_without_viscosity_is_one_stream():
    """Without viscosity nothing sets the profile of an inflow (Euler's equations need it
    given): the outlet's buffer lines, each reading its own speed back from the water it had
    let in, ran apart into jets (3.6 times the stream's speed at H/dx = 40). Such a zone now
    lets water in at its mean speed, and a viscous scene keeps each line's own. At the peak
    of the reversing stream's first inflow (t/T = 0.75, the inlet drawing 0.01 m/s out) the
    whole column moves as one: the outlet's lines at 0.01 m/s within 5 % (measured
    2026-12-07: 0.009776 m/s, 2.2 % low), all at one speed, exactly (measured: spread 0,
    before 0.0087 m/s at H/dx = 40), and straight in (no tangential speed, exactly)."""
    from taisph.engine import assembly, kernels

    scene, T = reversing(1, viscous=False)
    assembly._cache.clear()
    kernels.TRACED.clear()
    sim = taisph.Simulation(scene)
    sim.run(0.75 * T, frames=0)
    assert ("open_boundaries", "uniform inflow") in kernels.TRACED
    x, v = sim.positions(), sim.velocities()
    lines = sim.buffer & (x[:, 0] > L)
    print(f"mean {-v[lines, 0].mean():.5g}, std {v[lines, 0].std():.3g}, v {np.abs(v[lines, 1]).max():.3g}")
    assert -v[lines, 0].mean() == pytest.approx(0.01, rel=0.05)
    assert np.ptp(v[lines, 0]) == 0.0 and np.abs(v[lines, 1]).max() == 0.0
    assembly._cache.clear()
    kernels.TRACED.clear()
    taisph.Simulation(reversing(1)[0]).step(1)  # viscous: each line its own speed
    assert ("open_boundaries", "uniform inflow") not in kernels.TRACED


def test_a_scene_without_zones_compiles_none_of_their_code():
    from taisph.engine import assembly, kernels

    assembly._cache.clear()
    kernels.TRACED.clear()
    taisph.Simulation(taisph.cases.poiseuille(dx=2.5e-4)).step(1)
    assert not {t for t in kernels.TRACED if t[0] == "open_boundaries"}
    assembly._cache.clear()
    kernels.TRACED.clear()
    taisph.Simulation(stream()).step(1)
    assert {("open_boundaries", "buffer pass"), ("open_boundaries", "zone bookkeeping")} <= kernels.TRACED


def fluid_block():
    scene = Scene(name="bad", dim=2, dx=DX, smoothing_length=1.3 * DX, domain=((0, 0), (L, H)),
                  materials=[Material("water", 1000.0, C0, 7.0)], terms=[Continuity(), PressureGradient()],
                  kernel="wendland")
    scene.add_fluid(lattice((0, 0), (L, H), DX))
    return scene


@pytest.mark.parametrize("kwargs, message", [
    (dict(at=(L / 2, 0), to=(L / 2, H), normal=(1, 0)), "fluid particles lie inside its buffer zone"),
    (dict(at=(L / 2, 0), to=(L / 2, H)), "fluid on neither side of the face, or on both"),
    (dict(at=(0, 0), to=(0, H), normal=(-1, 0)), "points out of the fluid"),
    (dict(at=(-1e-3, 0), to=(-1e-3, H)), "cannot be found from the fluid"),
    (dict(at=(-1e-3, 0), to=(-1e-3, H), normal=(1, 0)), "no fluid lies within"),
    (dict(at=(0, 0), to=(0, H), normal=(1, 1)), "not perpendicular"),
    (dict(at=(0, 0), to=(0, H), layers=1), "less than the kernel support"),
    (dict(at=(0, 0), to=(0, 1.01e-3)), "not a whole number of particle spacings"),
    (dict(at=(0, 0), to=(0, H), profile="square"), "profile 'square'"),
    (dict(at=(0, 0), to=(0, H), velocity=lambda x, t: np.full(len(x), np.nan)), "is not finite"),
    (dict(at=(0, 0), to=(0, H), velocity=np.array([[0.0, 0.0], [0.1, 1.0], [0.05, 1.0]])), "must increase"),
    (dict(at=(0, 0), to=(0, H), pressure=float("inf")), "pressure must be a finite number"),
    (dict(name="in let", at=(0, 0), to=(0, H)), "its name must be a word"),
])
def test_bad_zones_are_refused_naming_the_zone(kwargs, message):
    scene = fluid_block()
    kwargs = {"name": "inlet", **kwargs}
    with pytest.raises(InputError, match="open boundary") as err:
        scene.add_open_boundary(**kwargs)
    assert message in str(err.value)
    assert scene.open_boundaries == [] or "velocity" in kwargs  # a refused zone adds nothing


def test_overlapping_zones_walls_in_a_zone_and_dfsph_are_refused():
    scene = fluid_block()
    scene.add_open_boundary("a", at=(0, 0), to=(0, H))
    with pytest.raises(InputError, match="another open boundary has that name"):
        scene.add_open_boundary("a", at=(L, 0), to=(L, H))
    with pytest.raises(InputError, match="overlaps that of open boundary 'a'"):
        scene.add_open_boundary("b", at=(0, 0), to=(0, H / 2), normal=(1, 0))
    scene.add_walls(np.array([[-2 * DX, H / 2]]))
    with pytest.raises(InputError, match="wall particles lie inside its buffer zone"):
        scene.validate()
    scene = fluid_block()
    scene.add_open_boundary("a", at=(0, 0), to=(0, H))
    scene.solver = "dfsph"
    with pytest.raises(InputError, match="WCSPH solver only"):
        scene.validate()
    scene.solver, scene.neighbour_skin = "wcsph", 0.3
    with pytest.raises(InputError, match="without neighbour lists"):
        scene.validate()


def test_a_channel_resumes_from_a_checkpoint_bit_for_bit(tmp_path):
    """Particles created and retired, ids past the scene's, the mass counters: all in
    the checkpoint. A run stopped and resumed ends where an unbroken one does."""
    scene = stream(inlet={"velocity": 0.01})
    whole = taisph.Simulation(scene, deterministic=True)
    whole.run(0.02, frames=0)  # (the same steps: a run's end shortens the step that reaches it)
    whole.run(0.04, frames=0)  # (0.04 s: a column of particles crossed each face, ids past the scene's)
    half = taisph.Simulation(stream(inlet={"velocity": 0.01}), deterministic=True)
    half.run(0.02, frames=0)
    half.save_checkpoint(tmp_path / "cp")
    resumed = taisph.Simulation.from_checkpoint(tmp_path / "cp")
    resumed.run(0.04, frames=0)
    assert resumed.n == whole.n
    assert np.array_equal(resumed.ids(), whole.ids())
    assert np.array_equal(resumed.positions(), whole.positions())
    assert resumed.open_boundary_mass() == whole.open_boundary_mass()


def stream_3d(inlet):
    """The stream of :func:`stream` in 3D (2 x 1 x 1 mm, dx = 0.1 mm), periodic in y and z."""
    dx, h = 1e-4, 1e-3
    scene = Scene(name="stream3d", dim=3, dx=dx, smoothing_length=1.3 * dx, domain=((0, 0, 0), (2 * h, h, h)),
                  materials=[Material("water", 1000.0, C0, 7.0)], kernel="wendland", periodic=(False, True, True),
                  terms=[Continuity(), PressureGradient(), DensityDiffusion(delta=0.1, hydrostatic=False)])
    rho = tait_density(0.1)
    scene.add_fluid(lattice((0, 0, 0), (2 * h, h, h), dx), density=rho, mass=rho * dx**3, velocity=(0.01, 0, 0))
    scene.add_open_boundary("inlet", at=(0, 0, 0), to=(0, h, h), **inlet)
    scene.add_open_boundary("outlet", at=(2 * h, 0, 0), to=(2 * h, h, h), pressure=0.1)
    return scene


def test_a_3d_stream_through_rectangular_zones_is_kept_to_round_off():
    """To round-off over 0.03 s (125 steps; a column crossed each face): velocity within
    1e-15 m/s of the stream's (measured 2026-12-07: 3.2e-16; was 1e-12), fluid count
    constant, mass in = out."""
    sim = taisph.Simulation(stream_3d({"velocity": 0.01}))
    n0 = sim.n_fluid
    sim.run(0.03, frames=0)
    v = sim.velocities()[sim.fluid]
    print(f"u {np.abs(v[:, 0] - 0.01).max():.3g}, v {np.abs(v[:, 1:]).max():.3g}, steps {sim.steps}")
    assert np.abs(v[:, 0] - 0.01).max() < 1e-15 and np.abs(v[:, 1:]).max() < 1e-15
    assert sim.n_fluid == n0 and sim.open_boundary_mass()[0] == sim.open_boundary_mass()[1] > 0


@pytest.mark.parametrize("dim", [2, 3])
def test_a_parabolic_inlet_gives_each_buffer_particle_its_profile_speed(dim):
    """The prescribed table, interpolated at the buffer particles after a step: 4 s (1 - s)
    across the face in 2D, its product over both axes in 3D (sampled at 65 and 17 points
    per axis: linear interpolation of 4 s (1 - s) errs by at most ds^2 = (1/64)^2 and
    (1/16)^2 of U per axis; measured 2026-12-07: 2.3e-4 U in 2D against the bound 2.4e-4 U,
    6.8e-3 U in 3D against 7.8e-3 U)."""
    scene = stream_3d({"velocity": 0.02, "profile": "parabolic"}) if dim == 3 else stream(
        inlet={"velocity": 0.02, "profile": "parabolic"})
    sim = taisph.Simulation(scene)
    sim.step(1)
    inlet = sim.buffer & (sim.positions()[:, 0] < 0)
    x, u = sim.positions()[inlet], sim.velocities()[inlet]
    side = 1e-3
    shape = np.prod([4 * (c / side) * (1 - c / side) for c in x[:, 1:].T], axis=0)
    tolerance = 0.02 * (dim - 1) * (1 / 64**2 if dim == 2 else 1 / 16**2)
    print(f"error {np.abs(u[:, 0] - 0.02 * shape).max() / 0.02:.3g} U, tolerance {tolerance / 0.02:.3g} U")
    assert np.abs(u[:, 0] - 0.02 * shape).max() <= tolerance
    assert np.abs(u[:, 1:]).max() == 0.0
