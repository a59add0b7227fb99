"""Validation cases against their references, at CI-affordable resolutions.

Tolerances are set from measured values with a margin, and are listed with the
references and the measured numbers in docs/validation.md. The long versions
(`pytest -m slow`) run the cases at the resolutions the documentation quotes.
"""

import numpy as np
import pytest

from taisph import validation


# --- hydrostatic tank -------------------------------------------------------------------------
def test_hydrostatic_tank_dummy_walls():
    """Still water, dx = H/10, 1 s (~60 acoustic periods H/c0), dummy walls and delta-SPH
    (the case's defaults): rms pressure error below 1 % of rho g H (measured 0.2 %),
    velocities small and not growing over that second, surface flat to 5 % of dx, no
    particle through a wall."""
    out = validation.hydrostatic_tank(dx=0.05, t_end=1.0)
    m = out.metrics
    assert out.error < 0.01
    assert m["vmax_last_quarter"] < 0.01 and m["vmax_last_quarter"] <= m["vmax_first_quarter"]
    assert m["surface_std_over_dx"] < 0.05
    assert m["particles_outside"] == 0


def test_dummy_walls_hold_hydrostatic_pressure_where_lj_walls_do_not():
    """The same tank with the seed's Lennard-Jones walls: instantaneous rms pressure
    error ~20 % (acoustic oscillation, dense floor layer), at least 10x the dummy walls'."""
    dummy = validation.hydrostatic_tank(dx=0.05, t_end=0.5, walls="dummy")
    lj = validation.hydrostatic_tank(dx=0.05, t_end=0.5, walls="lj")
    assert lj.error > 10 * dummy.error


def test_density_diffusion_needs_its_hydrostatic_correction():
    """delta-SPH (delta = 0.1) in the still tank: with the hydrostatic correction the
    pressure stays within 1 % rms; without it, diffusion flattens the hydrostatic
    density profile and the error grows (measured 2.3 % after 2 s at dx = H/20)."""
    import taisph
    from taisph.terms import DensityDiffusion

    corrected = validation.hydrostatic_tank(dx=0.05, t_end=1.0, delta=0.1)
    assert corrected.error < 0.01
    scene = taisph.cases.hydrostatic_tank(dx=0.05, delta=None)
    scene.terms.append(DensityDiffusion(delta=0.1, hydrostatic=False))
    sim = taisph.Simulation(scene)
    sim.run(1.0, frames=1)
    x, p = sim.positions()[sim.fluid], sim.pressure()[sim.fluid]
    H, rho_g = 0.5, 1000.0 * 9.81
    deep = x[:, 1] < H - scene.support_radius
    rms = np.sqrt(np.mean((p[deep] - rho_g * (H - x[deep, 1])) ** 2)) / (rho_g * H)
    sim.close()
    assert rms > 2 * corrected.error


def test_dummy_wall_pressure_is_hydrostatic():
    """Adami et al.'s extrapolation: the first wall layer under the water (y = -dx/2)
    carries rho g (H + dx/2) within 3 %."""
    import taisph

    scene = taisph.cases.hydrostatic_tank(dx=0.05)
    sim = taisph.Simulation(scene)
    sim.run(0.5, frames=1)
    x, p = sim.positions(), sim.pressure()
    floor = sim.wall & np.isclose(x[:, 1], -0.025) & (x[:, 0] > 0.1) & (x[:, 0] < 0.9)
    expected = 1000.0 * 9.81 * (0.5 + 0.025)
    sim.close()
    assert floor.sum() > 10
    assert np.mean(p[floor]) == pytest.approx(expected, rel=0.03)


# --- channel flows --------------------------------------------------------------------------------
def test_poiseuille_profile_and_convergence():
    """Start-up Poiseuille (Morris et al. 1997), dx = L/20: max |u - u_exact| / u_max
    over t = 0.0225 ... 1 s below 1 % (measured 0.59 %); at L/10 it is larger (1.9 %)."""
    fine = validation.poiseuille(dx=5e-5)
    coarse = validation.poiseuille(dx=1e-4)
    assert fine.error < 0.01
    assert fine.error < coarse.error / 2


def test_couette_profile():
    """Start-up Couette (Morris et al. 1997), dx = L/20: max |u - u_exact| / V0 over
    t = 0.0225 ... 1 s below 1 % (measured 0.64 %, at the first time)."""
    out = validation.couette(dx=5e-5)
    assert out.error < 0.01
    assert out.metrics["linf_t1"] < 0.002  # steady linear profile


# --- Taylor-Green ------------------------------------------------------------------------------------
def test_taylor_green_beats_pysph_edac():
    """Re = 100, 50 x 50 particles, t = 2: L1 speed error (PySPH's metric) at most 0.020,
    what PySPH's EDAC scheme reaches there (measured here 0.013 with particle shifting and
    delta-SPH); decay of the largest speed within 2 %."""
    out = validation.taylor_green(dx=1 / 50, shifting=True, delta=0.1)
    assert out.error <= 0.020
    assert out.metrics["max_speed_error_end"] < 0.02


