"""DensityRelaxation (taisph/terms/density_relaxation.py): an evolved density relaxes
towards the summed one at the rate 1 / tau where the support is full, and not elsewhere."""

import math

import numpy as np
import pytest

import taisph
from taisph.geometry import lattice
from taisph.messages import InputError
from taisph.scene import Material, Scene
from taisph.terms import Continuity, DensityRelaxation, PressureGradient, SummationDensity

DX, SIDE, RHO0, C0 = 0.01, 0.2, 1000.0, 10.0


def box(periodic, tau, excess, terms=None):
    """Water on the lattice at rest, mass rho0 dx^2 but density rho0 (1 + excess): its
    particles are spaced for rho0 while their density says more."""
    terms = [Continuity(), PressureGradient(), DensityRelaxation(relaxation_time=tau)] if terms is None else terms
    scene = Scene(name="box", dim=2, dx=DX, smoothing_length=1.3 * DX, domain=((0, 0), (SIDE, SIDE)),
                  materials=[Material("water", RHO0, C0, 7.0)], terms=terms, kernel="wendland", periodic=periodic)
    scene.add_fluid(lattice((0, 0), (SIDE, SIDE) if periodic[1] else (SIDE, SIDE / 2), DX),
                    density=RHO0 * (1 + excess), mass=RHO0 * DX**2, velocity=(0.0, 0.0))
    return scene


def test_a_uniform_excess_decays_as_exp_minus_t_over_tau():
    """Periodic both ways, so the pressure is uniform and nothing moves: d rho/dt =
    (rho0 - rho) / tau exactly, and rho - rho0 = excess rho0 exp(-t / tau). Measured at
    t = tau with dt = tau / 100 (predictor-corrector): within 1e-4 of the excess."""
    tau, excess = 0.01, 0.01
    sim = taisph.Simulation(box((True, True), tau, excess), dt=tau / 100)
    sim.step(100)
    rho = sim.density()[sim.fluid]
    expected = excess * math.exp(-sim.time / tau)
    assert sim.time == pytest.approx(tau)
    assert np.abs(rho / RHO0 - 1 - expected).max() <= 1e-4 * excess


def test_the_outer_row_of_a_free_surface_is_left_alone():
    """Periodic along x only, free top and bottom: the outermost rows have about half a
    support (their sum reads ~0.6 rho0), below the 95 % that counts as full, and are left
    to the continuity equation. One step of dt = tau / 100, the same scene with and
    without the term: the term changes the interior's density by -(1 - exp(-dt / tau))
    times the excess (within 1 %) and the outermost rows' by less than 1e-3 of that. (The
    second row, 1 dx inside, has 98 % of a support and is relaxed towards a sum 0.7 %
    short: measured 1.7x the interior's change here; the term is meant for confined flows.)"""
    tau, excess, dt = 0.01, 0.01, 1e-4
    runs = []
    for terms in ([Continuity(), PressureGradient(), DensityRelaxation(relaxation_time=tau)],
                  [Continuity(), PressureGradient()]):
        sim = taisph.Simulation(box((True, False), tau, excess, terms=terms), dt=dt)
        y0 = sim.positions()[sim.fluid, 1]
        sim.step(1)
        runs.append(sim.density()[sim.fluid] / RHO0)
        sim.close()
    by_term = runs[0] - runs[1]
    interior = (y0 > 0.25 * SIDE / 2) & (y0 < 0.75 * SIDE / 2)
    outer = (y0 < 0.5 * DX + 1e-9) | (y0 > SIDE / 2 - 0.5 * DX - 1e-9)
    expected = -excess * (1 - math.exp(-dt / tau))
    assert by_term[interior] == pytest.approx(expected, rel=0.01)
    assert outer.sum() == 2 * round(SIDE / DX)
    assert np.abs(by_term[outer]).max() <= 1e-3 * abs(expected)


def test_it_is_refused_without_an_evolved_density_or_a_time():
    with pytest.raises(InputError, match="continuity"):
        taisph.Simulation(box((True, True), 0.01, 0.0, terms=[SummationDensity(lattice=True), PressureGradient(),
                                                                DensityRelaxation(relaxation_time=0.01)]))
    with pytest.raises(InputError, match="relaxation_time > 0"):
        taisph.Simulation(box((True, True), 0.0, 0.0))


def test_a_scene_file_sets_it_with_physics_density_relaxation(tmp_path):
    from taisph.formats.scenefile import SceneFileError, load

    text = ('name = "relaxed"\ndim = 2\ndx = 0.02\nt_end = 0.05\nframes = 1\n[physics]\ndensity_relaxation = {tau}\n'
            '[[fluid]]\nbox = [[0.0, 0.0], [0.4, 0.2]]\n[[walls]]\nbox = [[0.0, 0.0], [1.0, 1.0]]\n')
    path = tmp_path / "relaxed.toml"
    path.write_text(text.format(tau=0.01))
    scene, _ = load(path)
    assert scene.terms_by_name["density_relaxation"].values["relaxation_time"] == 0.01
    path.write_text(text.format(tau=0.0))
    assert "density_relaxation" not in load(path)[0].terms_by_name
    path.write_text(text.format(tau=-1.0))
    with pytest.raises(SceneFileError, match="physics.density_relaxation"):
        load(path)


def test_its_code_is_compiled_only_where_it_is_listed():
    from taisph.engine import assembly, kernels

    traced = []
    for terms in ([Continuity(), PressureGradient()],
                  [Continuity(), PressureGradient(), DensityRelaxation(relaxation_time=0.01)]):
        assembly._cache.clear()
        kernels.TRACED.clear()
        taisph.Simulation(box((True, True), 0.01, 0.0, terms=terms)).step(1)
        traced.append({role for name, role in kernels.TRACED if name == "density_relaxation"})
    assert traced == [set(), {"pass", "particle"}]
