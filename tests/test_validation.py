"""Validation cases against their references, at CI-affordable resolutions.

Tolerances are one-sided bars against the reference (an experiment, an exact solution, a
published benchmark), set at about 1.3-3x the measured value, and are listed with the
references and the measured numbers in docs/validation.md. The long versions
(`pytest -m slow`) run the cases at the resolutions the documentation quotes. A known miss
is a strict xfail whose reason gives its measured value. The tests named `verification`
compare taisph with its own fine solution (convergence), not with an experiment.
"""

import numpy as np
import pytest

from taisph import validation


# --- hydrostatic tank -------------------------------------------------------------------------
def test_hydrostatic_tank_dummy_walls():
    """Still water, dx = H/10, 1 s (~60 acoustic periods H/c0), dummy walls and delta-SPH
    (the case's defaults): rms pressure error below 0.6 % of rho g H (measured 0.20 %),
    largest speed over the last quarter below 0.15 % of sqrt(g H) (measured 0.044 %) and
    not above the first quarter's (0.23 %), surface flat to 2.5 % of dx (measured 0.83 %),
    no particle through a wall."""
    out = validation.hydrostatic_tank(dx=0.05, t_end=1.0)
    m = out.metrics
    assert out.error < 0.006, m
    assert m["vmax_last_quarter"] < 0.0015 and m["vmax_last_quarter"] <= m["vmax_first_quarter"], m
    assert m["surface_std_over_dx"] < 0.025, m
    assert m["particles_outside"] == 0


def test_dummy_walls_hold_hydrostatic_pressure_where_lj_walls_do_not():
    """The same tank with the seed's Lennard-Jones walls (0.5 s): rms pressure error over the
    second half (acoustic oscillation, dense floor layer) at least 25x the dummy walls'
    (measured 16.6 % against 0.20 %, 84x)."""
    dummy = validation.hydrostatic_tank(dx=0.05, t_end=0.5, walls="dummy")
    lj = validation.hydrostatic_tank(dx=0.05, t_end=0.5, walls="lj")
    assert lj.error > 25 * dummy.error, (lj.error, dummy.error)


def test_density_diffusion_needs_its_hydrostatic_correction():
    """delta-SPH (delta = 0.1) in the still tank (dx = H/10, 1 s): with the hydrostatic
    correction the rms pressure error stays below 0.6 % (measured 0.20 %); without it,
    diffusion flattens the hydrostatic density profile and the error at the end is above
    0.8 % (measured 2.45 %; 2.3 % after 2 s at dx = H/20)."""
    import taisph
    from taisph.terms import DensityDiffusion

    corrected = validation.hydrostatic_tank(dx=0.05, t_end=1.0, delta=0.1)
    assert corrected.error < 0.006
    scene = taisph.cases.hydrostatic_tank(dx=0.05, delta=None)
    scene.terms.append(DensityDiffusion(delta=0.1, hydrostatic=False))
    sim = taisph.Simulation(scene)
    sim.run(1.0, frames=1)
    x, p = sim.positions()[sim.fluid], sim.pressure()[sim.fluid]
    H, rho_g = 0.5, 1000.0 * 9.81
    deep = x[:, 1] < H - scene.support_radius
    rms = np.sqrt(np.mean((p[deep] - rho_g * (H - x[deep, 1])) ** 2)) / (rho_g * H)
    sim.close()
    assert rms > 0.008, rms


def test_dummy_wall_pressure_is_hydrostatic():
    """Adami et al.'s extrapolation (dx = H/10, 0.5 s): the first wall layer under the water
    (y = -dx/2, the 16 particles away from the side walls) carries rho g (H + dx/2) within
    0.2 % on average (measured -0.07 %)."""
    import taisph

    scene = taisph.cases.hydrostatic_tank(dx=0.05)
    sim = taisph.Simulation(scene)
    sim.run(0.5, frames=1)
    x, p = sim.positions(), sim.pressure()
    floor = sim.wall & np.isclose(x[:, 1], -0.025) & (x[:, 0] > 0.1) & (x[:, 0] < 0.9)
    expected = 1000.0 * 9.81 * (0.5 + 0.025)
    sim.close()
    assert floor.sum() > 10
    assert np.mean(p[floor]) == pytest.approx(expected, rel=0.002)