def test_taylor_green_converges():
    """L1 speed error at t = 2: 32 x 32 particles beat 20 x 20."""
    coarse = validation.taylor_green(dx=1 / 20, shifting=True, delta=0.1)
    fine = validation.taylor_green(dx=1 / 32, shifting=True, delta=0.1)
    assert fine.error < coarse.error


# --- elliptical drop ----------------------------------------------------------------------------------
def test_elliptical_drop_semi_axis():
    """Monaghan's drop, dx = 0.05 (1256 particles), t = 0.0076 s: semi-major axis within 2 %
    of the ODE solution b = 1.9445 (measured 0.9 %)."""
    out = validation.elliptical_drop(dx=0.05)
    assert out.error < 0.02


# --- dam break --------------------------------------------------------------------------------------------
def test_dam_break_front_and_column_height():
    """dx = 0.05, T <= 3.1. The case's defaults (dummy walls with friction, delta-SPH,
    Courant 0.3) and the seed's physics (Lennard-Jones walls): mean |Z - Z_KO| <= 0.10
    (measured 0.071 and 0.052). Dummy walls with free slip and no density diffusion:
    column height within 0.03 of Martin & Moyce (measured 0.007), but the front runs
    ahead of the experiments (signed mean > 0, measured 0.19): see docs/accuracy.md."""
    default = validation.dam_break(dx=0.05)
    assert default.error <= 0.10
    lj = validation.dam_break(dx=0.05, seed_physics=True)
    assert lj.error <= 0.10
    dummy = validation.dam_break(dx=0.05, walls="dummy", wall_friction=False, delta=0)
    assert dummy.metrics["height_mean_abs"] < 0.03
    assert dummy.metrics["ko_mean_signed"] > 0


def test_dam_break_short_run_uses_the_reference_points_it_reaches():
    """T_end = 0.6 (before Martin & Moyce's first column height, tau = 0.56 i.e. T = 0.79;
    after their first front point, T = 0.41): the errors are computed over the points
    that exist up to T_end, the column height's are NaN (it crashed on the empty slice)."""
    out = validation.dam_break(dx=0.1, T_end=0.6)
    assert np.isfinite(out.error) and out.error == out.metrics["ko_mean_abs"]
    assert np.isfinite(out.metrics["mm_mean_abs"]) and np.isfinite(out.metrics["mm_max_abs"])
    assert np.isnan(out.metrics["height_mean_abs"]) and np.isnan(out.metrics["height_max_abs"])
    assert "T <= 0.6" in out.error_name


def test_dam_break_front_converges_towards_the_fine_solution():
    """The front against the case's defaults at dx = 0.005 (the study's case dam_break_front;
    references/data/dam_break_front_defaults_dx0.005.csv): from dx = 0.1 to 0.05 the error
    falls by 0.66 (measured 0.253 -> 0.168), where against the experiments it does not
    (docs/accuracy.md); held at <= 0.8."""
    coarse = validation.run("dam_break_front", dx=0.1)
    finer = validation.run("dam_break_front", dx=0.05)
    assert finer.error <= 0.8 * coarse.error
    assert finer.error == finer.metrics["fine_mean_abs"] and "dx = 0.005" in finer.error_name


def test_dfsph_front_agrees_with_the_weakly_compressible_fine_solution():
    """Two solvers, one model: DFSPH's front at dx = 0.02 lies within 0.05 L (mean |Z -
    Z_fine|, T <= 3.1) of the weakly compressible defaults at dx = 0.005 (measured 0.032 on
    2026-12-06; 0.0023 at dx = 0.01), while both lie ~0.2 from Koshizuka & Oka (0.193 here;
    docs/dfsph.md, "Not done"): the incompressible projection converges to the same surge."""
    out = validation.run("dam_break_front", dx=0.02, solver="dfsph")
    assert out.error <= 0.05


# --- long versions ------------------------------------------------------------------------------------------
@pytest.mark.slow
def test_dam_break_at_reference_resolution():
    """dx = 0.02 (5000 particles, PySPH's resolution), T <= 3.1: the case's defaults
    mean |Z - Z_KO| <= 0.17 (measured 0.150); the seed's Lennard-Jones walls <= 0.18
    (measured 0.166; PySPH's WCSPH: 0.23); dummy walls with free slip and no density
    diffusion <= 0.26 (measured 0.243) with column height within 0.02 of Martin & Moyce."""
    default = validation.dam_break(dx=0.02)
    assert default.error <= 0.17
    lj = validation.dam_break(dx=0.02, seed_physics=True)
    assert lj.error <= 0.18
    dummy = validation.dam_break(dx=0.02, walls="dummy", wall_friction=False, delta=0)
    assert dummy.error <= 0.26
    assert dummy.metrics["height_mean_abs"] < 0.02


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
    """L/40: Poiseuille and Couette profiles within 0.3 % of u_max."""
    assert validation.poiseuille(dx=2.5e-5).error < 0.003
    assert validation.couette(dx=2.5e-5).error < 0.003
