"""Compressible gas: ideal-gas EOS, energy equation, artificial viscosity and
conductivity, variable smoothing length; validated against the exact Riemann solution
(Sod shock tube, 1D) and the Sedov-Taylor similarity law (2D blast wave).

Error definitions (cases/sod.py, ``compare``): L1 = mean over the particles in the
tube of |q - q_exact(x)|; plateau values are means over the star region 4 h away from
the waves; the shock is where rho falls through (rho*_R + rho_R) / 2. The thresholds
are the values measured when the tests were written plus a stated margin.
"""

import math

import numpy as np
import pytest

import taisph
from taisph.engine import smoothing
from taisph.scene import gas
from taisph.cases.sedov import shock_radius
from taisph.cases.sod import compare, tube
from taisph.validation.references.riemann import RiemannProblem
from taisph.validation.references.sedov_taylor import SedovTaylor
from taisph.terms import XSPH, AdaptiveSmoothingLength, ArtificialConductivity, InternalEnergy, PressureGradient

SOD = RiemannProblem((1.0, 0.0, 1.0), (0.125, 0.0, 0.1), gamma=1.4)


# --- references ---------------------------------------------------------------------
def test_exact_riemann_solver_reproduces_toro():
    """Toro (2009) test 1 star state and shock speed (the values in FORMULAS.md, to
    their 5 digits), and p*, u* of tests 2-5 (Toro table 4.3)."""
    assert SOD.p_star == pytest.approx(0.30313, abs=5e-6)
    assert SOD.u_star == pytest.approx(0.92745, abs=5e-6)
    assert SOD.rho_star_left == pytest.approx(0.42632, abs=5e-6)
    assert SOD.rho_star_right == pytest.approx(0.26557, abs=5e-6)
    assert SOD.speeds["right_shock"] == pytest.approx(1.75216, abs=5e-6)
    for left, right, p_star, u_star in [
        ((1.0, -2.0, 0.4), (1.0, 2.0, 0.4), 0.00189, 0.0),
        ((1.0, 0.0, 1000.0), (1.0, 0.0, 0.01), 460.894, 19.5975),
        ((1.0, 0.0, 0.01), (1.0, 0.0, 100.0), 46.0950, -6.19633),
        ((5.99924, 19.5975, 460.894), (5.99242, -6.19633, 46.0950), 1691.64, 8.68975),
    ]:
        problem = RiemannProblem(left, right, 1.4)
        assert problem.p_star == pytest.approx(p_star, rel=1e-4, abs=1e-5)
        assert problem.u_star == pytest.approx(u_star, rel=1e-4, abs=1e-5)


def test_exact_riemann_solution_conserves_across_waves():
    """The sampled solution obeys the Rankine-Hugoniot conditions across the shock
    (mass and momentum flux in the shock frame, to 1e-12) and is isentropic
    (p / rho^gamma constant) through the rarefaction fan."""
    S = SOD.speeds["right_shock"]
    (r1, u1, p1), (r2, u2, p2) = SOD.right, (SOD.rho_star_right, SOD.u_star, SOD.p_star)
    assert r1 * (u1 - S) == pytest.approx(r2 * (u2 - S), rel=1e-12)
    assert r1 * (u1 - S) ** 2 + p1 == pytest.approx(r2 * (u2 - S) ** 2 + p2, rel=1e-12)
    x = np.linspace(0.5 + SOD.speeds["left_head"] * 0.2, 0.5 + SOD.speeds["left_tail"] * 0.2, 50)
    rho, u, p, e = SOD.sample(x, 0.2, 0.5)
    np.testing.assert_allclose(p / rho**1.4, 1.0, rtol=1e-12)
    np.testing.assert_allclose(e, p / (0.4 * rho), rtol=1e-14)


@pytest.mark.parametrize("gamma, xi0", [(1.4, 1.033), (5.0 / 3.0, 1.152)])
def test_sedov_taylor_constant_spherical(gamma, xi0):
    """The similarity integration gives Taylor's xi0 of the spherical blast."""
    assert SedovTaylor(gamma, nu=3).xi0 == pytest.approx(xi0, abs=1e-3)