# --- channel flows --------------------------------------------------------------------------------
def test_poiseuille_profile_and_convergence():
    """Start-up Poiseuille (Morris et al. 1997), dx = L/20: max |u - u_exact| / u_max
    over t = 0.0225 ... 1 s below 1 % (measured 0.59 %); at L/10 it is more than
    twice that (measured 1.87 %, 3.2x)."""
    fine = validation.poiseuille(dx=5e-5)
    coarse = validation.poiseuille(dx=1e-4)
    assert fine.error < 0.01
    assert fine.error < coarse.error / 2


def test_couette_profile():
    """Start-up Couette (Morris et al. 1997), dx = L/20: max |u - u_exact| / V0 over
    t = 0.0225 ... 1 s below 1 % (measured 0.64 %, at the first time); at t = 1 s, the
    steady linear profile, below 0.15 % (measured 0.057 %)."""
    out = validation.couette(dx=5e-5)
    assert out.error < 0.01, out.metrics
    assert out.metrics["linf_t1"] < 0.0015, out.metrics  # steady linear profile


# --- Taylor-Green ------------------------------------------------------------------------------------
def test_taylor_green_beats_pysph_edac():
    """Re = 100, 50 x 50 particles, t = 2: L1 speed error (PySPH's metric) at most 0.020,
    what PySPH's EDAC scheme reaches there (measured here 0.010 with particle shifting and
    delta-SPH); the largest speed at t = 2 within 0.35 % of the exact decay (measured 0.12 %)."""
    out = validation.taylor_green(dx=1 / 50, shifting=True, delta=0.1)
    assert out.error <= 0.020, out.metrics
    assert out.metrics["max_speed_error_end"] < 0.0035, out.metrics


def test_taylor_green_converges():
    """L1 speed error at t = 2 against the exact vortex: 32 x 32 particles beat 20 x 20
    (measured 0.015 against 0.033)."""
    coarse = validation.taylor_green(dx=1 / 20, shifting=True, delta=0.1)
    fine = validation.taylor_green(dx=1 / 32, shifting=True, delta=0.1)
    assert fine.error < coarse.error


# --- elliptical drop ----------------------------------------------------------------------------------
def test_elliptical_drop_semi_axis():
    """Monaghan's drop, dx = 0.05 (1256 particles), t = 0.0076 s: semi-major axis within 2 %
    of the ODE solution b = 1.9445 (measured 0.89 %)."""
    out = validation.elliptical_drop(dx=0.05)
    assert out.error < 0.02


# --- dam break --------------------------------------------------------------------------------------------
def test_dam_break_front_and_column_height():
    """dx = 0.05, T <= 3.1. The case's defaults (dummy walls with friction, delta-SPH,
    Courant 0.3) and the seed's physics (Lennard-Jones walls): mean |Z - Z_KO| <= 0.10
    (measured 0.071 and 0.057). Dummy walls with free slip and no density diffusion:
    column height within 0.02 of Martin & Moyce (mean |H - H_MM|, measured 0.0070), but the
    front runs ahead of the experiments (signed mean Z - Z_KO above 0.1, measured 0.188):
    see docs/accuracy.md. This error grows with refinement (the case's defaults: 0.151 at
    dx = 0.02, 0.215 at 0.005): test_dam_break_front_at_reference_resolution_misses_the_ci_bar."""
    default = validation.dam_break(dx=0.05)
    assert default.error <= 0.10, default.metrics
    lj = validation.dam_break(dx=0.05, seed_physics=True)
    assert lj.error <= 0.10, lj.metrics
    dummy = validation.dam_break(dx=0.05, walls="dummy", wall_friction=False, delta=0)
    assert dummy.metrics["height_mean_abs"] < 0.02, dummy.metrics
    assert dummy.metrics["ko_mean_signed"] > 0.1, dummy.metrics


def test_dam_break_short_run_uses_the_reference_points_it_reaches():
    """T_end = 0.6 (before Martin & Moyce's first column height, tau = 0.56 i.e. T = 0.79;
    after their first front point, T = 0.41): the errors are computed over the points
    that exist up to T_end, the column height's are NaN (it crashed on the empty slice)."""
    out = validation.dam_break(dx=0.1, T_end=0.6)
    assert np.isfinite(out.error) and out.error == out.metrics["ko_mean_abs"]
    assert np.isfinite(out.metrics["mm_mean_abs"]) and np.isfinite(out.metrics["mm_max_abs"])
    assert np.isnan(out.metrics["height_mean_abs"]) and np.isnan(out.metrics["height_max_abs"])
    assert "T <= 0.6" in out.error_name