def test_sedov_taylor_profile_holds_the_energy():
    """2D: the sampled profile integrated over the disc, sum (rho u^2/2 + p/(gamma-1))
    2 pi r dr, returns E (to 1e-4), and the shock values are the strong-shock jumps."""
    st = SedovTaylor(1.4, nu=2)
    t, energy = 0.1, 2.0
    r = np.linspace(0.0, float(st.radius(t, energy)) * (1 - 1e-12), 200_001)
    rho, u, p = st.sample(r, t, energy)
    total = np.trapezoid((0.5 * rho * u**2 + p / 0.4) * 2 * math.pi * r, r)
    assert total == pytest.approx(energy, rel=1e-4)
    assert rho[-1] == pytest.approx(2.4 / 0.4, rel=1e-6)


# --- the equations -------------------------------------------------------------------
def test_ideal_gas_eos_in_the_kernels():
    """Pressure (gamma - 1) rho e and sound speed sqrt(gamma (gamma - 1) e) of every
    particle equal the formulas (to 1e-12), for two gases with different gamma."""
    scene = taisph.Scene("eos", dim=1, dx=0.1, smoothing_length=0.1, domain=(0.0, 10.0), eos=gas.IdealGas(),
                         materials=[taisph.Gas("air", gamma=1.4), taisph.Gas("helium", gamma=5 / 3)],
                         terms=[PressureGradient(), InternalEnergy()])
    rho = np.linspace(0.1, 2.0, 20)
    e = np.linspace(0.5, 3.0, 20)
    x = np.arange(20)[:, None] * 0.5  # no neighbours: density stays as given
    scene.add_fluid(x[:10], material=0, density=rho[:10], mass=1.0, energy=e[:10])
    scene.add_fluid(x[10:], material=1, density=rho[10:], mass=1.0, energy=e[10:])
    sim = taisph.Simulation(scene)
    gamma = np.r_[np.full(10, 1.4), np.full(10, 5 / 3)]
    np.testing.assert_allclose(sim.pressure(), gas.pressure(rho, e, gamma), rtol=1e-12)
    np.testing.assert_allclose(sim.quantity("sound_speed"), gas.sound_speed(gas.pressure(rho, e, gamma), rho, gamma),
                               rtol=1e-12)


@pytest.mark.parametrize("density, variable_h", [("summation", True), ("summation", False), ("continuity", True)])
def test_gas_rates_conserve_momentum_and_energy(density, variable_h, rng):
    """On a random 2D cloud of unequal masses, with every gas term on (pressure,
    compatible energy equation, viscosity with heating, conductivity): sum m a = 0 and
    sum m (v . a + de/dt) = 0 to 1e-12 of the sum of their magnitudes (round-off), also
    with a variable smoothing length (the mean of both kernel gradients)."""
    n = 600
    points = rng.uniform(0, 1, size=(n, 2))
    terms = gas.effects(density=density, conductivity=True, variable_h=variable_h, h_factor=1.3)
    scene = taisph.Scene("cloud", dim=2, dx=0.04, smoothing_length=0.12, domain=([0, 0], [1, 1]),
                         eos=gas.IdealGas(), materials=[taisph.Gas(gamma=1.4)], terms=terms)
    mass = rng.uniform(0.5, 1.5, size=n) * 1.6e-3
    scene.add_fluid(points, mass=mass, density=rng.uniform(0.8, 1.2, size=n), velocity=rng.normal(0, 1, size=(n, 2)),
                    energy=rng.uniform(1.0, 3.0, size=n))
    sim = taisph.Simulation(scene)  # the pc integrator stores the first rates (acc_prev, ...)
    m, v = sim.masses(), sim.velocities()
    a, de = sim.quantity("acc_prev"), sim.quantity("d_energy_prev")
    assert np.abs(a).max() > 0 and np.abs(de).max() > 0
    force = m[:, None] * a
    np.testing.assert_array_less(np.abs(force.sum(axis=0)), 1e-12 * np.abs(force).sum())
    power = m * ((v * a).sum(axis=1) + de)
    assert abs(power.sum()) < 1e-12 * (np.abs(m * (v * a).sum(axis=1)).sum() + np.abs(m * de).sum())


def test_seed_energy_form_is_the_seeds_equation_11():
    """form="seed" gives de_a/dt = (P_a/rho_a) sum (m_b/rho_b) v_ab . grad W: on a cloud
    of equal density it equals the compatible form (P_a/rho_a^2) sum m_b v_ab . grad W."""
    rng = np.random.default_rng(5)
    points = rng.uniform(0, 1, size=(300, 2))
    mass = rng.uniform(0.5, 1.5, size=300)
    rates = []
    for form in ("compatible", "seed"):
        scene = taisph.Scene("cloud", dim=2, dx=0.05, smoothing_length=0.08, domain=([0, 0], [1, 1]),
                             eos=gas.IdealGas(), materials=[taisph.Gas(gamma=1.4)],
                             terms=[PressureGradient(), InternalEnergy(form=form)])
        scene.add_fluid(points, mass=mass, density=1.3, energy=2.0,
                        velocity=np.sin(6 * points))
        rates.append(taisph.Simulation(scene).quantity("d_energy_prev"))
    assert np.abs(rates[0]).max() > 0
    np.testing.assert_allclose(rates[1], rates[0], rtol=1e-12, atol=1e-12 * np.abs(rates[0]).max())


def test_variable_smoothing_length_follows_density():
    """h = eta m / rho (1D) on a uniform periodic lattice, with rho by summation: rho of
    every particle is the scene's kernel (the cubic spline) summed over the lattice at the
    initial h = eta dx, sum_j dx W(j dx, 1.2 dx) = 1 + eps (eps = +0.0018: the lattice-sum
    error, computed here as tests/test_kernels.py does, not pinned), to 1e-6; h of every
    particle is then eta dx / rho to round-off."""
    dx = 0.01
    scene = taisph.Scene("line", dim=1, dx=dx, smoothing_length=0.02, domain=(0.0, 1.0), periodic=(True,),
                         eos=gas.IdealGas(), materials=[taisph.Gas(gamma=1.4)],
                         terms=gas.effects(variable_h=True, h_factor=1.2))
    scene.add_fluid(((np.arange(100) + 0.5) * dx)[:, None], mass=dx, density=1.0, energy=1.0)
    offsets = np.arange(-3, 4)[:, None] * dx  # the cubic spline's support at 1.2 dx is 2.4 dx
    w, _ = smoothing.evaluate(scene.kernel, 1, offsets, 1.2 * dx)
    lattice_sum = float(w.sum() * dx)
    assert lattice_sum == pytest.approx(1.0018, abs=1e-4)  # the quoted eps, for the reader
    sim = taisph.Simulation(scene)
    rho = sim.density()
    np.testing.assert_allclose(rho, lattice_sum, rtol=1e-6)
    np.testing.assert_allclose(sim.quantity("h"), 1.2 * dx / rho, rtol=1e-12)


def test_gas_scenes_are_checked():
    def scene(terms, energy=True, cap=1.0):
        s = taisph.Scene("s", dim=1, dx=0.1, smoothing_length=cap, domain=(0.0, 10.0), eos=gas.IdealGas(),
                         materials=[taisph.Gas()], terms=terms)
        s.add_fluid(np.arange(10)[:, None] * 0.1, mass=0.1, **({"energy": 1.0} if energy else {}))
        return s

    with pytest.raises(ValueError, match="internal energy"):
        scene([PressureGradient()], energy=False).validate()
    with pytest.raises(ValueError, match="needs the internal energy equation"):
        scene([PressureGradient(), ArtificialConductivity()]).validate()
    with pytest.raises(ValueError, match="raise smoothing_length"):
        scene([AdaptiveSmoothingLength(h_factor=1.2)], cap=0.05).validate()
    with pytest.raises(ValueError, match="XSPH"):
        scene([AdaptiveSmoothingLength(), XSPH()]).validate()
    with pytest.raises(ValueError, match="gamma must be > 1"):
        taisph.Gas(gamma=1.0).check()