def test_verification_dam_break_front_converges_towards_taisphs_own_fine_solution():
    """Verification, not validation: the reference is taisph's own output, the front of the
    case's defaults at dx = 0.005 (the study's case dam_break_front;
    references/data/dam_break_front_defaults_dx0.005.csv), itself 0.215 from Koshizuka &
    Oka's experiment. From dx = 0.1 to 0.05 the error against it falls by a factor 0.66
    (measured 0.253 -> 0.168), held at <= 0.8, where against the experiment it grows
    (0.044 -> 0.071; docs/accuracy.md)."""
    coarse = validation.run("dam_break_front", dx=0.1)
    finer = validation.run("dam_break_front", dx=0.05)
    assert finer.error <= 0.8 * coarse.error
    assert finer.error == finer.metrics["fine_mean_abs"] and "dx = 0.005" in finer.error_name


def test_verification_dfsph_front_agrees_with_taisphs_own_wcsph_fine_solution():
    """Verification, not validation: two solvers, one model. DFSPH's front at dx = 0.02 lies
    within 0.05 L (mean |Z - Z_fine|, T <= 3.1) of taisph's own weakly compressible defaults
    at dx = 0.005 (measured 0.032; 0.0023 at dx = 0.01), while both lie ~0.2 from Koshizuka &
    Oka's experiment (0.193 here, 0.215 the fine front; docs/dfsph.md, "Not done"): the
    incompressible projection converges to the same surge, not to the experiment."""
    out = validation.run("dam_break_front", dx=0.02, solver="dfsph")
    assert out.error <= 0.05, out.metrics


# --- long versions ------------------------------------------------------------------------------------------
@pytest.mark.slow
def test_dam_break_at_reference_resolution():
    """dx = 0.02 (5000 particles, PySPH's resolution), T <= 3.1: the case's defaults
    mean |Z - Z_KO| <= 0.17 (measured 0.150); the seed's Lennard-Jones walls <= 0.18
    (measured 0.166; PySPH's WCSPH: 0.23); dummy walls with free slip and no density
    diffusion <= 0.26 (measured 0.243) with column height within 0.02 of Martin & Moyce
    (measured 0.0084; docs/accuracy.md)."""
    default = validation.dam_break(dx=0.02)
    assert default.error <= 0.17, default.metrics
    lj = validation.dam_break(dx=0.02, seed_physics=True)
    assert lj.error <= 0.18
    dummy = validation.dam_break(dx=0.02, walls="dummy", wall_friction=False, delta=0)
    assert dummy.error <= 0.26
    assert dummy.metrics["height_mean_abs"] < 0.02


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason="a known miss: the front runs ahead of Koshizuka & Oka the more, the finer "
                   "the particles; measured mean |Z - Z_KO| 0.151 at dx = 0.02 against the CI bar 0.10 (0.071 at "
                   "dx = 0.05; 0.215 at 0.005); validation.dam_break(dx=0.02), 39 s on 2 cores")
def test_dam_break_front_at_reference_resolution_misses_the_ci_bar():
    """The case's defaults at dx = 0.02, T <= 3.1, held to the bar the CI test holds at
    dx = 0.05: mean |Z - Z_KO| <= 0.10. Expected to fail (measured 0.151: the inviscid model
    runs ahead of the experiment, docs/accuracy.md); a pass means the front came nearer."""
    out = validation.dam_break(dx=0.02)
    assert out.error <= 0.10, out.metrics


@pytest.mark.slow
def test_hydrostatic_tank_long_run():
    """dx = H/20, 10 s (~600 acoustic periods), dummy walls and delta-SPH 0.1 (the case's
    defaults): rms pressure error below 1 % (measured 0.54 %), speeds bounded by 1 % of
    sqrt(g H), no penetration. Not asserted, because it is not true: that the speeds decay.
    After ~2-3 s the square particle lattice rearranges and spurious speeds of ~0.3-0.5 %
    of sqrt(g H) persist (docs/accuracy.md). Without delta-SPH a zig-zag pressure mode of
    the floor row grows as well (measured 2.6 % rms over the second half)."""
    out = validation.hydrostatic_tank(dx=0.025, t_end=10.0, samples=50)
    m = out.metrics
    assert out.error < 0.01
    assert m["vmax_last_quarter"] < 0.01
    assert m["particles_outside"] == 0


@pytest.mark.slow
def test_channel_flows_fine():
    """L/40: Poiseuille and Couette profiles within 0.3 % of u_max (measured 0.21 % and
    0.19 %; docs/validation.md)."""
    assert validation.poiseuille(dx=2.5e-5).error < 0.003
    assert validation.couette(dx=2.5e-5).error < 0.003