# --- Sod shock tube (1D) ---------------------------------------------------------------
def run_sod(t_end=0.2, **params):
    """A Sod run; every one checks that density and internal energy stay positive."""
    scene = taisph.cases.sod(**params)
    sim = taisph.Simulation(scene)
    state0 = tube(sim)
    sim.run(t_end, frames=1)
    state = tube(sim)
    result = compare(state, SOD, t_end)
    assert result["rho_min"] > 0 and result["e_min"] > 0
    return scene, state0, state, result


@pytest.fixture(scope="module")
def sod_runs():
    """Equal-mass Sod tube, default effects, 200 and 400 particles on the left half."""
    return {n: run_sod(dx=0.5 / n) for n in (200, 400)}


def test_sod_errors_fall_with_resolution(sod_runs):
    """L1 errors of rho, u, p, e at t = 0.2 fall by at least 1.5x from 200 to 400 left
    particles (measured 1.7-2.0x: first order, as expected with shocks), and at 400 stay
    below the measured values + 30 % (0.0022, 0.0050, 0.0020, 0.0088)."""
    coarse, fine = sod_runs[200][3], sod_runs[400][3]
    for q, bound in (("rho", 0.0029), ("u", 0.0065), ("p", 0.0026), ("e", 0.0115)):
        assert fine[f"L1_{q}"] < coarse[f"L1_{q}"] / 1.5, q
        assert fine[f"L1_{q}"] < bound, q


def test_sod_plateaus_and_shock(sod_runs):
    """At 400 left particles, against Toro's exact solution: p* within 0.5 % of 0.30313,
    u* within 0.25 % of 0.92745, rho*_L within 0.3 % of 0.42632, rho*_R within 1 % of
    0.26557, the shock within 0.66 h of x0 + 1.75216 t. Measured 2026-12-07 (`pytest -n 0
    -s tests/test_gas.py -k "sod_plateaus or sod_positivity"` with a print, 36 s): p* -0.22 %,
    u* +0.077 %, rho*_L -0.098 %, rho*_R -0.36 %, the shock 0.221 h ahead; the bars are
    about 3x those (p* 2.3x and rho*_R 2.8x: the bars they had, not loosened)."""
    r = sod_runs[400][3]
    assert r["p_star"] == pytest.approx(0.30313, rel=5e-3)
    assert r["u_star"] == pytest.approx(0.92745, rel=2.5e-3)
    assert r["rho_star_left"] == pytest.approx(0.42632, rel=3e-3)
    assert r["rho_star_right"] == pytest.approx(0.26557, rel=1e-2)
    assert abs(r["shock"] - r["shock_exact"]) < 0.66 * r["h_shock"]


def test_sod_positivity_and_energy(sod_runs):
    """Density and internal energy stay positive - indeed within the exact solution's
    range less 1 % (rho >= 0.125, e >= 1.7776) - and the tube's total energy
    sum m (e + u^2/2) (closed: reflecting ends) is conserved to 1e-5: measured 2026-12-07
    (the command above) -3.3e-6 at 200 and -1.7e-6 at 400 left particles (5e-7 was quoted
    before: stale), so the bar is 3x the larger."""
    for scene, state0, state, r in sod_runs.values():
        assert r["rho_min"] > 0.99 * 0.125 and r["e_min"] > 0.99 * 1.7776
        energy = lambda s: (s["m"] * (s["e"] + 0.5 * s["u"] ** 2)).sum()  # noqa: E731
        assert energy(state) == pytest.approx(energy(state0), rel=1e-5)


def test_sod_matches_pysph_at_equal_particle_count():
    """PySPH's Sod example (640 + 80 = 720 equal-mass particles, t = 0.15) has L1 errors
    rho 0.0024, u 0.0031, p 0.0020 against the exact solution (measured by the project
    lead). The same set-up here (its tube [-0.5, 0.5] is our [0, 1]) must do no worse;
    measured 0.0014, 0.0026, 0.0013."""
    _, _, state, r = run_sod(t_end=0.15, dx=0.5 / 640)
    assert len(state["x"]) == 720
    assert r["L1_rho"] <= 0.0024 and r["L1_u"] <= 0.0031 and r["L1_p"] <= 0.0020


def test_sod_conductivity_removes_the_contact_blip():
    """Without conductivity SPH keeps a pressure blip at the contact discontinuity
    (e is discontinuous there, rho is smoothed); Price's conductivity shrinks it:
    max |p - p*| within 0.03 of the contact at t = 0.15 (720 particles) measured 0.028
    without and 0.0072 with. Asserted: at least 2.5x smaller, and below 0.012."""
    blips = []
    for conductivity in (False, True):
        _, _, state, _ = run_sod(t_end=0.15, dx=0.5 / 640, conductivity=conductivity)
        near = np.abs(state["x"] - (0.5 + SOD.u_star * 0.15)) < 0.03
        blips.append(np.abs(state["p"][near] - SOD.p_star).max())
    assert blips[1] < blips[0] / 2.5 and blips[1] < 0.012


def test_sod_with_continuity_density():
    """Density by the continuity equation instead of summation (200 left particles):
    L1 errors below the measured values + 30 % (rho 0.0088, u 0.0094, p 0.0090: about
    twice those of summation density), p* within 5 % (measured -3.0 %; -1.0 % at 400),
    density and energy positive."""
    _, _, _, r = run_sod(dx=0.5 / 200, density="continuity")
    assert r["L1_rho"] < 0.0114 and r["L1_u"] < 0.0122 and r["L1_p"] < 0.0117
    assert r["p_star"] == pytest.approx(0.30313, rel=5e-2)
    assert r["rho_min"] > 0 and r["e_min"] > 0


# --- Sedov blast (2D) ------------------------------------------------------------------
@pytest.mark.parametrize("conductivity", [False, True])
def test_sedov_blast_follows_the_similarity_law(conductivity):
    """2D blast (E = 1, rho = 1, gamma = 1.4, 50 x 50 particles, variable h): the shock
    radius - where the ring-averaged density falls half way from its peak to rho0 -
    stays within one initial smoothing length h0 = 1.3 dx of R = xi0 (E t^2/rho)^(1/4),
    xi0 = 1.004, at t = 0.04, 0.07, 0.1 (measured at 0.1: +0.33 h0 without conductivity,
    +0.77 h0 with); density and energy stay positive; total energy is conserved to 1e-3.
    With conductivity the centre is right too: the internal energy within R/4 is 0.046
    (exact 0.039; asserted < 0.06). Without, the initially heated particles keep 0.26
    of E there (cases/sedov.py, docs/gas.md): not asserted, a known limit."""
    scene = taisph.cases.sedov(dx=0.02, conductivity=conductivity)
    sim = taisph.Simulation(scene)
    st = SedovTaylor(1.4, nu=2)
    energy0 = (sim.masses() * sim.quantity("energy")).sum()
    h0 = 1.3 * scene.dx
    for t in (0.04, 0.07, 0.1):
        sim.run(t, frames=1)
        assert abs(shock_radius(sim) - st.radius(t)) < h0, t
    e = sim.quantity("energy")
    assert sim.density().min() > 0 and e.min() > 0
    v = sim.velocities()
    m = sim.masses()
    assert (m * (e + 0.5 * (v * v).sum(axis=1))).sum() == pytest.approx(energy0, rel=1e-3)
    if conductivity:
        r = np.linalg.norm(sim.positions(), axis=1)
        assert (m * e)[r < st.radius(0.1) / 4].sum() < 0.06
